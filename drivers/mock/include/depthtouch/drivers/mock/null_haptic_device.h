#pragma once
/// \file
/// \brief NullHapticDevice: the explicit "no haptic device" backend (`none`): haptics off.
///
/// Choice: it reports no device rather than a fixed position, so the app runs its ordinary
/// "device not connected" path (zero force, no contact) instead of computing forces nobody feels.
/// open() succeeds and leaves the device Disconnected; read() and commandForce() return
/// Errc::NoDevice (InvalidState when Closed); isConnected() is false (hal::HapticDeviceBase does
/// all of it: the device hooks are never reached). Capabilities: name "none",
/// maxForce 0, an empty workspace at the origin, nominal 1000 Hz, no buttons. Thread-safety and
/// real-time: as hal::HapticDevice (every call is trivially real-time safe).

#include <memory>

#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/haptic_device_base.h"

namespace depthtouch::drivers {

class NullHapticDevice final : public hal::HapticDeviceBase {
public:
    /// Backend factory; ignores the options (so "mock,none" can share them as a fallback).
    static Result<std::unique_ptr<hal::HapticDevice>> create(const hal::BackendConfig &cfg);

    NullHapticDevice();
    ~NullHapticDevice() override = default;

protected:
    /// Leaves the device Disconnected.
    [[nodiscard]] Result<State> openDevice() override { return State::Disconnected; }
    void closeDevice() noexcept override {}
    [[nodiscard]] bool devicePresent() const noexcept override { return false; }
    [[nodiscard]] Result<void> readDevice(hal::HapticState &out) noexcept override;
    [[nodiscard]] Result<void>
    commandForceDevice(const hal::ForceCommand &command) noexcept override;
    void zeroForceDevice() noexcept override {}
};

} // namespace depthtouch::drivers
