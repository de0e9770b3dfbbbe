// The names of the HAL interfaces' states, for messages: one copy for every backend.
#include "depthtouch/hal/audio_output.h"
#include "depthtouch/hal/depth_camera.h"
#include "depthtouch/hal/display.h"
#include "depthtouch/hal/haptic_device.h"
#include "depthtouch/hal/media_source.h"
#include "depthtouch/hal/video_decoder.h"
#include "depthtouch/platform/enum_names.h"

#include <array>

namespace depthtouch::hal {

namespace {

// Every interface's state names, in the order of its State enumeration.
constexpr std::array<const char *, 3> kHapticDeviceStates = {"Closed", "Open", "Disconnected"};
constexpr std::array<const char *, 3> kDisplayStates = {"Closed", "Open", "Lost"};
constexpr std::array<const char *, 3> kDepthCameraStates = {"Unconfigured", "Configured",
                                                            "Streaming"};
constexpr std::array<const char *, 3> kVideoDecoderStates = {"Closed", "Configured", "Running"};
constexpr std::array<const char *, 2> kMediaSourceStates = {"Closed", "Open"};
constexpr std::array<const char *, 4> kAudioOutputStates = {"Closed", "Open", "Paused", "Lost"};

} // namespace

const char *toString(HapticDevice::State s) noexcept
{
    return platform::enumName(s, kHapticDeviceStates, "?");
}

const char *toString(Display::State s) noexcept
{
    return platform::enumName(s, kDisplayStates, "?");
}

const char *toString(DepthCamera::State s) noexcept
{
    return platform::enumName(s, kDepthCameraStates, "?");
}

const char *toString(VideoDecoder::State s) noexcept
{
    return platform::enumName(s, kVideoDecoderStates, "?");
}

const char *toString(MediaSource::State s) noexcept
{
    return platform::enumName(s, kMediaSourceStates, "?");
}

const char *toString(AudioOutput::State s) noexcept
{
    return platform::enumName(s, kAudioOutputStates, "?");
}

} // namespace depthtouch::hal
