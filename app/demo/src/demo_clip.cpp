/// \file
/// \brief The demo's clip: see demo_clip.h.

#include "depthtouch/demo/demo_clip.h"

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "depthtouch/media/encode_job.h"
#include "depthtouch/media/sound_file.h"
#include "depthtouch/platform/stop_signals.h"
#if DT_DEMO_SOUNDTRACK
#include "depthtouch/synthetic/soundtrack.h"
#endif

namespace depthtouch::demo {

namespace {

/// Writes the scene's soundtrack for \a frames frames at 30 fps to \a path (a click at the start,
/// for the head its turning: synthetic/soundtrack.h). \return an error text, or empty.
std::string writeSoundtrack(const std::string &scene, int frames, const std::string &path)
{
#if DT_DEMO_SOUNDTRACK
    constexpr int kRate = 48000;
    const auto pcm = synthetic::sceneSoundtrack(scene, frames / 30.0, kRate);
    if (auto r = media::writeWavFile(path, pcm, hal::AudioFormat{kRate, 1}); !r)
        return std::string("cannot write the scene's soundtrack: ") + r.error().what;
    return {};
#else
    (void)scene;
    (void)frames;
    (void)path;
    return "the built-in scenes are not built";
#endif
}

} // namespace

std::string encodeScene(const std::string &scene, const std::string &size, int frames,
                        const std::string &clip, const media::SourceProviders &providers,
                        bool &interrupted)
{
    const std::string spec =
        "synthetic:" + scene + ",size=" + size + ",frames=" + std::to_string(frames);
    media::SourceOptions so;
    so.streamTitle = "color";
    auto color = media::openFrameSource(spec, so, providers);
    if (!color)
        return std::string("cannot render the scene: ") + color.error().what;
    so.streamTitle = "depth";
    auto depth = media::openFrameSource(spec, so, providers);
    if (!depth)
        return std::string("cannot render the scene's depth: ") + depth.error().what;
    // The scene's haptic materials (skin, cloth...) as the clip's material track.
    so.streamTitle = "material";
    auto material = media::openFrameSource(spec, so, providers);
    if (!material)
        return std::string("cannot render the scene's materials: ") + material.error().what;
    media::EncodeOptions eo;
    eo.output = clip;
    eo.preset = "veryfast";
    eo.depthCrf = 12;
    const std::string soundtrack = clip + ".soundtrack.wav";
    if (std::string why = writeSoundtrack(scene, frames, soundtrack); !why.empty())
        return why;
    eo.audioSource = soundtrack;
    eo.audioRequired = true;
    media::EncodeCallbacks cb;
    cb.progress = [](const media::EncodeProgress &p) {
        if (p.totalFrames > 0 && (p.frames % 10 == 0 || p.frames == p.totalFrames)) {
            std::fprintf(stderr, "\r  rendering and encoding frame %lld of %lld (%.1f fps)",
                         p.frames, p.totalFrames,
                         p.elapsed > 0 ? static_cast<double>(p.frames) / p.elapsed : 0.0);
            std::fflush(stderr);
        }
    };
    std::atomic<bool> stop{false};
    auto r = [&] {
        platform::StopSignals signals(stop, false);
        return media::encodeStreams(**color, **depth, material->get(), eo, &stop, cb);
    }();
    std::fprintf(stderr, "\n");
    std::error_code removed;
    std::filesystem::remove(soundtrack, removed);
    if (stop.load()) {
        interrupted = true;
        std::error_code ec;
        std::filesystem::remove(clip, ec);
        return {};
    }
    if (!r)
        return std::string("cannot encode the scene: ") + r.error().what;
    return {};
}

} // namespace depthtouch::demo
