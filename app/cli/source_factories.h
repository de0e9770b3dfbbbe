#pragma once
/// \file
/// \brief The pieces behind makeSourceProviders() (source_providers.h): parsing the `synthetic:`
/// and `v4l2:` targets, the synthetic-scene source and the depth-camera source. Declared here so
/// tests can reach them (e.g. a camera source on the mock camera or a fake V4L2 kernel).

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "depthtouch/hal/depth_camera.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::cli {

/// \brief A copy of \a text that lives until the process ends, for Error::what (a static string).
/// Equal texts share one copy, so the store grows only with distinct messages. Thread-safe.
const char *persistentText(const std::string &text);

/// \brief Parses "WxH" (both > 0). \return false when \a text is not that.
bool parseSizeText(std::string_view text, int &width, int &height);

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

// ---------------------------------------------------------------------------------------------
// synthetic:

/// \brief A parsed `synthetic:` target (grammar in source_providers.h).
struct SyntheticSpec {
    std::string scene;      ///< One of synthetic::listScenes().
    int width = 720;        ///< Pixels.
    int height = 486;       ///< Pixels.
    double fps = 30.0;      ///< Frames per second.
    long long frames = 120; ///< Frames delivered; 0 = endless.
    bool depth = false;     ///< The depth (nearness) stream, else color.
    /// The material stream (stream=material, or the source titled "material"): the scene's
    /// per-pixel haptic material codes, Rgb24 (depthtouch/scene/material.h).
    bool material = false;
};

/// Default length of a synthetic source: this many seconds of frames.
inline constexpr double kSyntheticDefaultSeconds = 4.0;

/// \brief Parses \a target (after `synthetic:`) with \a options.
/// \return the spec. Errors: InvalidArgument (unknown scene — the message lists the scenes —,
/// unknown key, bad value, demuxer or pixel-format options, which a scene does not take).
Result<SyntheticSpec> parseSyntheticSpec(std::string_view target,
                                         const media::SourceOptions &options);

class SyntheticRenderer;

/// \brief Opens synthetic sources; sources of one scene, size and rate share one renderer (its
/// thread, GL context and scene) while any of them lives. Thread-safe.
class SyntheticSourceFactory {
public:
    SyntheticSourceFactory() = default;
    ~SyntheticSourceFactory();
    SyntheticSourceFactory(const SyntheticSourceFactory &) = delete;
    SyntheticSourceFactory &operator=(const SyntheticSourceFactory &) = delete;

    /// \brief Opens the source of \a target (after `synthetic:`).
    /// \return the source. Errors: those of parseSyntheticSpec(); NotSupported (no OpenGL ES
    /// display or context: the message names the display's failure; a scene that does not build).
    Result<std::unique_ptr<media::FrameSource>> open(std::string_view target,
                                                     const media::SourceOptions &options);

    /// \return whether this build renders synthetic scenes (it has OpenGL ES).
    static bool available() noexcept;

    /// \return frames drawn so far by the renderers this factory started (each frame drawn once
    /// serves every stream attached to its renderer).
    [[nodiscard]] std::uint64_t framesDrawn() const noexcept;

private:
    std::mutex mutex_;
    SharedCache<SyntheticRenderer> renderers_;
    std::shared_ptr<std::atomic<std::uint64_t>> drawn_ =
        std::make_shared<std::atomic<std::uint64_t>>(0);
};

// ---------------------------------------------------------------------------------------------
// v4l2:

/// \brief A parsed `v4l2:` target (grammar in source_providers.h).
struct CameraSpec {
    std::string device;         ///< Depth node, e.g. "/dev/video0".
    std::string backendOptions; ///< Options passed on to the backend, e.g. "color=/dev/video2".
    int width = 0;              ///< Pixels; 0 = SourceOptions::videoSize or the camera's choice.
    int height = 0;             ///< Pixels.
    double fps = 0.0;           ///< Frames/s asked with `fps=`; 0 = SourceOptions::fps if offered.
    double preferredFps = 30.0; ///< SourceOptions::fps: used when the camera offers it.
    bool depth = false;         ///< The depth stream, else color.
};

/// \brief Parses \a target (after `v4l2:`). \return the spec. Errors: InvalidArgument (empty
/// device, bad size/fps/stream, demuxer or pixel-format options).
Result<CameraSpec> parseCameraSpec(std::string_view target, const media::SourceOptions &options);

class CameraShare;

/// \brief Puts \a camera (Unconfigured) to work for sources: picks the mode (size and rate of
/// \a spec, else the camera's first; Z16 depth preferred, with the color stream when the mode
/// has one) and configures it. Streaming starts at the first frame asked.
/// \return the share. Errors: NotSupported (no mode of that size and rate), the camera's errors.
Result<std::shared_ptr<CameraShare>> shareCamera(std::unique_ptr<hal::DepthCamera> camera,
                                                 const CameraSpec &spec);

/// \brief A source of the color or the depth stream of \a share.
/// \return the source. Errors: NotSupported (color asked of a camera without a color stream).
Result<std::unique_ptr<media::FrameSource>> openCameraSource(std::shared_ptr<CameraShare> share,
                                                             bool depth);

/// \brief Opens `v4l2:` sources; sources of one spec (without `stream=`) share one camera while
/// any of them lives. Thread-safe.
class CameraSourceFactory {
public:
    /// \brief Opens the source of \a target (after `v4l2:`) on the `v4l2` backend.
    /// \return the source. Errors: those of parseCameraSpec(), shareCamera(), openCameraSource()
    /// and the backend (NoDevice: no such node; NotSupported: not a depth camera).
    Result<std::unique_ptr<media::FrameSource>> open(std::string_view target,
                                                     const media::SourceOptions &options);

private:
    std::mutex mutex_;
    SharedCache<CameraShare> cameras_;
};

} // namespace depthtouch::cli
