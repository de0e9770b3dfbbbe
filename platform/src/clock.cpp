#include "depthtouch/platform/clock.h"

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

bool SteadyClock::sleepUntil(TimePoint deadline) noexcept
{
    if (now() >= deadline)
        return false;
    const timespec ts = toTimespec(deadline);
    // clock_nanosleep returns the error number; EINTR means a signal arrived: sleep again to the same
    // absolute deadline (no drift, unlike relative sleeps).
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
    return true;
}

SteadyClock &SteadyClock::instance() noexcept
{
    static SteadyClock clock;
    return clock;
}

ManualClock::ManualClock(Mode mode, TimePoint start) : mode_(mode), now_(start) {}

TimePoint ManualClock::now() const noexcept
{
    std::lock_guard<std::mutex> lock(mutex_);
    return now_;
}

bool ManualClock::sleepUntil(TimePoint deadline) noexcept
{
    std::unique_lock<std::mutex> lock(mutex_);
    ++sleepCalls_;
    cv_.notify_all(); // advance() may be waiting for this thread to sleep again
    if (released_ || now_ >= deadline)
        return false;
    if (mode_ == Mode::AutoAdvance) {
        now_ = deadline;
        return true;
    }
    ++sleepers_;
    const auto entry = deadlines_.insert(deadline);
    cv_.notify_all();
    cv_.wait(lock, [&] { return released_ || now_ >= deadline; });
    deadlines_.erase(entry);
    --sleepers_;
    return !released_;
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
    // time to the earliest deadline, wake its sleepers, and wait until each of them has come back to
    // sleepUntil() or detached (a real-time guard keeps a thread that exits without detaching from
    // hanging the caller).
    while (!released_ && !deadlines_.empty() && *deadlines_.begin() <= target) {
        now_ = *deadlines_.begin();
        std::uint64_t due = 0;
        for (auto it = deadlines_.begin(); it != deadlines_.end() && *it <= now_; ++it)
            ++due;
        const std::uint64_t callsBefore = sleepCalls_;
        cv_.notify_all();
        const auto guard = std::chrono::steady_clock::now() + std::chrono::seconds(2);
        if (!cv_.wait_until(lock, guard, [&] { return released_ || sleepCalls_ - callsBefore >= due; }))
            break;
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
    return cv_.wait_for(lock, timeout, [&] { return sleepers_ >= count || released_; }) && sleepers_ >= count;
}

void ManualClock::detachThread() noexcept
{
    std::lock_guard<std::mutex> lock(mutex_);
    ++sleepCalls_;
    cv_.notify_all();
}

void ManualClock::release() noexcept
{
    std::lock_guard<std::mutex> lock(mutex_);
    released_ = true;
    cv_.notify_all();
}

} // namespace depthtouch::platform
