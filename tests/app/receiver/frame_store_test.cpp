// receiver::FrameStore::allocate(): the pool sizes its header documents (1..1024 frames), bounds
// included, and a refusal that leaves the pool as it was.
#include "depthtouch/receiver/frame_store.h"

#include <gtest/gtest.h>

namespace depthtouch::receiver {
namespace {

TEST(FrameStoreTest, poolsOfOneTo1024FramesAreMadeAndOthersRefused)
{
    FrameStore store;
    // GIVEN the bounds: 1 and 1024 frames of 2 x 2 Gray8
    ASSERT_TRUE(store.allocate(1, hal::PixelFormat::Gray8, 2, 2));
    EXPECT_EQ(store.size(), 1);
    ASSERT_TRUE(store.allocate(1024, hal::PixelFormat::Gray8, 2, 2));
    EXPECT_EQ(store.size(), 1024);
    // THEN one past them is InvalidArgument and the pool keeps its 1024 frames
    for (const int count : {0, 1025}) {
        const Result<void> r = store.allocate(count, hal::PixelFormat::Gray8, 2, 2);
        ASSERT_FALSE(r) << count;
        EXPECT_EQ(r.error().code, Errc::InvalidArgument) << count;
        EXPECT_EQ(store.size(), 1024) << count;
    }
    // AND so is a frame with no bytes
    EXPECT_FALSE(store.allocate(4, hal::PixelFormat::Gray8, 0, 2));
}

} // namespace
} // namespace depthtouch::receiver
