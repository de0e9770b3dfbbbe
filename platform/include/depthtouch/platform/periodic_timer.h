#pragma once
/// \file
/// \brief PeriodicTimer: the fixed-rate wait of a periodic task (the 1 kHz haptic loop), on
/// absolute deadlines, with overrun re-sync and lock-free statistics (docs/style.md §4.4, §4.6).
///
/// The header is C++17-clean.

#include <atomic>
#include <cstdint>

#include "depthtouch/platform/cache_line.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"

namespace depthtouch::platform {

/// \brief What one PeriodicTimer::wait() did.
struct PeriodicWait {
    TimePoint deadline; ///< The deadline this wait was for.
    TimePoint wakeTime; ///< Clock time when wait() returned.
    Duration
        latency; ///< wakeTime − deadline: wake-up latency, or how late the call was on an overrun.
    bool overrun;   ///< The deadline had already passed when wait() was called (no sleep).
    bool cancelled; ///< The clock cancelled the sleep before the deadline (ManualClock::release()).
    /// Overrun only: deadlines after this one that had also passed and are skipped by the re-sync.
    std::uint64_t missedPeriods;
};

/// \brief Sleeps a periodic task to absolute deadlines deadline₀ + k·period through
/// Clock::sleepUntil() (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME) on SteadyClock), so the
/// period never drifts.
///
/// start() anchors the schedule: the first deadline is now + period. Each wait() sleeps to the next
/// deadline and then advances it by one period. When wait() is called after its deadline has passed
/// (the previous cycle overran), it returns at once, counts an overrun and re-syncs: the next
/// deadline becomes now + period. It never returns back-to-back to catch up on missed deadlines.
///
/// Statistics (cycles, overruns, missed periods, maximum wake latency) are atomics written only by
/// the waiting thread and readable from any other thread, so a non-real-time thread can log them.
///
/// Thread-safety: start() and wait() are thread-bound (the periodic thread); period(), cycles(),
/// overruns(), missedPeriods() and maxWakeLatency() are thread-safe.
/// Real-time safety: wait() and start() are real-time safe (no allocation, no lock, no log) when
/// the clock is (SteadyClock is; ManualClock in Blocking mode takes a mutex).
class PeriodicTimer {
public:
    /// \param[in] clock time source; must outlive the timer.
    /// \param[in] period time between deadlines, > 0 (DT_ASSERT).
    PeriodicTimer(Clock &clock, Duration period) noexcept;

    /// Anchors the schedule: the next deadline is clock.now() + period. Call again to restart.
    void start() noexcept;
    /// Anchors the schedule on an explicit first deadline \a firstDeadline.
    void startAt(TimePoint firstDeadline) noexcept;

    /// \brief Sleeps until the next deadline (or returns at once on an overrun, see the class
    /// comment). \pre start() or startAt() was called (DT_ASSERT). \return what happened; see
    /// PeriodicWait.
    PeriodicWait wait() noexcept;

    /// \return the period given at construction.
    [[nodiscard]] Duration period() const noexcept { return period_; }
    /// \return the deadline the next wait() sleeps to. Thread-bound.
    [[nodiscard]] TimePoint nextDeadline() const noexcept { return next_; }

    /// \return the number of wait() calls that returned (slept, overran or cancelled). Thread-safe.
    [[nodiscard]] std::uint64_t cycles() const noexcept
    {
        return stats_.cycles.load(std::memory_order_relaxed);
    }
    /// \return the number of overruns (wait() called after its deadline). Thread-safe.
    [[nodiscard]] std::uint64_t overruns() const noexcept
    {
        return stats_.overruns.load(std::memory_order_relaxed);
    }
    /// \return the total of PeriodicWait::missedPeriods. Thread-safe.
    [[nodiscard]] std::uint64_t missedPeriods() const noexcept
    {
        return stats_.missedPeriods.load(std::memory_order_relaxed);
    }
    /// \return the largest wakeTime − deadline over the waits that slept (overruns excluded: their
    /// lateness comes from the task, not from the wake-up). Thread-safe.
    [[nodiscard]] Duration maxWakeLatency() const noexcept
    {
        return Duration(stats_.maxWakeLatencyNs.load(std::memory_order_relaxed));
    }

private:
    DT_DISABLE_COPY_AND_MOVE(PeriodicTimer)

    Clock &clock_;
    const Duration period_;
    TimePoint next_{};
    bool started_ = false;

    /// Written by the waiting thread only (plain load + store, no read-modify-write needed); read
    /// by others. On its own cache line so readers do not slow the writer's next_.
    struct alignas(kCacheLineBytes) Stats {
        std::atomic<std::uint64_t> cycles{0};
        std::atomic<std::uint64_t> overruns{0};
        std::atomic<std::uint64_t> missedPeriods{0};
        std::atomic<std::int64_t> maxWakeLatencyNs{0};
    } stats_;
};

} // namespace depthtouch::platform
