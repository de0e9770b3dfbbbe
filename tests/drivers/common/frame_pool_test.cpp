/// \file
/// \brief FramePool: pixels allocated now or on demand (dma-buf backends), slot state.

#include "depthtouch/drivers/common/frame_pool.h"

#include <gtest/gtest.h>

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

} // namespace
} // namespace depthtouch::drivers
