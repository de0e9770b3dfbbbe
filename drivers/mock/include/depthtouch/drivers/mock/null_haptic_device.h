#pragma once
/// \file
/// \brief NullHapticDevice: the explicit "no haptic device" backend (`none`): haptics off.
///
/// Choice: it reports no device rather than a fixed position, so the app runs its ordinary
/// "device not connected" path (zero force, no contact) instead of computing forces nobody feels.
/// open() succeeds and leaves the device Disconnected; read() and commandForce() return
/// Errc::NoDevice (InvalidState when Closed); isConnected() is false. Capabilities: name "none",
/// maxForce 0, an empty workspace at the origin, nominal 1000 Hz, no buttons. Thread-safety and
/// real-time: as hal::HapticDevice (every call is trivially real-time safe).

#include <atomic>
#include <memory>

#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/haptic_device.h"

namespace depthtouch::drivers {

class NullHapticDevice final : public hal::HapticDevice {
public:
    /// Backend factory; ignores the options (so "mock,none" can share them as a fallback).
    static Result<std::unique_ptr<hal::HapticDevice>> create(const hal::BackendConfig &cfg);

    NullHapticDevice();
    ~NullHapticDevice() override = default;

    [[nodiscard]] const hal::HapticCapabilities &capabilities() const noexcept override
    {
        return caps_;
    }
    [[nodiscard]] State state() const noexcept override
    {
        return state_.load(std::memory_order_acquire);
    }
    [[nodiscard]] Result<void> open() override;
    void close() noexcept override { state_.store(State::Closed, std::memory_order_release); }
    [[nodiscard]] Result<void> read(hal::HapticState &out) noexcept override;
    [[nodiscard]] Result<void> commandForce(const hal::Vec3 &force) noexcept override;
    [[nodiscard]] bool isConnected() const noexcept override { return false; }

private:
    [[nodiscard]] Result<void> noDevice() const noexcept;

    hal::HapticCapabilities caps_;
    std::atomic<State> state_{State::Closed};
};

} // namespace depthtouch::drivers
