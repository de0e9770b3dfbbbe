#include "depthtouch/platform/assert.h"

#include <gtest/gtest.h>

namespace depthtouch::platform {
namespace {

TEST(AssertDeathTest, failedAssertPrintsFileLineAndAborts)
{
    // GIVEN a condition that is false
    const int two = 2;
    // THEN DT_ASSERT aborts with file:line, function and condition on stderr
    EXPECT_DEATH(DT_ASSERT(two + 1 == 4),
                 "assert_test\\.cpp:[0-9]+: .*\\(\\): assertion `two \\+ 1 == 4' failed");
}

TEST(AssertTest, passingAssertDoesNothing)
{
    // GIVEN a true condition
    int reached = 0;
    // WHEN asserted
    DT_ASSERT(reached == 0);
    ++reached;
    // THEN execution continues
    EXPECT_EQ(reached, 1);
}

TEST(AssertTest, debugAssertIsNotEvaluatedWithNdebug)
{
    // GIVEN a condition that counts its evaluations (only to observe the macro; real asserts have
    // no side effects)
    int evaluations = 0;
    // WHEN passed to DT_DEBUG_ASSERT
    DT_DEBUG_ASSERT(++evaluations > 0);
    // THEN it is evaluated exactly when NDEBUG is not defined
#ifdef NDEBUG
    EXPECT_EQ(evaluations, 0);
#else
    EXPECT_EQ(evaluations, 1);
#endif
}

} // namespace
} // namespace depthtouch::platform
