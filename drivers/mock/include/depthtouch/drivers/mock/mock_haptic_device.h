#pragma once
/// \file
/// \brief MockHapticDevice: a simulated 3-DOF haptic device. The handle follows a script of
/// waypoints interpolated on the injected clock; commanded forces are clamped and recorded; the
/// device can be unplugged and can stall. Backend name `mock`.
///
/// Script: waypoints (time on the clock, position in the device frame, buttons). Between two
/// waypoints the position is interpolated linearly and the velocity is the segment's slope; before
/// the first and after the last the handle rests there (velocity zero); positions are clamped to
/// the workspace. With no script the handle rests at the workspace centre. Buttons are those of the
/// waypoint at or before the time.
///
/// The state, the clamp and non-finite handling are hal::HapticDeviceBase's, the fault injection
/// and the output force SimulatedHapticDeviceBase's; this class is the device. Real-time: read(),
/// commandForce(), state() and isConnected() do not allocate, lock or log; they read the injected
/// clock (a platform::ManualClock takes a mutex: use it for simulation only). Thread-safety: as
/// hal::HapticDevice. setWaypoints() must not run concurrently with read(). The fault injection and
/// observer calls are thread-safe (a test thread may unplug the device while the haptic thread
/// runs).

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "depthtouch/hal/backends.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/drivers/mock/simulated_haptic_device.h"

namespace depthtouch::drivers {

/// \brief The simulated device's capabilities.
struct MockHapticSettings {
    double maxForce = 8.5; ///< Newtons (option `max_force`, > 0).
    double workspaceHalfExtent =
        0.05; ///< Half the edge of the cubic workspace, metres (option `workspace`, > 0).
    double servoRateHz = 1000.0; ///< Hertz (option `servo_rate`, > 0).
    int buttonCount = 4;         ///< Buttons (option `buttons`, 0..32).

    /// \return the settings from \a options over the defaults; InvalidArgument for an unknown key
    /// or a value out of range.
    static Result<MockHapticSettings> parse(hal::OptionList options);
};

/// One point of the handle's script.
struct HapticWaypoint {
    platform::TimePoint time{}; ///< On the device's clock.
    hal::Vec3 position;         ///< Metres, device frame.
    std::uint32_t buttons = 0;  ///< Buttons held from this waypoint to the next.
};

class MockHapticDevice final : public SimulatedHapticDeviceBase {
public:
    /// Backend factory: settings from cfg.options, time from cfg.clock.
    static Result<std::unique_ptr<hal::HapticDevice>> create(const hal::BackendConfig &cfg);

    explicit MockHapticDevice(platform::Clock &clock, const MockHapticSettings &settings = {});
    ~MockHapticDevice() override = default;

    /// \name Scripting (not concurrently with read())
    ///@{
    /// Replaces the script; the points are sorted by time.
    void setWaypoints(std::vector<HapticWaypoint> points);
    ///@}

    /// \name Observers (thread-safe)
    ///@{
    /// lastForce() and the fault injection (disconnect(), reconnect(), setStalled()): see
    /// SimulatedHapticDeviceBase.
    /// \return commands accepted since creation (non-finite ones included).
    [[nodiscard]] std::uint64_t forceCount() const noexcept
    {
        return forceCount_.load(std::memory_order_relaxed);
    }
    /// \return commands that were clamped to maxForce since creation.
    [[nodiscard]] std::uint64_t clampCount() const noexcept
    {
        return clampCount_.load(std::memory_order_relaxed);
    }
    /// \return the largest output force magnitude since creation, newtons.
    [[nodiscard]] double maxForceMagnitude() const noexcept
    {
        return maxMagnitude_.load(std::memory_order_relaxed);
    }
    /// \return successful reads since creation.
    [[nodiscard]] std::uint64_t readCount() const noexcept
    {
        return readCount_.load(std::memory_order_relaxed);
    }
    ///@}

    /// \return the scripted handle sample at \a t (position clamped to the workspace).
    [[nodiscard]] hal::HapticState sampleAt(platform::TimePoint t) const noexcept;

protected:
    [[nodiscard]] Result<State> openDevice() override;
    [[nodiscard]] Result<void> readDevice(hal::HapticState &out) noexcept override;
    [[nodiscard]] Result<void>
    commandForceDevice(const hal::ForceCommand &command) noexcept override;

private:
    platform::Clock &clock_;
    std::vector<HapticWaypoint> waypoints_;

    std::atomic<std::uint64_t> forceCount_{0};
    std::atomic<std::uint64_t> clampCount_{0};
    std::atomic<double> maxMagnitude_{0.0};
    std::atomic<std::uint64_t> readCount_{0};
};

} // namespace depthtouch::drivers
