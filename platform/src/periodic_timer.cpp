#include "depthtouch/platform/periodic_timer.h"

#include "depthtouch/platform/assert.h"

namespace depthtouch::platform {

namespace {

/// Adds \a delta to a counter that only the calling thread writes (no atomic read-modify-write
/// needed).
void bump(std::atomic<std::uint64_t> &counter, std::uint64_t delta = 1) noexcept
{
    counter.store(counter.load(std::memory_order_relaxed) + delta, std::memory_order_relaxed);
}

} // namespace

PeriodicTimer::PeriodicTimer(Clock &clock, Duration period) noexcept
    : clock_(clock), period_(period)
{
    DT_ASSERT(period > Duration::zero());
}

void PeriodicTimer::start() noexcept
{
    startAt(clock_.now() + period_);
}

void PeriodicTimer::startAt(TimePoint firstDeadline) noexcept
{
    next_ = firstDeadline;
    started_ = true;
}

PeriodicWait PeriodicTimer::wait() noexcept
{
    DT_ASSERT(started_);
    const TimePoint deadline = next_;
    const bool slept = clock_.sleepUntil(deadline);
    const TimePoint wake = clock_.now();

    PeriodicWait result{deadline, wake, wake - deadline, false, false, 0};
    if (slept) {
        next_ = deadline + period_;
        const std::int64_t latencyNs = result.latency.count();
        if (latencyNs > stats_.maxWakeLatencyNs.load(std::memory_order_relaxed))
            stats_.maxWakeLatencyNs.store(latencyNs, std::memory_order_relaxed);
    } else if (wake < deadline) {
        // The clock gave up before the deadline (ManualClock::release()): not the task's fault, and
        // the schedule stays as it was.
        result.cancelled = true;
    } else {
        // Late: the previous cycle took too long. Re-sync to now instead of returning back-to-back
        // for every missed deadline, which would only make the next cycles late too.
        result.overrun = true;
        result.missedPeriods = static_cast<std::uint64_t>(result.latency / period_);
        next_ = wake + period_;
        bump(stats_.overruns);
        bump(stats_.missedPeriods, result.missedPeriods);
    }
    bump(stats_.cycles);
    return result;
}

} // namespace depthtouch::platform
