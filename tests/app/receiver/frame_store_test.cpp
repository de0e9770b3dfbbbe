// receiver::FrameStore::allocate(): the pool sizes its header documents (1..1024 frames), bounds
// included, and a refusal that leaves the pool as it was; and the pixels that become resident only
// when a frame is written into its slot.
#include "depthtouch/receiver/frame_store.h"

#include <gtest/gtest.h>

#include <cstring>

#include "support/resident_memory.h"

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

using testing::residentBytes;

TEST(FrameStoreTest, aSlotBecomesResidentOnlyWhenAFrameIsWrittenIntoIt)
{
    // GIVEN 32 slots of 3840 x 2160 Gray16 (16.6 MB each, 531 MB in all)
    constexpr int kW = 3840;
    constexpr int kH = 2160;
    constexpr long long kFrame = 2LL * kW * kH;
    const long long before = residentBytes();
    FrameStore store;
    ASSERT_TRUE(store.allocate(32, hal::PixelFormat::Gray16, kW, kH));
    // THEN allocating them made less than two frames resident
    const long long allocated = residentBytes();
    EXPECT_LT(allocated - before, 2 * kFrame) << "allocate() touched the slots' pixels";
    // WHEN three frames are written, one after another, each released before the next
    for (int i = 0; i < 3; ++i) {
        StoredFrame *w = nullptr;
        FrameHandle h = store.acquire(w);
        ASSERT_TRUE(h);
        std::memset(w->image.row(0, 0), 0x5a, static_cast<std::size_t>(kFrame));
    }
    // THEN they went into the same slot: about one frame became resident, not three
    const long long written = residentBytes();
    EXPECT_GT(written - allocated, kFrame * 9 / 10);
    EXPECT_LT(written - allocated, 2 * kFrame);
}

} // namespace
} // namespace depthtouch::receiver
