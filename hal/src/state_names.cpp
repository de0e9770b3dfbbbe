// The names of the HAL interfaces' states, for messages: one copy for every backend.
#include "depthtouch/hal/depth_camera.h"
#include "depthtouch/hal/display.h"
#include "depthtouch/hal/haptic_device.h"
#include "depthtouch/hal/media_source.h"
#include "depthtouch/hal/video_decoder.h"

namespace depthtouch::hal {

const char *toString(HapticDevice::State s) noexcept
{
    switch (s) {
    case HapticDevice::State::Closed:
        return "Closed";
    case HapticDevice::State::Open:
        return "Open";
    case HapticDevice::State::Disconnected:
        return "Disconnected";
    }
    return "?";
}

const char *toString(Display::State s) noexcept
{
    switch (s) {
    case Display::State::Closed:
        return "Closed";
    case Display::State::Open:
        return "Open";
    case Display::State::Lost:
        return "Lost";
    }
    return "?";
}

const char *toString(DepthCamera::State s) noexcept
{
    switch (s) {
    case DepthCamera::State::Unconfigured:
        return "Unconfigured";
    case DepthCamera::State::Configured:
        return "Configured";
    case DepthCamera::State::Streaming:
        return "Streaming";
    }
    return "?";
}

const char *toString(VideoDecoder::State s) noexcept
{
    switch (s) {
    case VideoDecoder::State::Closed:
        return "Closed";
    case VideoDecoder::State::Configured:
        return "Configured";
    case VideoDecoder::State::Running:
        return "Running";
    }
    return "?";
}

const char *toString(MediaSource::State s) noexcept
{
    switch (s) {
    case MediaSource::State::Closed:
        return "Closed";
    case MediaSource::State::Open:
        return "Open";
    }
    return "?";
}

} // namespace depthtouch::hal
