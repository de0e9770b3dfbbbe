#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/cpu_time.h"

#include <atomic>
#include <cerrno>
#include <ctime>

namespace depthtouch::platform {

namespace {

timespec toTimespec(TimePoint t) noexcept
{
    const auto ns = t.time_since_epoch().count();
    timespec ts{};
    ts.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
    ts.tv_nsec = static_cast<long>(ns % 1'000'000'000);
    return ts;
}

} // namespace

TimePoint SteadyClock::now() const noexcept
{
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return TimePoint(Duration(static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec));
}

Duration processCpuTime() noexcept
{
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return Duration(static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec);
}

bool SteadyClock::sleepUntil(TimePoint deadline) noexcept
{
    if (now() >= deadline)
        return false;
    const timespec ts = toTimespec(deadline);
    // clock_nanosleep returns the error number; EINTR means a signal arrived: sleep again to the
    // same absolute deadline (no drift, unlike relative sleeps).
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
    return true;
}

SteadyClock &SteadyClock::instance() noexcept
{
    // Never destroyed: a thread still running at exit (an open abandoned while libavformat blocks
    // in it, whose interrupt callback reads the clock) must not meet a destroyed clock.
    static SteadyClock *const clock = new SteadyClock;
    return *clock;
}

namespace {

std::atomic<std::uint64_t> gNextManualClockId{1};

/// The ManualClock (and its wake epoch) that last woke the calling thread; cleared when the thread
/// sleeps again or detaches. Identifies "this thread is running on that clock's behalf" without a
/// per-thread registry.
struct WokenBy {
    std::uint64_t clockId = 0;
    std::uint64_t epoch = 0;
};
thread_local WokenBy tWokenBy;

} // namespace

ManualClock::ManualClock(Mode mode, TimePoint start)
    : mode_(mode), id_(gNextManualClockId.fetch_add(1, std::memory_order_relaxed)), now_(start)
{}

TimePoint ManualClock::now() const noexcept
{
    std::lock_guard<std::mutex> lock(mutex_);
    return now_;
}

bool ManualClock::callerIsRunningLocked() const noexcept
{
    return tWokenBy.clockId == id_ && tWokenBy.epoch == wakeEpoch_;
}

void ManualClock::markNotRunningLocked() noexcept
{
    if (callerIsRunningLocked() && running_ > 0) {
        --running_;
        cv_.notify_all(); // advance() may be waiting for this thread
    }
    tWokenBy = WokenBy{};
}

bool ManualClock::sleepUntil(TimePoint deadline) noexcept
{
    std::unique_lock<std::mutex> lock(mutex_);
    // A passed deadline returns at once: the caller keeps running (and, if advance() woke it,
    // advance() keeps waiting for it), it is late rather than asleep.
    if (released_ || now_ >= deadline)
        return false;
    if (mode_ == Mode::AutoAdvance) {
        now_ = deadline;
        return true;
    }
    markNotRunningLocked();
    ++sleepers_;
    const auto entry = deadlines_.insert(deadline);
    cv_.notify_all(); // waitForSleepers() and advance() watch the sleepers
    cv_.wait(lock, [&] { return released_ || now_ >= deadline; });
    deadlines_.erase(entry);
    --sleepers_;
    if (released_)
        return false;
    // Woken by advance(): the time must not move on until this thread sleeps again or detaches.
    ++running_;
    tWokenBy = WokenBy{id_, wakeEpoch_};
    cv_.notify_all();
    return true;
}

void ManualClock::advance(Duration d) noexcept
{
    if (d <= Duration::zero())
        return;
    std::unique_lock<std::mutex> lock(mutex_);
    advanceLocked(lock, now_ + d);
}

void ManualClock::advanceTo(TimePoint t) noexcept
{
    std::unique_lock<std::mutex> lock(mutex_);
    if (t > now_)
        advanceLocked(lock, t);
}

void ManualClock::advanceLocked(std::unique_lock<std::mutex> &lock, TimePoint target) noexcept
{
    if (mode_ == Mode::AutoAdvance) {
        now_ = target;
        return;
    }
    // Step through the pending deadlines in order so clock-driven threads run reproducibly: set the
    // time to the earliest deadline, wake its sleepers, and wait until every woken thread has gone
    // back to sleep or detached, and no deadline at or before the current time is left. The caller
    // itself is not waited for when a clock-driven thread advances the time from its own cycle.
    //
    // Counting "woken and not yet asleep" threads, not sleepUntil() calls, matters: a woken thread
    // that calls sleepUntil() twice (once on a passed deadline, which returns at once) used to
    // count for two threads, so the time moved on while another woken thread was still running its
    // cycle.
    const auto settled = [&] {
        const int others = running_ - (callerIsRunningLocked() ? 1 : 0);
        return released_ || (others <= 0 && (deadlines_.empty() || *deadlines_.begin() > now_));
    };
    while (!released_ && !deadlines_.empty() && *deadlines_.begin() <= target) {
        // Never backwards: another thread's advance() may have moved the time past a deadline whose
        // sleeper has not run yet.
        if (*deadlines_.begin() > now_)
            now_ = *deadlines_.begin();
        cv_.notify_all();
        const auto guard = std::chrono::steady_clock::now() + std::chrono::seconds(2);
        if (!cv_.wait_until(lock, guard, settled)) {
            // A woken thread neither slept again nor detached within 2 s of real time (it exited or
            // blocks on something else): stop waiting for it and the threads woken with it, but
            // keep stepping the remaining deadlines in order.
            const bool self = callerIsRunningLocked();
            ++wakeEpoch_;
            running_ = 0;
            if (self) {
                running_ = 1;
                tWokenBy.epoch = wakeEpoch_;
            }
            // Sleepers that were woken but never got the mutex back would be stepped again: wait
            // for them at least to leave the deadline set.
            cv_.wait_until(lock, std::chrono::steady_clock::now() + std::chrono::seconds(2), [&] {
                return released_ || deadlines_.empty() || *deadlines_.begin() > now_;
            });
        }
    }
    if (target > now_)
        now_ = target;
    cv_.notify_all();
}

int ManualClock::sleepers() const noexcept
{
    std::lock_guard<std::mutex> lock(mutex_);
    return sleepers_;
}

bool ManualClock::waitForSleepers(int count, std::chrono::milliseconds timeout) noexcept
{
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, timeout, [&] { return sleepers_ >= count || released_; }) &&
           sleepers_ >= count;
}

void ManualClock::detachThread() noexcept
{
    std::lock_guard<std::mutex> lock(mutex_);
    markNotRunningLocked();
}

void ManualClock::release() noexcept
{
    std::lock_guard<std::mutex> lock(mutex_);
    released_ = true;
    cv_.notify_all();
}

} // namespace depthtouch::platform
