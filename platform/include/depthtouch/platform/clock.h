#pragma once
/// \file
/// \brief Monotonic time for the whole stack. All time flows through Clock: no other code reads
/// std::chrono::steady_clock or sleeps directly, so any component can run on simulated time.
///
/// Units: nanoseconds (Duration); TimePoint counts from an arbitrary epoch (CLOCK_MONOTONIC's for
/// SteadyClock, 0 or the given start for ManualClock). The header is C++17-clean.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <set>

#include "depthtouch/platform/macros.h"

namespace depthtouch::platform {

/// Tag clock for TimePoint: monotonic, nanosecond resolution.
struct MonotonicEpoch {
    using duration = std::chrono::nanoseconds;
    using rep = duration::rep;
    using period = duration::period;
    using time_point = std::chrono::time_point<MonotonicEpoch, duration>;
    static constexpr bool is_steady = true;
};

using Duration = std::chrono::nanoseconds;
using TimePoint = MonotonicEpoch::time_point;

/// Seconds (double) of a duration, for physics and logs.
constexpr double toSeconds(Duration d) noexcept { return static_cast<double>(d.count()) * 1e-9; }
/// Duration of \a seconds, rounded to the nearest nanosecond.
constexpr Duration fromSeconds(double seconds) noexcept
{
    return Duration(static_cast<std::int64_t>(seconds * 1e9 + (seconds >= 0 ? 0.5 : -0.5)));
}

/// \brief A monotonic clock that can also sleep until an absolute deadline.
///
/// Thread-safety: now() and sleepUntil() are thread-safe on every implementation.
class Clock {
public:
    virtual ~Clock() = default;

    /// \return the current time. Never goes backwards. Real-time safe (no allocation, no lock on
    /// SteadyClock).
    [[nodiscard]] virtual TimePoint now() const noexcept = 0;

    /// \brief Sleeps until \a deadline (absolute).
    /// \return true when the caller slept until the deadline, false when the deadline had already
    /// passed at the call (no sleep: the caller is late) or the sleep was cancelled
    /// (ManualClock::release()). Real-time safe on SteadyClock (clock_nanosleep with
    /// TIMER_ABSTIME).
    virtual bool sleepUntil(TimePoint deadline) noexcept = 0;

    /// Sleeps for \a d from now. \return as sleepUntil().
    bool sleepFor(Duration d) noexcept { return sleepUntil(now() + d); }

protected:
    Clock() = default;
    DT_DISABLE_COPY_AND_MOVE(Clock)
};

/// \brief The real monotonic clock (CLOCK_MONOTONIC); sleeps with clock_nanosleep(TIMER_ABSTIME),
/// resuming after signals. Thread-safe and real-time safe.
class SteadyClock final : public Clock {
public:
    SteadyClock() = default;
    [[nodiscard]] TimePoint now() const noexcept override;
    bool sleepUntil(TimePoint deadline) noexcept override;

    /// A process-wide instance for production code that has no clock injected; never destroyed
    /// (threads still running at exit may read it).
    static SteadyClock &instance() noexcept;
};

/// \brief Simulated time that moves only when told, for deterministic simulation and tests.
///
/// Modes:
/// - AutoAdvance (default): sleepUntil(t) jumps the time to t at once. A single-threaded loop
///   then runs as fast as the CPU allows on exact simulated deadlines (offline replay,
///   deterministic tests). Work can be made to "take time" with advance().
/// - Blocking: sleepUntil(t) blocks the calling thread until another thread advances the time to
///   t or beyond (or calls release()). advance() steps through the pending deadlines in time
///   order: it sets the time to the earliest one, wakes its sleepers and waits until each of
///   them sleeps again (a sleepUntil() that returns at once because its deadline has passed does
///   not count: that thread is still running) or detaches (detachThread(), or a 2 s real-time
///   guard expires). The time therefore does not move while a woken thread runs, and threads
///   driven by the clock run in a reproducible order. A woken thread may itself call advance()
///   (to make its work take simulated time); it is not waited for.
///
/// Thread-safety: thread-safe. Not real-time safe in Blocking mode (it takes a mutex); use it for
/// simulation only.
class ManualClock final : public Clock {
public:
    enum class Mode { AutoAdvance, Blocking };

    explicit ManualClock(Mode mode = Mode::AutoAdvance, TimePoint start = TimePoint{});

    [[nodiscard]] TimePoint now() const noexcept override;
    bool sleepUntil(TimePoint deadline) noexcept override;

    /// Moves the time forward by \a d (negative durations are ignored). Wakes due sleepers in
    /// order.
    void advance(Duration d) noexcept;
    /// Moves the time forward to \a t (never backwards). Wakes due sleepers in order.
    void advanceTo(TimePoint t) noexcept;

    /// Blocking mode: the number of threads currently sleeping in sleepUntil().
    [[nodiscard]] int sleepers() const noexcept;
    /// Blocking mode: waits (real time, at most \a timeout) until at least \a count threads sleep.
    /// \return true when they do.
    bool waitForSleepers(int count,
                         std::chrono::milliseconds timeout = std::chrono::seconds(2)) noexcept;
    /// Tells advance() not to wait for the calling thread to sleep again (call before a
    /// clock-driven thread exits).
    void detachThread() noexcept;
    /// Cancels every current and future sleep: sleepUntil() returns false at once. For shutdown.
    void release() noexcept;

    [[nodiscard]] Mode mode() const noexcept { return mode_; }

private:
    void advanceLocked(std::unique_lock<std::mutex> &lock, TimePoint target) noexcept;
    /// Blocking mode: the calling thread stops counting as woken-and-running. \pre mutex_ held.
    void markNotRunningLocked() noexcept;
    /// \return true when the calling thread was woken by this clock and has not slept or detached
    /// since. \pre mutex_ held.
    [[nodiscard]] bool callerIsRunningLocked() const noexcept;

    const Mode mode_;
    const std::uint64_t id_; ///< Unique per clock object, tags the threads it wakes.
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    TimePoint now_;                ///< Guarded by mutex_.
    int sleepers_ = 0;             ///< Guarded by mutex_.
    /// Guarded by mutex_: threads woken by advance() that have neither slept again nor detached.
    int running_ = 0;
    /// Guarded by mutex_: changes when advance() stops waiting for running threads (real-time
    /// guard), so the threads woken before do not count themselves off twice.
    std::uint64_t wakeEpoch_ = 0;
    bool released_ = false;        ///< Guarded by mutex_.
    std::multiset<TimePoint> deadlines_; ///< Guarded by mutex_: deadlines of the sleeping threads.
};

} // namespace depthtouch::platform
