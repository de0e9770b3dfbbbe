/// \file
/// \brief FramePool: pixels allocated now or on demand (dma-buf backends), slot state.

#include "depthtouch/drivers/common/frame_pool.h"

#include <gtest/gtest.h>

#include <cstring>

#include "support/resident_memory.h"

namespace depthtouch::drivers {
namespace {

TEST(FramePoolTest, onDemandFramesGetPlanesOnlyWhenAsked)
{
    // GIVEN a pool whose pixels are allocated on demand
    FramePool pool;
    ASSERT_TRUE(pool.allocate(2, hal::PixelFormat::Yuv420p, 6, 4, FramePool::Pixels::OnDemand));
    std::uint32_t slot = 99;
    hal::Frame *f = pool.acquire(slot);
    ASSERT_NE(f, nullptr);
    // THEN the acquired frame has its size and format but no planes
    EXPECT_TRUE(f->image.empty());
    EXPECT_EQ(f->image.width, 6);
    EXPECT_EQ(f->image.format, hal::PixelFormat::Yuv420p);
    EXPECT_TRUE(pool.isLent(slot));
    // WHEN its pixels are asked for  THEN it has three tightly packed planes
    ASSERT_TRUE(pool.ensurePixels(slot));
    EXPECT_FALSE(f->image.empty());
    EXPECT_EQ(f->image.planes[0].strideBytes, 6);
    EXPECT_EQ(f->image.planes[1].strideBytes, 3);
    EXPECT_EQ(f->image.planes[1].data, f->image.planes[0].data + 24);
    // AND asking again (a view reset in between) gives the same memory back
    std::uint8_t *const first = f->image.planes[0].data;
    f->image = hal::ImageView{};
    ASSERT_TRUE(pool.ensurePixels(slot));
    EXPECT_EQ(f->image.planes[0].data, first);
    {
        hal::FrameRef ref = pool.lend(slot);
        EXPECT_TRUE(pool.isLent(slot));
    }
    // AND a returned frame is no longer lent
    EXPECT_FALSE(pool.isLent(slot));
    EXPECT_EQ(pool.lent(), 0);
}

TEST(FramePoolTest, framesHavePlanesAtOnceByDefault)
{
    FramePool pool;
    ASSERT_TRUE(pool.allocate(1, hal::PixelFormat::Nv12, 4, 2));
    std::uint32_t slot = 0;
    hal::Frame *f = pool.acquire(slot);
    ASSERT_NE(f, nullptr);
    EXPECT_FALSE(f->image.empty());
    EXPECT_EQ(f->image.planes[1].strideBytes, 4);
    pool.abandon(slot);
}

/// GIVEN a pool of 8 frames of 3840 x 2160 Gray16 (16.6 MB each) with pixels now WHEN it is made
/// THEN less than two frames become resident; a frame written, released and written again takes
/// the same slot: about one frame resident (the decoder's pool follows the frames lent at once).
TEST(FramePoolTest, aFrameBecomesResidentOnlyWhenWritten)
{
    constexpr int kW = 3840;
    constexpr int kH = 2160;
    constexpr long long kFrame = 2LL * kW * kH;
    const long long before = testing::residentBytes();
    FramePool pool;
    ASSERT_TRUE(pool.allocate(8, hal::PixelFormat::Gray16, kW, kH));
    const long long allocated = testing::residentBytes();
    EXPECT_LT(allocated - before, 2 * kFrame) << "allocate() touched the frames' pixels";
    for (int i = 0; i < 3; ++i) {
        std::uint32_t slot = 99;
        hal::Frame *f = pool.acquire(slot);
        ASSERT_NE(f, nullptr);
        std::memset(f->image.row(0, 0), 0x5a, static_cast<std::size_t>(kFrame));
        pool.releaseFrame(slot);
    }
    const long long written = testing::residentBytes();
    EXPECT_GT(written - allocated, kFrame * 9 / 10);
    EXPECT_LT(written - allocated, 2 * kFrame);
}

} // namespace
} // namespace depthtouch::drivers
