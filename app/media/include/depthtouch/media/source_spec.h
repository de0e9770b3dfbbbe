#pragma once
/// \file
/// \brief What the frame sources of a `scheme:TARGET,key=value,...` spec share (the `synthetic:`
/// scenes of dt_synthetic_source, the `v4l2:` cameras of camera_source.h): size and stream options,
/// error texts that outlive the call, and a cache of the objects their sources share.

#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "depthtouch/hal/backends.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::media {

/// \brief A copy of \a text that lives until the process ends, for Error::what (a static string).
/// Equal texts share one copy, so the store grows only with distinct messages. Thread-safe.
const char *persistentText(const std::string &text);

/// \brief Parses "WxH" (both > 0). \return false when \a text is not that.
bool parseSizeText(std::string_view text, int &width, int &height);

/// \brief Reads the frame size of a source that makes its frames itself (it has no demuxer):
/// `size=WxH` of its \a spec options, else SourceOptions::videoSize; neither leaves \a width and
/// \a height unchanged.
/// \return Errc::InvalidArgument with \a noDemuxer when \a options name a demuxer or a pixel
/// format, with \a badSize when the size is not WxH (both static strings).
Result<void> readSpecFrameSize(const hal::OptionList &spec, const SourceOptions &options,
                               const char *noDemuxer, const char *badSize, int &width, int &height);

/// \brief Which stream a source delivers: `stream=` of the spec, else SourceOptions::streamTitle
/// ("depth" → depth). \return Errc::InvalidArgument for a `stream=` other than color or depth.
Result<bool> wantsDepthStream(std::string_view streamOption, const media::SourceOptions &options);

/// \brief What a factory's sources share, one object per key, held weakly: the object lives as
/// long as a source holds it.
template <class T> using SharedCache = std::vector<std::pair<std::string, std::weak_ptr<T>>>;

/// \brief The object shared under \a key in \a cache, or null when no source holds one; drops
/// the entries whose object is gone. Not thread-safe: the caller holds the factory's lock.
template <class T> std::shared_ptr<T> findShared(SharedCache<T> &cache, const std::string &key)
{
    std::shared_ptr<T> found;
    for (auto it = cache.begin(); it != cache.end();) {
        if (it->second.expired()) {
            it = cache.erase(it);
            continue;
        }
        if (it->first == key)
            found = it->second.lock();
        ++it;
    }
    return found;
}

} // namespace depthtouch::media
