/// \file
/// \brief The hal::DepthCamera contract around a backend's hooks (see depth_camera_base.h).

#include "depthtouch/hal/depth_camera_base.h"

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(HalCamera)

namespace depthtouch::hal {

Result<void> DepthCameraBase::check(bool allowed, const char *call,
                                    const char *required) const noexcept
{
    if (allowed)
        return ok();
    DT_LOG(HalCamera, Error, "In state %s trying %s() requiring %s", toString(state_), call,
           required);
    return unexpected(Errc::InvalidState, "Call not allowed in the camera's state");
}

Result<void> DepthCameraBase::configure(const CameraConfig &cfg)
{
    DT_TRY(check(state_ != State::Streaming, "configure", "Unconfigured or Configured"));
    if (!cfg.depth && !cfg.color)
        return unexpected(Errc::InvalidArgument, "No stream requested");
    if (cfg.depth && cfg.depthFormat == PixelFormat::Gray16 &&
        !(cfg.nearMetres > 0.0 && cfg.farMetres > cfg.nearMetres))
        return unexpected(Errc::InvalidArgument, "Nearness needs 0 < near < far");
    unconfigured_ = false;
    if (auto r = configureDevice(cfg); !r) {
        if (unconfigured_)
            state_ = State::Unconfigured;
        return r;
    }
    state_ = State::Configured;
    return ok();
}

CameraIntrinsics DepthCameraBase::intrinsics() const noexcept
{
    return state_ == State::Unconfigured ? CameraIntrinsics{} : intrinsicsDevice();
}

Result<void> DepthCameraBase::start()
{
    DT_TRY(check(state_ == State::Configured, "start", "Configured"));
    DT_TRY(startDevice());
    state_ = State::Streaming;
    return ok();
}

Result<Capture> DepthCameraBase::capture(Deadline until)
{
    DT_TRY(check(state_ == State::Streaming, "capture", "Streaming"));
    return captureDevice(until);
}

Result<void> DepthCameraBase::stop()
{
    DT_TRY(check(state_ == State::Streaming, "stop", "Streaming"));
    stopDevice();
    state_ = State::Configured;
    return ok();
}

} // namespace depthtouch::hal
