#include <array>
#include <utility>

#include <gtest/gtest.h>

#include "depthtouch/hal/types.h"

namespace depthtouch::hal {
namespace {

/// Counts releases per slot.
class CountingOwner final : public FrameOwner {
public:
    void releaseFrame(std::uint32_t slot) noexcept override { ++released[slot]; }
    std::array<int, 4> released{};
};

TEST(FrameRefTest, destructionReturnsTheFrameOnce)
{
    CountingOwner owner;
    Frame frame;
    {
        FrameRef ref(&owner, 2, &frame);
        EXPECT_TRUE(ref);
        EXPECT_EQ(ref.get(), &frame);
        EXPECT_EQ(owner.released[2], 0);
    }
    EXPECT_EQ(owner.released[2], 1);
}

TEST(FrameRefTest, moveTransfersOwnership)
{
    CountingOwner owner;
    Frame frame;
    FrameRef a(&owner, 1, &frame);
    FrameRef b(std::move(a));
    EXPECT_FALSE(a); // NOLINT(bugprone-use-after-move): moved-from state is specified
    EXPECT_TRUE(b);
    a.reset();
    EXPECT_EQ(owner.released[1], 0);
    b.reset();
    EXPECT_EQ(owner.released[1], 1);
    b.reset(); // idempotent
    EXPECT_EQ(owner.released[1], 1);
}

TEST(FrameRefTest, moveAssignmentReleasesThePreviousFrame)
{
    CountingOwner owner;
    Frame f0;
    Frame f3;
    FrameRef a(&owner, 0, &f0);
    FrameRef b(&owner, 3, &f3);
    a = std::move(b);
    EXPECT_EQ(owner.released[0], 1);
    EXPECT_EQ(owner.released[3], 0);
    EXPECT_EQ(a.get(), &f3);
    auto &self = a;
    a = std::move(self); // self-move keeps the frame
    EXPECT_EQ(owner.released[3], 0);
    EXPECT_TRUE(a);
}

TEST(FrameRefTest, emptyRefReleasesNothing)
{
    FrameRef ref;
    EXPECT_FALSE(ref);
    EXPECT_EQ(ref.get(), nullptr);
    ref.reset();
}

} // namespace
} // namespace depthtouch::hal
