#pragma once
/// \file
/// \brief DepthCameraBase: the hal::DepthCamera state machine in one place, for every RGB-D camera
/// backend.
///
/// A backend derives from DepthCameraBase and implements only the device work (the protected
/// `...Device()` hooks); the public methods are `final` and do the contract of depth_camera.h
/// around them, as DisplayBase, VideoDecoderBase and MediaSourceBase do for theirs (libcamera's
/// queueRequest() and queueRequestDevice()):
/// - configure(): InvalidState when Streaming; InvalidArgument when no stream is on, or for 16-bit
///   nearness without 0 < near < far; then configureDevice(); Configured on success. On error the
///   state stays, unless the hook called markUnconfigured() (its device was left half set up).
/// - intrinsics(): {} when Unconfigured, else intrinsicsDevice().
/// - start(): InvalidState unless Configured, then startDevice(); Streaming on success.
/// - capture(): InvalidState unless Streaming, then captureDevice().
/// - stop(): InvalidState unless Streaming, then stopDevice(); Configured.
/// Every InvalidState is logged (category HalCamera, error) with the call and the state.
///
/// Thread-safety: thread-bound, as hal::DepthCamera.

#include "depthtouch/hal/depth_camera.h"

namespace depthtouch::hal {

/// \brief The base of every depth camera backend: owns the state and the contract (see the file
/// comment); the backend implements the hooks.
class DepthCameraBase : public DepthCamera {
public:
    ~DepthCameraBase() override = default;

    [[nodiscard]] const DepthCameraCapabilities &capabilities() const noexcept final
    {
        return caps_;
    }
    [[nodiscard]] State state() const noexcept final { return state_; }
    [[nodiscard]] Result<void> configure(const CameraConfig &cfg) final;
    [[nodiscard]] CameraIntrinsics intrinsics() const noexcept final;
    [[nodiscard]] Result<void> start() final;
    [[nodiscard]] Result<Capture> capture(Deadline until) final;
    [[nodiscard]] Result<void> stop() final;

protected:
    DepthCameraBase() = default;

    /// \brief Selects the mode of \a cfg and allocates the pools (called Unconfigured or
    /// Configured, with a stream on and valid near/far planes). \return Errors: as configure()
    /// (Busy, NotSupported, NoDevice, ...); call markUnconfigured() first when the device is left
    /// without a configuration.
    [[nodiscard]] virtual Result<void> configureDevice(const CameraConfig &cfg) = 0;
    /// \return the intrinsics of the configured depth image (called Configured or Streaming).
    [[nodiscard]] virtual CameraIntrinsics intrinsicsDevice() const noexcept = 0;
    /// \brief Starts streaming (called Configured). \return Errors: as start() (NoDevice, ...).
    [[nodiscard]] virtual Result<void> startDevice() = 0;
    /// \brief Lends the next frame set (called Streaming). \return Errors: as capture().
    [[nodiscard]] virtual Result<Capture> captureDevice(Deadline until) = 0;
    /// \brief Stops streaming (called Streaming); lent frames stay valid.
    virtual void stopDevice() noexcept = 0;

    /// \brief From configureDevice() on error: the device lost its configuration, the camera is
    /// Unconfigured when configure() returns.
    void markUnconfigured() noexcept { unconfigured_ = true; }

    DepthCameraCapabilities caps_; ///< Set by the backend's constructor; constant afterwards.

private:
    /// InvalidState (logged) unless \a allowed.
    [[nodiscard]] Result<void> check(bool allowed, const char *call,
                                     const char *required) const noexcept;

    State state_ = State::Unconfigured;
    bool unconfigured_ = false; ///< Set by markUnconfigured() during a configure().
};

} // namespace depthtouch::hal
