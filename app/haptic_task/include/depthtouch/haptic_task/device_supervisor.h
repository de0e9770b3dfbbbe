#pragma once
/// \file
/// \brief DeviceSupervisor: the haptic task's device supervision (docs/architecture.md §5): the two
/// watchdogs (missed deadlines, device time-outs) on the haptic thread, the hand-over of a lost
/// device to the telemetry thread, which closes and opens it every reconnectIntervalMs until it
/// answers, and back (hot-plug recovery), and the counters of all that.

#include <algorithm>
#include <atomic>
#include <cstdint>

#include "depthtouch/hal/haptic_device.h"
#include "depthtouch/haptic_task/haptic_counters.h"
#include "depthtouch/haptic_task/haptic_stats.h"
#include "depthtouch/haptic_task/haptic_task_config.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/periodic_timer.h"

namespace depthtouch::haptic_task {

/// \brief Who may use the device, the watchdogs' counts and the supervision counters.
///
/// The device belongs to the haptic thread (Owned) until it is lost (lose(): unplugged or closed
/// under the task); then to the telemetry thread (supervise() closes and opens it), which hands it
/// back reopened (Restored); the haptic thread's takeDevice() takes it (Owned again). The owner
/// state is an atomic published with release and read with acquire, so whoever takes the device
/// sees what the other thread did to it.
///
/// Thread-safety: begin() on the owner thread before the threads start; the "haptic thread"
/// functions on the haptic thread only (real-time safe: inline, atomics and plain counters, no
/// allocation, lock, log or device call); supervise() on the telemetry thread only (it logs and
/// calls the device's close() and open()); the readers anywhere.
class DeviceSupervisor {
public:
    /// What takeDevice() found.
    enum class Ownership : std::uint8_t {
        Owned,    ///< The haptic thread has the device.
        Restored, ///< It had been lost and is back: the haptic thread took it and starts afresh.
        Lost,     ///< The telemetry thread has it: don't touch it.
    };

    /// \a config (watchdog limits, servo rate, reconnect interval) and \a device must outlive it.
    DeviceSupervisor(const HapticTaskConfig &config, hal::HapticDevice &device) noexcept
        : config_(config), device_(device), period_(1.0 / config.servoRateHz)
    {
    }
    DT_DISABLE_COPY_AND_MOVE(DeviceSupervisor)

    /// The haptic thread starts with the device if it is answering; otherwise the telemetry thread
    /// polls for it (hot-plug) and hands it over once open. Owner thread, before start.
    void begin() noexcept
    {
        owner_.store(device_.isConnected() ? kRtOwns : kLost, std::memory_order_release);
    }

    /// \name Haptic thread only (real-time safe)
    ///@{
    /// \return true when the loop missed more than watchdogMissedDeadlines deadlines in a row, or
    /// woke that late (a stopped process): the update must command no force.
    bool watchDeadlines(const platform::PeriodicWait &wait) noexcept;
    /// Takes a reopened device back. \return who has the device now.
    Ownership takeDevice() noexcept;
    /// \return true while the haptic thread owns the device.
    [[nodiscard]] bool owns() const noexcept
    {
        return owner_.load(std::memory_order_acquire) == kRtOwns;
    }
    /// Counts a device time-out. \return true when this one trips the device watchdog (more than
    /// watchdogDeviceTimeouts in a row, not already holding zero): command zero, then holdZero().
    bool countTimeout() noexcept
    {
        return ++timeoutsInARow_ > config_.watchdogDeviceTimeouts && !deviceFailed_.load();
    }
    /// The device watchdog holds zero force until the device answers; counts the trip.
    void holdZero() noexcept
    {
        deviceFailed_.store(true, std::memory_order_release);
        bump(watchdogTrips_);
    }
    /// The device answered: the time-out count restarts and the device watchdog lets go.
    void answered() noexcept
    {
        timeoutsInARow_ = 0;
        deviceFailed_.store(false, std::memory_order_relaxed);
    }
    /// Counts a zero-force trip of the deadline watchdog.
    void countTrip() noexcept { bump(watchdogTrips_); }
    /// The device went away: count it and hand it to the telemetry thread.
    void lose() noexcept
    {
        bump(deviceLosses_);
        owner_.store(kLost, std::memory_order_release);
    }
    ///@}

    /// Telemetry thread only: while the device is lost, closes and opens it every
    /// reconnectIntervalMs (on the steady clock) and hands it back once it answers; logs the loss
    /// once and each return.
    void supervise();

    /// \name Readers (thread-safe)
    ///@{
    /// \return true while the haptic thread owns a connected device (false while it is lost or the
    /// device watchdog holds zero).
    [[nodiscard]] bool connected() const noexcept { return owns() && !deviceFailed_.load(); }
    /// Fills watchdogTrips, deviceLosses, reconnects and deviceConnected of \a s.
    void fill(HapticStats &s) const noexcept
    {
        s.deviceConnected = connected();
        s.watchdogTrips = watchdogTrips_.load(std::memory_order_relaxed);
        s.deviceLosses = deviceLosses_.load(std::memory_order_relaxed);
        s.reconnects = reconnects_.load(std::memory_order_relaxed);
    }
    ///@}

private:
    static constexpr std::uint8_t kRtOwns = 0;   ///< The haptic thread uses the device.
    static constexpr std::uint8_t kLost = 1;     ///< The telemetry thread may close/open it.
    static constexpr std::uint8_t kRestored = 2; ///< Reopened; the haptic thread takes it back.

    const HapticTaskConfig &config_;
    hal::HapticDevice &device_;
    const double period_; ///< s.

    std::atomic<std::uint8_t> owner_{kRtOwns};
    std::atomic<bool> deviceFailed_{false}; ///< Watchdog holding zero for device time-outs.
    // Counters written by one thread (plain load + store), read by anyone.
    std::atomic<std::uint64_t> watchdogTrips_{0}; ///< Haptic thread.
    std::atomic<std::uint64_t> deviceLosses_{0};  ///< Haptic thread.
    std::atomic<std::uint64_t> reconnects_{0};    ///< Telemetry thread.
    // Haptic thread only.
    int missedInARow_ = 0;
    int timeoutsInARow_ = 0;
    // Telemetry thread only.
    bool lostLogged_ = false;
    platform::TimePoint lastReconnectTry_{}; ///< On the steady clock.
};

[[gnu::always_inline]] inline bool
DeviceSupervisor::watchDeadlines(const platform::PeriodicWait &wait) noexcept
{
    // Watchdog 1: the loop itself is late. More than N deadlines missed in a row → zero force now;
    // the ramp brings the force back once the deadlines are kept again.
    if (wait.overrun) {
        missedInARow_ += 1 + static_cast<int>(std::min<std::uint64_t>(wait.missedPeriods, 1000000));
    } else {
        missedInARow_ = 0;
    }
    // A wake-up as late as that many deadlines (the process was stopped, SIGSTOP then SIGCONT,
    // while the thread slept; a suspended machine) missed them as surely as an overrun does, and
    // the device moved meanwhile: this update commands no force either, not only the next one.
    const double lateSeconds = platform::toSeconds(wait.latency);
    const bool wokeLate =
        !wait.overrun && lateSeconds > (config_.watchdogMissedDeadlines + 1) * period_;
    return wokeLate || missedInARow_ > config_.watchdogMissedDeadlines;
}

[[gnu::always_inline]] inline DeviceSupervisor::Ownership DeviceSupervisor::takeDevice() noexcept
{
    const std::uint8_t owner = owner_.load(std::memory_order_acquire);
    if (owner == kRestored) {
        owner_.store(kRtOwns, std::memory_order_release);
        return Ownership::Restored;
    }
    return owner == kRtOwns ? Ownership::Owned : Ownership::Lost;
}

} // namespace depthtouch::haptic_task
