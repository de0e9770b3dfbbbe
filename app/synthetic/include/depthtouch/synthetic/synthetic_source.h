#pragma once
/// \file
/// \brief `synthetic:NAME` frame sources (the grammar: app/cli/source_providers.h): a built-in
/// scene rendered on a thread of its own with a GL ES context of its own, on a display the caller
/// hands in (DisplayOpener: the executable opens the headless EGL backend). The color, depth and
/// material sources of one scene, size and rate share one renderer.
///
/// Thread-safety: SyntheticSourceFactory may be called from any thread; a source may be used from
/// any one thread (it renders on its own thread and never touches the caller's GL context).

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>

#include "depthtouch/hal/display.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/source_spec.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::synthetic {

/// \brief A parsed `synthetic:` target (grammar in app/cli/source_providers.h).
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

/// \brief Opens the display a scene's render thread draws with, on that thread: a backend whose
/// capabilities().hasGlesContext is true, not opened yet (the executable hands in the headless EGL
/// backend). Called once per renderer.
using DisplayOpener = std::function<Result<std::unique_ptr<hal::Display>>()>;

/// \brief Opens synthetic sources; sources of one scene, size and rate share one renderer (its
/// thread, GL context and scene) while any of them lives. Thread-safe.
class SyntheticSourceFactory {
public:
    /// \a openDisplay: see DisplayOpener.
    explicit SyntheticSourceFactory(DisplayOpener openDisplay);
    ~SyntheticSourceFactory();
    SyntheticSourceFactory(const SyntheticSourceFactory &) = delete;
    SyntheticSourceFactory &operator=(const SyntheticSourceFactory &) = delete;

    /// \brief Opens the source of \a target (after `synthetic:`).
    /// \return the source. Errors: those of parseSyntheticSpec(); NotSupported (no OpenGL ES
    /// display or context: the message names the display's failure; a scene that does not build).
    Result<std::unique_ptr<media::FrameSource>> open(std::string_view target,
                                                     const media::SourceOptions &options);

    /// \return frames drawn so far by the renderers this factory started (each frame drawn once
    /// serves every stream attached to its renderer).
    [[nodiscard]] std::uint64_t framesDrawn() const noexcept;

private:
    std::mutex mutex_;
    const DisplayOpener openDisplay_;
    media::SharedCache<SyntheticRenderer> renderers_;
    std::shared_ptr<std::atomic<std::uint64_t>> drawn_ =
        std::make_shared<std::atomic<std::uint64_t>>(0);
};

} // namespace depthtouch::synthetic
