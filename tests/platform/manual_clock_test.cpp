#include "depthtouch/platform/clock.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace depthtouch::platform {
namespace {

using std::chrono::milliseconds;

constexpr TimePoint at(int ms)
{
    return TimePoint(milliseconds(ms));
}

/// A wake-up seen by a clock-driven thread.
struct Wake {
    char thread;
    TimePoint deadline;
    TimePoint now;
};

/// Thread-safe list of wake-ups, in the order they were recorded.
class WakeLog {
public:
    void add(char thread, TimePoint deadline, TimePoint now)
    {
        std::lock_guard<std::mutex> lock(mutex_);
        wakes_.push_back({thread, deadline, now});
    }
    std::vector<Wake> wakes() const
    {
        std::lock_guard<std::mutex> lock(mutex_);
        return wakes_;
    }

private:
    mutable std::mutex mutex_;
    std::vector<Wake> wakes_;
};

TEST(ManualClockTest, autoAdvanceJumpsToTheDeadline)
{
    // GIVEN an AutoAdvance clock at 100 ms
    ManualClock clock(ManualClock::Mode::AutoAdvance, at(100));
    // WHEN a thread sleeps until 150 ms
    const bool slept = clock.sleepUntil(at(150));
    // THEN it returns at once with the time set to the deadline
    EXPECT_TRUE(slept);
    EXPECT_EQ(clock.now(), at(150));
    EXPECT_TRUE(clock.sleepFor(milliseconds(5)));
    EXPECT_EQ(clock.now(), at(155));
}

TEST(ManualClockTest, autoAdvanceReportsPassedDeadlines)
{
    // GIVEN an AutoAdvance clock at 100 ms
    ManualClock clock(ManualClock::Mode::AutoAdvance, at(100));
    // WHEN sleeping until a deadline that has passed, or is now
    // THEN sleepUntil returns false and the time stays
    EXPECT_FALSE(clock.sleepUntil(at(90)));
    EXPECT_FALSE(clock.sleepUntil(at(100)));
    EXPECT_EQ(clock.now(), at(100));
}

TEST(ManualClockTest, advanceNeverGoesBackwards)
{
    // GIVEN an AutoAdvance clock at 100 ms
    ManualClock clock(ManualClock::Mode::AutoAdvance, at(100));
    // WHEN advanced by a negative amount or to an earlier time
    clock.advance(milliseconds(-10));
    clock.advanceTo(at(50));
    // THEN the time does not change; forward moves work
    EXPECT_EQ(clock.now(), at(100));
    clock.advance(milliseconds(7));
    EXPECT_EQ(clock.now(), at(107));
    clock.advanceTo(at(200));
    EXPECT_EQ(clock.now(), at(200));
}

TEST(ManualClockTest, blockingStepsTwoThreadsInDeadlineOrder)
{
    // GIVEN two threads driven by a Blocking clock, with periods 3 ms and 5 ms
    ManualClock clock(ManualClock::Mode::Blocking);
    WakeLog log;
    auto periodic = [&](char name, int periodMs) {
        TimePoint next = at(periodMs);
        while (clock.sleepUntil(next)) {
            log.add(name, next, clock.now());
            next += milliseconds(periodMs);
        }
    };
    std::thread a(periodic, 'A', 3);
    std::thread b(periodic, 'B', 5);
    ASSERT_TRUE(clock.waitForSleepers(2));

    // WHEN the time is advanced to 30 ms in one call
    clock.advanceTo(at(30));
    const std::vector<Wake> wakes = log.wakes();
    clock.release();
    a.join();
    b.join();

    // THEN every wake saw the time equal to its deadline, in non-decreasing time order
    std::vector<std::string> seen;
    for (std::size_t i = 0; i < wakes.size(); ++i) {
        EXPECT_EQ(wakes[i].now, wakes[i].deadline) << "wake " << i;
        if (i > 0) {
            EXPECT_LE(wakes[i - 1].now, wakes[i].now) << "wake " << i;
        }
        seen.push_back(
            std::string(1, wakes[i].thread) +
            std::to_string(
                std::chrono::duration_cast<milliseconds>(wakes[i].now.time_since_epoch()).count()));
    }
    // AND exactly the deadlines up to 30 ms were served (ties at 15 and 30 in either order)
    std::vector<std::string> expected;
    for (int t = 3; t <= 30; t += 3)
        expected.push_back("A" + std::to_string(t));
    for (int t = 5; t <= 30; t += 5)
        expected.push_back("B" + std::to_string(t));
    std::sort(seen.begin(), seen.end());
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(seen, expected);
    EXPECT_EQ(clock.now(), at(30));
}

TEST(ManualClockTest, blockingTimeStaysWhileAWokenThreadWorks)
{
    // Regression: a woken thread that called sleepUntil() twice (once on a passed deadline) was
    // counted as two threads going back to sleep, so advance() moved the time on while another
    // thread woken at the same deadline was still running its cycle. GIVEN threads A and B both
    // sleeping until 10 ms; A, once woken, calls sleepUntil() on a passed deadline and then sleeps
    // again; B works for a while (real time) before reading the clock
    ManualClock clock(ManualClock::Mode::Blocking);
    std::atomic<bool> aPassedReturnedFalse{false};
    TimePoint bSaw{};
    std::thread a([&] {
        if (!clock.sleepUntil(at(10)))
            return;
        aPassedReturnedFalse = !clock.sleepUntil(at(10));
        clock.sleepUntil(at(20));
        clock.detachThread();
    });
    std::thread b([&] {
        if (!clock.sleepUntil(at(10)))
            return;
        std::this_thread::sleep_for(milliseconds(50));
        bSaw = clock.now();
        clock.sleepUntil(at(20));
        clock.detachThread();
    });
    ASSERT_TRUE(clock.waitForSleepers(2));

    // WHEN the time is advanced to 20 ms
    clock.advanceTo(at(20));
    a.join();
    b.join();

    // THEN B still saw 10 ms: the time did not move while it ran
    EXPECT_TRUE(aPassedReturnedFalse.load());
    EXPECT_EQ(bSaw, at(10));
    EXPECT_EQ(clock.now(), at(20));
}

TEST(ManualClockTest, blockingWokenThreadMayAdvanceTheTimeItself)
{
    // GIVEN thread A waking at 10 ms whose work takes 5 ms of simulated time (it advances the
    // clock), and thread B waking at 12 ms
    ManualClock clock(ManualClock::Mode::Blocking);
    WakeLog log;
    std::thread a([&] {
        if (!clock.sleepUntil(at(10)))
            return;
        log.add('A', at(10), clock.now());
        clock.advance(milliseconds(5));
        log.add('a', at(15), clock.now());
        clock.sleepUntil(at(40));
    });
    std::thread b([&] {
        if (!clock.sleepUntil(at(12)))
            return;
        log.add('B', at(12), clock.now());
        clock.sleepUntil(at(40));
    });
    ASSERT_TRUE(clock.waitForSleepers(2));
    const auto started = std::chrono::steady_clock::now();

    // WHEN the test advances to 20 ms
    clock.advanceTo(at(20));
    const auto elapsed = std::chrono::steady_clock::now() - started;
    const std::vector<Wake> wakes = log.wakes();
    clock.release();
    a.join();
    b.join();

    // THEN B woke at 12 ms inside A's advance, before A's work ended at 15 ms
    ASSERT_EQ(wakes.size(), 3u);
    EXPECT_EQ(wakes[0].thread, 'A');
    EXPECT_EQ(wakes[0].now, at(10));
    EXPECT_EQ(wakes[1].thread, 'B');
    EXPECT_EQ(wakes[1].now, at(12));
    EXPECT_EQ(wakes[2].thread, 'a');
    EXPECT_EQ(wakes[2].now, at(15));
    // AND A's own advance() did not wait for A (the 2 s guard would have expired); generous bound
    EXPECT_LT(elapsed, std::chrono::milliseconds(1500));
}

TEST(ManualClockTest, detachedThreadDoesNotStallAdvance)
{
    // GIVEN a thread that wakes once at 5 ms, detaches and exits
    ManualClock clock(ManualClock::Mode::Blocking);
    std::atomic<bool> woke{false};
    std::thread t([&] {
        woke = clock.sleepUntil(at(5));
        clock.detachThread();
    });
    ASSERT_TRUE(clock.waitForSleepers(1));
    const auto started = std::chrono::steady_clock::now();
    // WHEN the time is advanced past its deadline
    clock.advanceTo(at(100));
    const auto elapsed = std::chrono::steady_clock::now() - started;
    t.join();
    // THEN it woke, and advance() returned without waiting for the 2 s guard (generous bound)
    EXPECT_TRUE(woke.load());
    EXPECT_EQ(clock.now(), at(100));
    EXPECT_LT(elapsed, std::chrono::milliseconds(1500));
}

TEST(ManualClockTest, releaseUnblocksSleepers)
{
    // GIVEN two threads sleeping far in the future on a Blocking clock
    ManualClock clock(ManualClock::Mode::Blocking);
    std::atomic<int> falseReturns{0};
    auto sleeper = [&] {
        if (!clock.sleepUntil(at(3'600'000)))
            ++falseReturns;
    };
    std::thread a(sleeper);
    std::thread b(sleeper);
    ASSERT_TRUE(clock.waitForSleepers(2));
    EXPECT_EQ(clock.sleepers(), 2);
    // WHEN the clock is released
    clock.release();
    a.join();
    b.join();
    // THEN both sleeps returned false, the time did not move, and later sleeps return at once
    EXPECT_EQ(falseReturns.load(), 2);
    EXPECT_EQ(clock.sleepers(), 0);
    EXPECT_EQ(clock.now(), at(0));
    EXPECT_FALSE(clock.sleepUntil(at(1)));
}

TEST(ManualClockTest, waitForSleepersTimesOut)
{
    // GIVEN a Blocking clock with no sleeper
    ManualClock clock(ManualClock::Mode::Blocking);
    // THEN waiting for one returns false after the timeout
    EXPECT_FALSE(clock.waitForSleepers(1, milliseconds(10)));
    EXPECT_EQ(clock.mode(), ManualClock::Mode::Blocking);
}

TEST(SteadyClockTest, nowIsMonotonicAndSleepReachesTheDeadline)
{
    // GIVEN the steady clock
    SteadyClock &clock = SteadyClock::instance();
    const TimePoint start = clock.now();
    // WHEN sleeping 2 ms ahead, then on a passed deadline
    const TimePoint deadline = start + milliseconds(2);
    const bool slept = clock.sleepUntil(deadline);
    const TimePoint woke = clock.now();
    // THEN the wake is at or after the deadline, and a passed deadline returns false
    EXPECT_TRUE(slept);
    EXPECT_GE(woke, deadline);
    EXPECT_FALSE(clock.sleepUntil(start));
    EXPECT_LT(woke - start, std::chrono::seconds(5)); // generous sanity bound
}

TEST(ClockTest, secondsConversions)
{
    // THEN toSeconds/fromSeconds convert and round to the nearest nanosecond
    EXPECT_DOUBLE_EQ(toSeconds(milliseconds(1500)), 1.5);
    EXPECT_EQ(fromSeconds(0.001), milliseconds(1));
    EXPECT_EQ(fromSeconds(-0.25), milliseconds(-250));
    EXPECT_EQ(fromSeconds(1e-9 * 0.6), Duration(1));
}

} // namespace
} // namespace depthtouch::platform
