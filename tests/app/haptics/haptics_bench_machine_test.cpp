// bench haptics' record of the machine (issue 61, item 8: the CPU's load and steal time beside the
// timings, a figure taken under load flagged): the steal share between two /proc/stat readings and
// the verdict "loaded".

#include <gtest/gtest.h>

#include "depthtouch/haptics/haptics_bench.h"

namespace depthtouch::haptics::bench {
namespace {

TEST(HapticsBenchMachineTest, theStealShareIsTheStolenTicksOverAllTicksThatPassed)
{
    // user nice system idle iowait irq softirq steal guest guest_nice
    const char *before = "cpu  1000 0 500 8000 100 0 0 400 300 0\n";
    // 400 ticks more in all (user 200, idle 120, steal 80); guest (in user already) not counted
    const char *after = "cpu  1200 0 500 8120 100 0 0 480 500 0\n";
    EXPECT_DOUBLE_EQ(stealPercent(before, after), 20.0);
    // no steal: 0; a kernel without the steal column (fewer than 8 numbers), a line that is not
    // the CPUs' line, or no time passed: unknown
    EXPECT_DOUBLE_EQ(stealPercent("cpu  1 2 3 4 5 6 7 8", "cpu  2 2 3 4 5 6 7 8"), 0.0);
    EXPECT_EQ(stealPercent("cpu  1 2 3 4 5 6 7", "cpu  2 2 3 4 5 6 7"), -1.0);
    EXPECT_EQ(stealPercent("cpu0 1 2 3 4 5 6 7 8", "cpu0 2 2 3 4 5 6 7 8"), -1.0);
    EXPECT_EQ(stealPercent("", after), -1.0);
    EXPECT_EQ(stealPercent(after, after), -1.0);
}

TEST(HapticsBenchMachineTest, aRunWithMuchStealIsTimedOnALoadedMachine)
{
    BenchReport r;
    r.cpus = 2;
    r.loadAtStart = 0.2;
    r.loadAtEnd = 0.3;
    EXPECT_FALSE(loadedMachine(r));
    r.stealPercent = kLoadedStealPercent;
    EXPECT_FALSE(loadedMachine(r)) << "at the limit";
    r.stealPercent = kLoadedStealPercent + 1.0;
    EXPECT_TRUE(loadedMachine(r)) << "steal reads high however low the load";
    r.stealPercent = 0.0;
    r.loadAtEnd = 1.5;
    EXPECT_TRUE(loadedMachine(r)) << "the load alone, as before";
}

} // namespace
} // namespace depthtouch::haptics::bench
