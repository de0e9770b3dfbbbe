/// \file
/// \brief The helpers of source_spec.h.

#include "depthtouch/media/source_spec.h"

#include <charconv>
#include <mutex>
#include <optional>
#include <set>

namespace depthtouch::media {

const char *persistentText(const std::string &text)
{
    static std::mutex mutex;
    static std::set<std::string> texts; // node-based: c_str() stays valid as the set grows
    const std::lock_guard lock(mutex);
    return texts.insert(text).first->c_str();
}

bool parseSizeText(std::string_view text, int &width, int &height)
{
    const std::size_t x = text.find('x');
    if (x == std::string_view::npos)
        return false;
    int w = 0;
    int h = 0;
    const char *end = text.data() + text.size();
    const auto rw = std::from_chars(text.data(), text.data() + x, w);
    const auto rh = std::from_chars(text.data() + x + 1, end, h);
    if (rw.ec != std::errc{} || rw.ptr != text.data() + x || rh.ec != std::errc{} ||
        rh.ptr != end || w <= 0 || h <= 0)
        return false;
    width = w;
    height = h;
    return true;
}

Result<void> readSpecFrameSize(const hal::OptionList &spec, const SourceOptions &options,
                               const char *noDemuxer, const char *badSize, int &width, int &height)
{
    if (!options.format.empty() || !options.pixelFormat.empty())
        return unexpected(Errc::InvalidArgument, noDemuxer);
    const std::optional<std::string_view> size = spec.find("size");
    const std::string_view sizeText = size ? *size : std::string_view(options.videoSize);
    if (!sizeText.empty() && !parseSizeText(sizeText, width, height))
        return unexpected(Errc::InvalidArgument, badSize);
    return ok();
}

Result<bool> wantsDepthStream(std::string_view streamOption, const SourceOptions &options)
{
    if (streamOption.empty())
        return options.streamTitle == "depth";
    if (streamOption == "depth")
        return true;
    if (streamOption == "color")
        return false;
    return unexpected(Errc::InvalidArgument, "stream= must be color or depth");
}

} // namespace depthtouch::media
