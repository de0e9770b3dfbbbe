#include "depthtouch/platform/thread_config.h"

#include <cstring>
#include <sched.h>

#include <gtest/gtest.h>

namespace depthtouch::platform {
namespace {

TEST(ThreadConfigTest, hapticIsTheOnlyFifoThreadAndTheHighest)
{
    // GIVEN the priority table
    int fifoCount = 0;
    for (const ThreadConfig &config : kThreadTable) {
        // THEN every entry is valid, and only the haptic thread is SCHED_FIFO
        EXPECT_TRUE(isValidThreadConfig(config)) << config.name;
        if (config.policy == SchedPolicy::Fifo) {
            ++fifoCount;
            EXPECT_STREQ(config.name, kHapticThread.name);
        }
        EXPECT_GE(absolutePriority(kHapticThread), absolutePriority(config)) << config.name;
    }
    EXPECT_EQ(fifoCount, 1);
    EXPECT_EQ(kHapticThread.policy, SchedPolicy::Fifo);
}

TEST(ThreadConfigTest, namesAreUnique)
{
    // GIVEN the priority table
    // THEN no two threads share a name (ps/top output must identify them)
    for (const ThreadConfig &a : kThreadTable) {
        int same = 0;
        for (const ThreadConfig &b : kThreadTable)
            same += std::strcmp(a.name, b.name) == 0 ? 1 : 0;
        EXPECT_EQ(same, 1) << a.name;
    }
}

TEST(ThreadConfigTest, absolutePriorityIsRelativeToTheMaximum)
{
    // GIVEN the kernel's SCHED_FIFO range
    const int maxPriority = sched_get_priority_max(SCHED_FIFO);
    const int minPriority = sched_get_priority_min(SCHED_FIFO);
    // THEN 0 is the maximum, -1 one below, and out-of-range values are clamped
    EXPECT_EQ(absolutePriority(ThreadConfig{"t", SchedPolicy::Fifo, 0, 1 << 20}), maxPriority);
    EXPECT_EQ(absolutePriority(ThreadConfig{"t", SchedPolicy::Fifo, -1, 1 << 20}), maxPriority - 1);
    EXPECT_EQ(absolutePriority(kHapticThread), maxPriority + kHapticThread.relativePriority);
    EXPECT_EQ(absolutePriority(ThreadConfig{"t", SchedPolicy::Fifo, -100000, 1 << 20}),
              minPriority);
    EXPECT_EQ(absolutePriority(ThreadConfig{"t", SchedPolicy::Fifo, 5, 1 << 20}), maxPriority);
    EXPECT_EQ(absolutePriority(kDecodeThread), 0);
}

TEST(ThreadConfigTest, nameLengthLimitIsFifteen)
{
    // GIVEN names around the pthread_setname_np limit
    // THEN 15 characters pass and 16 do not; empty and null names are rejected
    EXPECT_TRUE(isValidThreadName("0123456789abcde"));
    EXPECT_FALSE(isValidThreadName("0123456789abcdef"));
    EXPECT_FALSE(isValidThreadName(""));
    EXPECT_FALSE(isValidThreadName(nullptr));
}

TEST(ThreadConfigTest, invalidConfigsAreRejected)
{
    // GIVEN configs that break one rule each
    // THEN each is invalid
    EXPECT_FALSE(isValidThreadConfig(ThreadConfig{"t", SchedPolicy::Other, -1, 1 << 20}));
    EXPECT_FALSE(isValidThreadConfig(ThreadConfig{"t", SchedPolicy::Fifo, 1, 1 << 20}));
    EXPECT_FALSE(isValidThreadConfig(ThreadConfig{"t", SchedPolicy::Fifo, 0, 4096}));
    EXPECT_TRUE(isValidThreadConfig(ThreadConfig{"t", SchedPolicy::Fifo, 0, 64 * 1024}));
}

TEST(ThreadConfigTest, policyNamesAndConstants)
{
    // THEN names and SCHED_* constants match
    EXPECT_STREQ(schedPolicyName(SchedPolicy::Fifo), "SCHED_FIFO");
    EXPECT_STREQ(schedPolicyName(SchedPolicy::Other), "SCHED_OTHER");
    EXPECT_EQ(toSchedPolicy(SchedPolicy::Fifo), SCHED_FIFO);
    EXPECT_EQ(toSchedPolicy(SchedPolicy::Other), SCHED_OTHER);
}

} // namespace
} // namespace depthtouch::platform
