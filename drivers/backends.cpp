// The backend tables: the only file that tests the DT_HAVE_* macros (docs/style.md §2). A real
// driver adds its row here inside `#if DT_HAVE_<TECH>`, ahead of the mock rows, in the order
// autoprobe should try.
#include "depthtouch/drivers/backends.h"

#include <iterator>

#include "depthtouch/config.h"
#include "depthtouch/platform/message_text.h"
#if DT_HAVE_FFMPEG
#include "depthtouch/drivers/ffmpeg/ffmpeg_media_source.h"
#include "depthtouch/drivers/ffmpeg/ffmpeg_video_decoder.h"
#endif
#if DT_HAVE_LIBUSB
#include "depthtouch/drivers/usb/falcon_haptic_device.h"
#endif
#if DT_HAVE_EVDEV
#include "depthtouch/drivers/evdev/evdev_remote_input.h"
#endif
#if DT_HAVE_ALSA
#include "depthtouch/drivers/alsa/alsa_audio_output.h"
#endif
#if DT_HAVE_V4L2
#include "depthtouch/drivers/v4l2/v4l2_depth_camera.h"
#include "depthtouch/drivers/v4l2/v4l2_device.h"
#include "depthtouch/drivers/v4l2/v4l2_probe.h"
#endif
#if DT_HAVE_EGL
#include "depthtouch/drivers/egl/egl_headless_display.h"
#endif
#if DT_HAVE_EGL && DT_HAVE_EGL_GBM
#include "depthtouch/drivers/egl/egl_gbm_display.h"
#endif
#if DT_HAVE_EGL && DT_HAVE_EGL_X11
#include "depthtouch/drivers/egl/egl_x11_display.h"
#endif
#if DT_HAVE_FFMPEG
#include "depthtouch/drivers/ffmpeg/wav_audio_output.h"
#endif
#include "depthtouch/drivers/mock/mock_audio_output.h"
#include "depthtouch/drivers/mock/mock_depth_camera.h"
#include "depthtouch/drivers/mock/mock_display.h"
#include "depthtouch/drivers/mock/mock_haptic_device.h"
#include "depthtouch/drivers/mock/mock_media_source.h"
#include "depthtouch/drivers/mock/mock_remote_input.h"
#include "depthtouch/drivers/mock/mock_video_decoder.h"
#include "depthtouch/drivers/mock/null_haptic_device.h"
#include "depthtouch/drivers/mock/sim_haptic_device.h"
#include "depthtouch/drivers/tty/tty_remote_input.h"

namespace depthtouch::drivers {

namespace {

#if DT_HAVE_FFMPEG
// libavcodec's h264_v4l2m2m needs a V4L2 M2M node whose OUTPUT queue takes H.264; any /dev/video*
// (a webcam, a depth camera) is not enough.
Result<std::unique_ptr<hal::VideoDecoder>> createV4l2m2mDecoder(const hal::BackendConfig &cfg)
{
#if DT_HAVE_V4L2
    const auto device = makeV4l2Device(cfg.clockRef());
    if (auto node = findM2mH264Decoder(*device); !node)
        return unexpected(node.error());
#endif
    return FfmpegVideoDecoder::createV4l2m2m(cfg);
}
#endif

// Simulated backends never autoprobe: a product run must not silently play synthetic video or feel
// a scripted hand. The `none` backends do, last: no remote or no haptic device is a valid setup.

constexpr hal::Backend<hal::MediaSource> kMediaSourceBackends[] = {
#if DT_HAVE_FFMPEG
    {"ffmpeg", "libavformat demuxer: files, URLs, image sequences (d/%06d.png, option fps)", true,
     &FfmpegMediaSource::create},
#endif
    {"mock", "Deterministic synthetic color + depth file (mock: URLs)", false,
     &MockMediaSource::create},
};

constexpr hal::Backend<hal::VideoDecoder> kVideoDecoderBackends[] = {
#if DT_HAVE_FFMPEG
    {"v4l2m2m", "H.264 on a V4L2 M2M device through libavcodec h264_v4l2m2m", true,
     &createV4l2m2mDecoder},
    {"ffmpeg", "libavcodec software decoder (H.264, HEVC, FFV1, raw, MJPEG)", true,
     &FfmpegVideoDecoder::create},
#endif
    {"mock", "Deterministic simulated decoder for the Mock codec", false,
     &MockVideoDecoder::create},
};

constexpr hal::Backend<hal::Display> kDisplayBackends[] = {
#if DT_HAVE_EGL && DT_HAVE_EGL_GBM
    {"kms", "GBM/KMS full screen on a DRM card, page flips (options mode=HDMI-A-1[:WxH@HZ], "
            "card, readback)", true,
     &EglGbmDisplay::create},
#endif
#if DT_HAVE_EGL && DT_HAVE_EGL_X11
    {"x11", "EGL + GLES 3 in an X11 window on $DISPLAY (options width, height, refresh, "
            "swap_interval, fullscreen, readback)",
     true, &EglX11Display::create},
#endif
#if DT_HAVE_EGL
    {"headless", "EGL surfaceless (Mesa) + GLES 3, offscreen, simulated vsync (options width, "
                 "height, refresh)",
     true, &EglHeadlessDisplay::create},
#endif
    {"mock", "Simulated display without GL, paced on the clock", false, &MockDisplay::create},
};

constexpr hal::Backend<hal::HapticDevice> kHapticDeviceBackends[] = {
#if DT_HAVE_LIBUSB
    {"falcon", "Novint Falcon over libusb (options firmware=PATH, max_force, emulate)", true,
     &FalconHapticDevice::create},
#endif
    {"mock", "Simulated 3-DOF device following scripted waypoints", false,
     &MockHapticDevice::create},
    {"sim", "Simulated hand pushed by an intent script and the force (intent=press|stroke|explore)",
     false, &SimHapticDevice::create},
    {"none", "No haptic device: haptics off", true, &NullHapticDevice::create},
};

constexpr hal::Backend<hal::RemoteInput> kRemoteInputBackends[] = {
#if DT_HAVE_EVDEV
    {"evdev", "Linux input device keys (IR, CEC, USB remotes; option device=/dev/input/eventN)",
     true, &EvdevRemoteInput::create},
#endif
    {"tty", "Single keys on the terminal (space, s, arrows, 3, h, r, q)", false,
     &TtyRemoteInput::create},
    {"mock", "Scripted key events (option keys=KEY_PLAY@1+KEY_RIGHT@2)", false,
     &MockRemoteInput::create},
    {"none", "No remote control", true, &NullRemoteInput::create},
};

constexpr hal::Backend<hal::DepthCamera> kDepthCameraBackends[] = {
#if DT_HAVE_V4L2
    {"v4l2", "V4L2 depth camera: Z16/Y16/GREY depth node (device=), YUYV/MJPEG color node (color=)",
     true, &V4l2DepthCamera::create},
#endif
    {"mock", "Simulated RGB-D camera: a sphere moving in front of a wall", false,
     &MockDepthCamera::create},
};

// ALSA first; where no sound card answers, `null` keeps the time, so a player always has an audio
// clock; `wav` and `mock` are asked for by name.
constexpr hal::Backend<hal::AudioOutput> kAudioOutputBackends[] = {
#if DT_HAVE_ALSA
    {"alsa", "ALSA PCM (device=default|hw:0,3|plughw:1|null, buffer=MS)", true,
     &AlsaAudioOutput::create},
#endif
#if DT_HAVE_FFMPEG
    {"wav", "Writes the sound into a WAV file, timed like a sound card (path=FILE, buffer=MS)",
     false, &WavAudioOutput::create},
#endif
    {"mock",
     "Simulated sound card with faults (buffer=MS, unplug=S, refuse_rate, "
     "refuse_channels)",
     false, &createMockAudioOutput},
    {"null", "No sound: the time kept as a sound card would (buffer=MS)", true,
     &createNullAudioOutput},
};

template <class I> std::vector<hal::BackendInfo> infos(hal::BackendTable<I> table)
{
    std::vector<hal::BackendInfo> out;
    out.reserve(table.size());
    for (const hal::Backend<I> &b : table)
        out.push_back({b.name, b.description, b.autoProbe});
    return out;
}

} // namespace

const char *backendKindName(BackendKind kind) noexcept
{
    // Indexed by BackendKind.
    static constexpr const char *kNames[] = {"media source",  "video decoder", "display",
                                             "haptic device", "remote input",  "depth camera",
                                             "audio output"};
    static_assert(std::size(kNames) == static_cast<std::size_t>(BackendKind::AudioOutput) + 1);
    const auto i = static_cast<std::size_t>(kind);
    return i < std::size(kNames) ? kNames[i] : "unknown";
}

hal::BackendTable<hal::MediaSource> mediaSourceBackends() noexcept
{
    return kMediaSourceBackends;
}
hal::BackendTable<hal::VideoDecoder> videoDecoderBackends() noexcept
{
    return kVideoDecoderBackends;
}
hal::BackendTable<hal::Display> displayBackends() noexcept
{
    return kDisplayBackends;
}
hal::BackendTable<hal::HapticDevice> hapticDeviceBackends() noexcept
{
    return kHapticDeviceBackends;
}
hal::BackendTable<hal::RemoteInput> remoteInputBackends() noexcept
{
    return kRemoteInputBackends;
}
hal::BackendTable<hal::DepthCamera> depthCameraBackends() noexcept
{
    return kDepthCameraBackends;
}
hal::BackendTable<hal::AudioOutput> audioOutputBackends() noexcept
{
    return kAudioOutputBackends;
}

namespace {

/// \return \a f called with the table of \a kind, or R{} for a value outside BackendKind.
template <class R, class F> R withTable(BackendKind kind, F f)
{
    switch (kind) {
    case BackendKind::MediaSource:
        return f(mediaSourceBackends());
    case BackendKind::VideoDecoder:
        return f(videoDecoderBackends());
    case BackendKind::Display:
        return f(displayBackends());
    case BackendKind::HapticDevice:
        return f(hapticDeviceBackends());
    case BackendKind::RemoteInput:
        return f(remoteInputBackends());
    case BackendKind::DepthCamera:
        return f(depthCameraBackends());
    case BackendKind::AudioOutput:
        return f(audioOutputBackends());
    }
    return R{};
}

/// \brief hal::selectBackend() over \a table, after refusing options of which one has an empty
/// name ("=", "=1"): no backend reads such an option, and its firstUnknownKey() check cannot name
/// it (an empty name there means "none unknown").
/// \return the backend. Errors: InvalidArgument (report->message says which options), or those of
/// hal::selectBackend().
template <class I>
Result<std::unique_ptr<I>> selectChecked(BackendKind kind, hal::BackendTable<I> table,
                                         std::string_view names, const hal::BackendConfig &cfg,
                                         hal::SelectionReport *report)
{
    if (cfg.options.find("")) {
        if (report != nullptr) {
            report->chosen.clear();
            report->message = std::string("Invalid ") + backendKindName(kind) + " options " +
                              platform::quotedText(cfg.options.text()) +
                              ": an option has an empty name";
        }
        return unexpected(Errc::InvalidArgument, "A backend option has an empty name");
    }
    return hal::selectBackend(backendKindName(kind), table, names, cfg, report);
}

} // namespace

std::vector<hal::BackendInfo> listBackends(BackendKind kind)
{
    return withTable<std::vector<hal::BackendInfo>>(kind, [](auto table) { return infos(table); });
}

std::string backendNames(BackendKind kind)
{
    return withTable<std::string>(kind, [](auto table) { return hal::backendNames(table); });
}

Result<std::unique_ptr<hal::MediaSource>> createMediaSource(std::string_view names,
                                                            const hal::BackendConfig &cfg,
                                                            hal::SelectionReport *report)
{
    return selectChecked(BackendKind::MediaSource, mediaSourceBackends(), names, cfg, report);
}

Result<std::unique_ptr<hal::VideoDecoder>> createVideoDecoder(std::string_view names,
                                                              const hal::BackendConfig &cfg,
                                                              hal::SelectionReport *report)
{
    return selectChecked(BackendKind::VideoDecoder, videoDecoderBackends(), names, cfg, report);
}

Result<std::unique_ptr<hal::Display>>
createDisplay(std::string_view names, const hal::BackendConfig &cfg, hal::SelectionReport *report)
{
    return selectChecked(BackendKind::Display, displayBackends(), names, cfg, report);
}

Result<std::unique_ptr<hal::HapticDevice>> createHapticDevice(std::string_view names,
                                                              const hal::BackendConfig &cfg,
                                                              hal::SelectionReport *report)
{
    return selectChecked(BackendKind::HapticDevice, hapticDeviceBackends(), names, cfg, report);
}

Result<std::unique_ptr<hal::RemoteInput>> createRemoteInput(std::string_view names,
                                                            const hal::BackendConfig &cfg,
                                                            hal::SelectionReport *report)
{
    return selectChecked(BackendKind::RemoteInput, remoteInputBackends(), names, cfg, report);
}

Result<std::unique_ptr<hal::DepthCamera>> createDepthCamera(std::string_view names,
                                                            const hal::BackendConfig &cfg,
                                                            hal::SelectionReport *report)
{
    return selectChecked(BackendKind::DepthCamera, depthCameraBackends(), names, cfg, report);
}

Result<std::unique_ptr<hal::AudioOutput>> createAudioOutput(std::string_view names,
                                                            const hal::BackendConfig &cfg,
                                                            hal::SelectionReport *report)
{
    return selectChecked(BackendKind::AudioOutput, audioOutputBackends(), names, cfg, report);
}

std::string audioOutputFilePath(std::string_view names, std::string_view options)
{
#if DT_HAVE_FFMPEG
    for (std::string_view rest = names; !rest.empty();) {
        const std::size_t comma = rest.find(',');
        std::string_view name = rest.substr(0, comma);
        rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
        while (!name.empty() && name.front() == ' ')
            name.remove_prefix(1);
        while (!name.empty() && name.back() == ' ')
            name.remove_suffix(1);
        if (name == "wav")
            return wavOutputPath(options, {});
    }
#else
    (void)names;
    (void)options;
#endif
    return {};
}

} // namespace depthtouch::drivers
