#pragma once
/// \file
/// \brief HapticDeviceBase: the hal::HapticDevice contract in one place, for every backend.
///
/// A backend derives from HapticDeviceBase and implements only the device I/O (the protected
/// `...Device()` hooks); the public methods are `final` and do the contract around them, as
/// libcamera's PipelineHandler::queueRequest() checks a request before it calls the pipeline's
/// queueRequestDevice():
/// - open(): Closed required (else InvalidState, logged), then openDevice(); the state becomes the
///   one openDevice() returns (Open, or Disconnected for a backend without a device).
/// - read() and commandForce(): InvalidState when Closed, NoDevice when Disconnected; when the
///   device went away (devicePresent() false, or a hook returned NoDevice) the output is zeroed
///   (zeroForceDevice()) and the state becomes Disconnected, with NoDevice.
/// - commandForce(): a non-finite force commands zero (commandForceDevice() with a zero
///   ForceCommand) and returns InvalidArgument; a finite one is clamped to capabilities().maxForce
///   keeping its direction (clampForce()). commandForceDevice() never sees anything else.
/// - close(): closeDevice(), then Closed. isConnected(): Open and devicePresent().
///
/// Real-time: read(), commandForce(), state() and isConnected() only load and store atomics around
/// the hooks: no allocation, lock, log or throw (the hooks they call must keep to the same).
/// open() and close() are for a non-real-time thread, as in hal::HapticDevice.
/// Thread-safety: as hal::HapticDevice; state() may be read from any thread.

#include <atomic>

#include "depthtouch/hal/haptic_device.h"

namespace depthtouch::hal {

/// \brief A force command as a backend's commandForceDevice() receives it: finite, and no longer
/// than the device's maximum.
struct ForceCommand {
    Vec3 force;             ///< Newtons, device frame; |force| ≤ maxForce.
    double magnitude = 0.0; ///< |force|, newtons; exactly maxForce when clamped.
    bool clamped = false;   ///< The command was longer than maxForce and was scaled down to it.
};

/// \brief Clamps \a force to \a maxForce newtons keeping its direction (scaled by
/// maxForce / |force| when longer). \pre \a force is finite. Real-time safe.
[[nodiscard]] ForceCommand clampForce(const Vec3 &force, double maxForce) noexcept;

/// \brief The base of every haptic device backend: owns the state and the contract (see the file
/// comment); the backend implements the hooks.
class HapticDeviceBase : public HapticDevice {
public:
    ~HapticDeviceBase() override = default;

    [[nodiscard]] const HapticCapabilities &capabilities() const noexcept final { return caps_; }
    [[nodiscard]] State state() const noexcept final
    {
        return state_.load(std::memory_order_acquire);
    }
    [[nodiscard]] Result<void> open() final;
    void close() noexcept final;
    [[nodiscard]] Result<void> read(HapticState &out) noexcept final;
    [[nodiscard]] Result<void> commandForce(const Vec3 &force) noexcept final;
    [[nodiscard]] bool isConnected() const noexcept final;

protected:
    HapticDeviceBase() = default;

    /// \brief Connects to the device and starts it with zero force (called in state Closed).
    /// \return the state open() leaves: Open, or Disconnected for a backend without a device.
    /// Errors: as open() (NoDevice, PermissionDenied, Io, ...); the state stays Closed.
    [[nodiscard]] virtual Result<State> openDevice() = 0;
    /// \brief Outputs zero force and disconnects. Called by every close(), in any state (the state
    /// is still the one before close() while it runs). noexcept.
    virtual void closeDevice() noexcept = 0;
    /// \return whether the device is still there (plugged in). Real-time safe.
    [[nodiscard]] virtual bool devicePresent() const noexcept = 0;
    /// \brief Samples the handle into \a out (called Open and present). Real-time safe.
    /// \return Errors: Timeout (no answer), NoDevice (gone: the base marks it Disconnected).
    [[nodiscard]] virtual Result<void> readDevice(HapticState &out) noexcept = 0;
    /// \brief Outputs \a command until the next one (called Open and present; a non-finite
    /// command arrives as a zero one). Real-time safe.
    /// \return Errors: Timeout (no answer, output unchanged), NoDevice (gone).
    [[nodiscard]] virtual Result<void> commandForceDevice(const ForceCommand &command) noexcept = 0;
    /// \brief The device went away: forget the output force (zero), without device I/O.
    /// Real-time safe.
    virtual void zeroForceDevice() noexcept = 0;

    HapticCapabilities caps_; ///< Set by the backend's constructor; constant afterwards.

private:
    /// State and presence checks of read() and commandForce().
    [[nodiscard]] Result<void> checkUsable() noexcept;
    /// Zeroes the output and enters Disconnected.
    void markDisconnected() noexcept;
    /// \return \a r, marking the device Disconnected when it is NoDevice.
    [[nodiscard]] Result<void> noteLoss(Result<void> r) noexcept;

    std::atomic<State> state_{State::Closed};
};

} // namespace depthtouch::hal
