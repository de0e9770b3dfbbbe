#include "depthtouch/platform/periodic_timer.h"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>

#include <gtest/gtest.h>

namespace depthtouch::platform {
namespace {

using std::chrono::microseconds;
using std::chrono::milliseconds;

constexpr TimePoint kStart = TimePoint(std::chrono::seconds(1));
constexpr Duration kPeriod = milliseconds(1);

/// Clock that wakes each sleeper late by a scripted amount (simulated scheduling latency).
class LateClock final : public Clock {
public:
    [[nodiscard]] TimePoint now() const noexcept override { return now_; }
    bool sleepUntil(TimePoint deadline) noexcept override
    {
        if (now_ >= deadline)
            return false;
        now_ = deadline + nextLateness;
        return true;
    }
    void advance(Duration d) noexcept { now_ += d; }

    Duration nextLateness{};

private:
    TimePoint now_ = kStart;
};

TEST(PeriodicTimerTest, wakesExactlyOnAbsoluteDeadlines)
{
    // GIVEN a 1 ms timer on an AutoAdvance clock, started at 1 s
    ManualClock clock(ManualClock::Mode::AutoAdvance, kStart);
    PeriodicTimer timer(clock, kPeriod);
    timer.start();
    EXPECT_EQ(timer.nextDeadline(), kStart + kPeriod);
    // WHEN it waits 10 times
    for (int k = 1; k <= 10; ++k) {
        const PeriodicWait w = timer.wait();
        // THEN wake k is exactly at start + k periods, with no latency and no overrun
        EXPECT_EQ(w.deadline, kStart + k * kPeriod);
        EXPECT_EQ(w.wakeTime, w.deadline);
        EXPECT_EQ(w.latency, Duration::zero());
        EXPECT_FALSE(w.overrun);
        EXPECT_FALSE(w.cancelled);
        EXPECT_EQ(w.missedPeriods, 0u);
    }
    EXPECT_EQ(timer.cycles(), 10u);
    EXPECT_EQ(timer.overruns(), 0u);
    EXPECT_EQ(timer.maxWakeLatency(), Duration::zero());
}

TEST(PeriodicTimerTest, shortWorkKeepsTheScheduleWithoutDrift)
{
    // GIVEN a 1 ms timer whose cycles each take 0.4 ms of work
    ManualClock clock(ManualClock::Mode::AutoAdvance, kStart);
    PeriodicTimer timer(clock, kPeriod);
    timer.start();
    PeriodicWait w{};
    // WHEN it runs 100 cycles
    for (int k = 1; k <= 100; ++k) {
        w = timer.wait();
        clock.advance(microseconds(400));
    }
    // THEN the deadlines did not drift (absolute, not relative sleeps) and nothing overran
    EXPECT_EQ(w.deadline, kStart + 100 * kPeriod);
    EXPECT_EQ(timer.overruns(), 0u);
}

TEST(PeriodicTimerTest, longUpdateCountsAnOverrunAndResyncs)
{
    // GIVEN a 1 ms timer after its first wake at start + 1 ms
    ManualClock clock(ManualClock::Mode::AutoAdvance, kStart);
    PeriodicTimer timer(clock, kPeriod);
    timer.start();
    const PeriodicWait first = timer.wait();
    ASSERT_EQ(first.wakeTime, kStart + kPeriod);

    // WHEN the update takes 3.5 periods
    clock.advance(microseconds(3500));
    const PeriodicWait late = timer.wait();

    // THEN that wait returns at once as an overrun, with the two whole periods skipped
    EXPECT_TRUE(late.overrun);
    EXPECT_EQ(late.deadline, kStart + 2 * kPeriod);
    EXPECT_EQ(late.wakeTime, kStart + microseconds(4500));
    EXPECT_EQ(late.latency, microseconds(2500));
    EXPECT_EQ(late.missedPeriods, 2u);
    // AND the schedule re-synced to now + period
    EXPECT_EQ(timer.nextDeadline(), late.wakeTime + kPeriod);

    // WHEN the next cycles are quick
    const PeriodicWait next = timer.wait();
    const PeriodicWait after = timer.wait();
    // THEN they sleep a full period each: no burst of back-to-back wakes to catch up
    EXPECT_FALSE(next.overrun);
    EXPECT_EQ(next.deadline, kStart + microseconds(5500));
    EXPECT_EQ(next.wakeTime - late.wakeTime, kPeriod);
    EXPECT_FALSE(after.overrun);
    EXPECT_EQ(after.wakeTime - next.wakeTime, kPeriod);
    EXPECT_EQ(timer.cycles(), 4u);
    EXPECT_EQ(timer.overruns(), 1u);
    EXPECT_EQ(timer.missedPeriods(), 2u);
}

TEST(PeriodicTimerTest, slightlyLateCycleIsAnOverrunWithoutMissedPeriods)
{
    // GIVEN a 1 ms timer after its first wake
    ManualClock clock(ManualClock::Mode::AutoAdvance, kStart);
    PeriodicTimer timer(clock, kPeriod);
    timer.start();
    (void)timer.wait();
    // WHEN the update takes 1.2 periods
    clock.advance(microseconds(1200));
    const PeriodicWait w = timer.wait();
    // THEN it is an overrun with no whole period missed, and the next deadline is now + period
    EXPECT_TRUE(w.overrun);
    EXPECT_EQ(w.missedPeriods, 0u);
    EXPECT_EQ(timer.nextDeadline(), kStart + microseconds(3200));
}

TEST(PeriodicTimerTest, updateEndingExactlyOnTheDeadlineIsAnOverrun)
{
    // GIVEN a 1 ms timer after its first wake
    ManualClock clock(ManualClock::Mode::AutoAdvance, kStart);
    PeriodicTimer timer(clock, kPeriod);
    timer.start();
    (void)timer.wait();
    // WHEN the update takes exactly one period
    clock.advance(kPeriod);
    const PeriodicWait w = timer.wait();
    // THEN the deadline was not in the future: it counts as late (zero lateness), and re-syncs
    EXPECT_TRUE(w.overrun);
    EXPECT_EQ(w.latency, Duration::zero());
    EXPECT_EQ(timer.nextDeadline(), kStart + 3 * kPeriod);
}

TEST(PeriodicTimerTest, maxWakeLatencyTracksLateWakesOnly)
{
    // GIVEN a clock that wakes sleepers late by 30 us, then 70 us, then 10 us
    LateClock clock;
    PeriodicTimer timer(clock, kPeriod);
    timer.start();
    clock.nextLateness = microseconds(30);
    const PeriodicWait a = timer.wait();
    clock.nextLateness = microseconds(70);
    (void)timer.wait();
    clock.nextLateness = microseconds(10);
    (void)timer.wait();
    // WHEN a later cycle overruns by 5 ms (task lateness, not wake latency)
    clock.advance(milliseconds(5));
    const PeriodicWait overrun = timer.wait();
    // THEN the latency of each wake is reported, and the maximum covers the sleeps only
    EXPECT_EQ(a.latency, microseconds(30));
    EXPECT_TRUE(overrun.overrun);
    EXPECT_GT(overrun.latency, microseconds(70));
    EXPECT_EQ(timer.maxWakeLatency(), microseconds(70));
    // AND late wakes keep the absolute schedule (deadline + period, not wake + period)
    EXPECT_EQ(a.deadline + kPeriod, kStart + 2 * kPeriod);
}

TEST(PeriodicTimerTest, cancelledSleepIsNotAnOverrun)
{
    // GIVEN a released clock
    ManualClock clock(ManualClock::Mode::AutoAdvance, kStart);
    PeriodicTimer timer(clock, kPeriod);
    timer.start();
    clock.release();
    // WHEN the timer waits
    const PeriodicWait w = timer.wait();
    // THEN the wait is reported cancelled, not late, and the schedule is unchanged
    EXPECT_TRUE(w.cancelled);
    EXPECT_FALSE(w.overrun);
    EXPECT_EQ(timer.overruns(), 0u);
    EXPECT_EQ(timer.nextDeadline(), kStart + kPeriod);
}

TEST(PeriodicTimerTest, countersAreReadableFromAnotherThread)
{
    // GIVEN a timer running 20000 cycles on an AutoAdvance clock, one in ten overrunning
    ManualClock clock(ManualClock::Mode::AutoAdvance, kStart);
    PeriodicTimer timer(clock, kPeriod);
    constexpr std::uint64_t kCycles = 20000;
    std::atomic<bool> done{false};
    std::uint64_t backwards = 0;
    std::uint64_t lastSeen = 0;
    // WHEN another thread polls the counters meanwhile
    std::thread reader([&] {
        while (!done.load()) {
            const std::uint64_t c = timer.cycles();
            if (c < lastSeen)
                ++backwards;
            lastSeen = c;
            (void)timer.overruns();
            (void)timer.maxWakeLatency();
        }
    });
    timer.start();
    for (std::uint64_t k = 0; k < kCycles; ++k) {
        (void)timer.wait();
        if (k % 10 == 9)
            clock.advance(microseconds(1500));
    }
    done = true;
    reader.join();
    // THEN it never saw a counter go backwards, and the final values are exact
    EXPECT_EQ(backwards, 0u);
    EXPECT_EQ(timer.cycles(), kCycles);
    // (the last long update comes after the last wait)
    EXPECT_EQ(timer.overruns(), kCycles / 10 - 1);
}

TEST(PeriodicTimerTest, steadyClockSmoke)
{
    // GIVEN a 2 ms timer on the real clock
    SteadyClock &clock = SteadyClock::instance();
    PeriodicTimer timer(clock, milliseconds(2));
    const TimePoint begin = clock.now();
    timer.start();
    // WHEN it waits 25 times
    int sleptWithNegativeLatency = 0;
    for (int k = 0; k < 25; ++k) {
        const PeriodicWait w = timer.wait();
        if (!w.overrun && w.latency < Duration::zero())
            ++sleptWithNegativeLatency;
    }
    const Duration elapsed = clock.now() - begin;
    // THEN no wake came before its deadline, and the total time is plausible (generous bounds: an
    // overrun shifts the schedule later, never earlier)
    EXPECT_EQ(sleptWithNegativeLatency, 0);
    EXPECT_GE(elapsed, milliseconds(50));
    EXPECT_LT(elapsed, std::chrono::seconds(10));
    EXPECT_EQ(timer.cycles(), 25u);
    EXPECT_GE(timer.maxWakeLatency(), Duration::zero());
}

TEST(PeriodicTimerDeathTest, waitBeforeStartIsABug)
{
    // GIVEN a timer never started
    ManualClock clock;
    PeriodicTimer timer(clock, kPeriod);
    // THEN wait() aborts
    EXPECT_DEATH((void)timer.wait(), "assertion `started_' failed");
}

} // namespace
} // namespace depthtouch::platform
