#pragma once
/// \file
/// \brief SimulatedHapticDeviceBase: what the simulated haptic devices (MockHapticDevice, backend
/// `mock`; SimHapticDevice, backend `sim`) share over hal::HapticDeviceBase: the fault injection
/// (unplug, stall) and the published output force.
///
/// Real-time: every member is noexcept and only loads and stores atomics (no allocation, lock or
/// log). Thread-safety: the fault injection and lastForce() may be called from any thread;
/// setOutput() has one writer at a time (the haptic thread, or open()/close() when it is not
/// running).

#include <atomic>

#include "depthtouch/drivers/mock/vec3_cell.h"
#include "depthtouch/hal/haptic_device_base.h"

namespace depthtouch::drivers {

class SimulatedHapticDeviceBase : public hal::HapticDeviceBase {
public:
    /// \name Fault injection (thread-safe)
    ///@{
    /// Unplugs the device: the output force becomes zero; read() and commandForce() return NoDevice
    /// and the state becomes Disconnected; open() fails with NoDevice until reconnect().
    void disconnect() noexcept { present_.store(false, std::memory_order_release); }
    /// Plugs the device back in: a Disconnected device stays so until close() and open().
    void reconnect() noexcept { present_.store(true, std::memory_order_release); }
    /// While \a stalled, read() and commandForce() return Timeout (a stalled USB endpoint); the
    /// output force stays what it was.
    void setStalled(bool stalled) noexcept { stalled_.store(stalled, std::memory_order_release); }
    ///@}

    /// \return the force the device outputs now, newtons: the last accepted command after clamping,
    /// or zero when not connected, after open(), close() or a non-finite command. Thread-safe.
    [[nodiscard]] hal::Vec3 lastForce() const noexcept
    {
        return isConnected() ? output_.load() : hal::Vec3{};
    }

protected:
    SimulatedHapticDeviceBase() = default;

    /// \return false between disconnect() and reconnect().
    [[nodiscard]] bool devicePresent() const noexcept override
    {
        return present_.load(std::memory_order_acquire);
    }
    /// Outputs zero force (nothing to disconnect from).
    void closeDevice() noexcept override { zeroForceDevice(); }
    /// Sets the output force to zero.
    void zeroForceDevice() noexcept override { setOutput({}); }

    /// \return Timeout ("Haptic device did not answer") while stalled, else success.
    [[nodiscard]] Result<void> checkStall() const noexcept
    {
        if (stalled_.load(std::memory_order_acquire))
            return unexpected(Errc::Timeout, "Haptic device did not answer");
        return ok();
    }
    /// Publishes \a f (newtons) as the output force read by lastForce() (single writer).
    void setOutput(const hal::Vec3 &f) noexcept { output_.store(f); }

private:
    std::atomic<bool> present_{true};
    std::atomic<bool> stalled_{false};
    // Output force: a sequence lock over three atomics so observers on other threads read a
    // consistent vector without blocking the haptic thread.
    Vec3Cell output_;
};

} // namespace depthtouch::drivers
