#pragma once
/// \file
/// \brief HapticDevice: a 3-DOF force-feedback device (e.g. a Novint Falcon): reads the handle
/// position, outputs a force.
///
/// Device frame (every position, velocity and force here): right-handed, metres (positions), m/s
/// (velocities), newtons (forces); origin at the centre of the workspace; x to the user's right, y
/// up, z toward the user. The app maps it to the scene-box frame of docs/architecture.md §3 (same
/// axes).
///
/// State machine:
/// \verbatim
///   Closed --open()--> Open --(unplugged, USB error)--> Disconnected
///     ^                  |                                  |
///     +-----close()------+-------------close()--------------+
/// \endverbatim
/// In Disconnected, read() and commandForce() return Errc::NoDevice and the device outputs no
/// force. To recover, close() and open() again from a non-real-time thread (open() fails with
/// NoDevice while the device is absent). A call not allowed in the current state returns
/// Errc::InvalidState and has no effect; read() and commandForce() in Closed return InvalidState.
///
/// Safety: the output force is zero in Closed and Disconnected, after close(), and until the first
/// commandForce() after open(). Every backend clamps the commanded force to Capabilities::maxForce
/// (keeping its direction) and outputs zero for a non-finite force. Backends derive from
/// HapticDeviceBase (haptic_device_base.h), which does the state, presence, clamp and non-finite
/// checks of this contract and leaves them only the device I/O.
///
/// Thread-safety and real-time: read(), commandForce(), state() and isConnected() are called from
/// the haptic SCHED_FIFO thread at the servo rate: in every backend they are noexcept and do not
/// allocate, lock, log or wait for more than one device transaction. open() and close() are for a
/// non-real-time thread and must not run concurrently with read() or commandForce(); capabilities()
/// is constant. Time: HapticState::time is on the backend clock (BackendConfig::clock).

#include <cstdint>
#include <string>

#include "depthtouch/hal/types.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::hal {

/// \brief What a haptic device can do. Constant for the device's lifetime.
struct HapticCapabilities {
    std::string name; ///< Model, e.g. "Novint Falcon".
    double maxForce =
        0.0; ///< Largest force magnitude in newtons it outputs; commands are clamped to it.
    Vec3 workspaceMin; ///< Lowest corner of the reachable box, metres, device frame.
    Vec3 workspaceMax; ///< Highest corner of the reachable box, metres, device frame.
    double servoRateHz =
        0.0; ///< Nominal update rate of the device in hertz (read + command per period).
    int buttonCount = 0; ///< Buttons reported in HapticState::buttons (bits 0..buttonCount-1).
};

/// \brief One sample of the handle.
struct HapticState {
    Vec3 position;              ///< Metres, device frame; inside [workspaceMin, workspaceMax].
    Vec3 velocity;              ///< m/s, device frame; meaningful when velocityValid.
    bool velocityValid = false; ///< The device measured or estimated the velocity.
    std::uint32_t buttons = 0;  ///< Bit i set while button i is pressed.
    platform::TimePoint time{}; ///< When the position was sampled, on the backend clock.
};

/// \brief A 3-DOF haptic device.
class HapticDevice {
public:
    enum class State : std::uint8_t { Closed, Open, Disconnected };

    virtual ~HapticDevice() = default;

    /// \return what the device can do; constant for its whole lifetime.
    [[nodiscard]] virtual const HapticCapabilities &capabilities() const noexcept = 0;

    /// \return the current state. Real-time safe.
    [[nodiscard]] virtual State state() const noexcept = 0;

    /// \brief Connects to the device and starts it with zero force. Not real-time safe.
    /// \pre Closed.
    /// \return nothing on success (state Open, or Disconnected for a backend without a device such
    /// as `none`). Errors: InvalidState (not Closed), NoDevice (absent), PermissionDenied (no
    /// access), Io.
    [[nodiscard]] virtual Result<void> open() = 0;

    /// \brief Outputs zero force and disconnects. Always allowed; no-op when Closed. Not real-time
    /// safe.
    virtual void close() noexcept = 0;

    /// \brief Samples the handle. Real-time safe.
    /// \pre Open.
    /// \param[out] out The sample; written only on success.
    /// \return nothing on success. Errors: InvalidState (Closed), NoDevice (Disconnected, or the
    /// device went away during this call: state becomes Disconnected), Timeout (no answer within
    /// one servo period; the device stays Open and the next call may succeed).
    [[nodiscard]] virtual Result<void> read(HapticState &out) noexcept = 0;

    /// \brief Sets the output force until the next command. Real-time safe.
    /// \pre Open.
    /// \param[in] force Newtons, device frame. Clamped to capabilities().maxForce; a non-finite
    /// value outputs zero force and returns InvalidArgument. \return nothing on success. Errors:
    /// InvalidState (Closed), NoDevice (Disconnected: the output is zero), InvalidArgument
    /// (non-finite force), Timeout (as read()).
    [[nodiscard]] virtual Result<void> commandForce(const Vec3 &force) noexcept = 0;

    /// \return true when the device is Open and answering. Real-time safe.
    [[nodiscard]] virtual bool isConnected() const noexcept = 0;

    /// \return true while a backend created without its device (BackendConfig::awaitDevice: none
    /// was connected) has not yet opened one; false otherwise, and for backends that never wait.
    /// For the player's messages at its start. Thread-safe.
    [[nodiscard]] virtual bool awaitingDevice() const noexcept { return false; }

protected:
    HapticDevice() = default;
    DT_DISABLE_COPY_AND_MOVE(HapticDevice)
};

/// \return the name of \a s: "Closed", "Open" or "Disconnected" (a static string; "?" for another
/// value), for messages. Thread-safe.
[[nodiscard]] const char *toString(HapticDevice::State s) noexcept;

} // namespace depthtouch::hal
