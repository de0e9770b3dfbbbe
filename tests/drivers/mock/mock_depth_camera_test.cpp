#include "depthtouch/drivers/mock/mock_depth_camera.h"

#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "mock_test_util.h"

namespace depthtouch::drivers {
namespace {

using std::chrono::milliseconds;
using testing::errcOf;

hal::CameraConfig qqvga(hal::PixelFormat depth = hal::PixelFormat::Z16)
{
    hal::CameraConfig c;
    c.width = 160;
    c.height = 120;
    c.fps = 30.0;
    c.depthFormat = depth;
    return c;
}

std::uint16_t sample(const hal::ImageView &img, int x, int y)
{
    std::uint16_t v = 0;
    std::memcpy(&v, img.row(0, y) + 2 * x, sizeof(v));
    return v;
}

class MockDepthCameraTest : public ::testing::Test {
protected:
    void start(const hal::CameraConfig &cfg)
    {
        ASSERT_TRUE(camera_.configure(cfg));
        ASSERT_TRUE(camera_.start());
    }
    hal::Deadline soon() const { return clock_.now() + std::chrono::seconds(1); }

    /// Captures the next frame and checks its sequence number and the frames dropped so far.
    void expectNextFrame(std::uint64_t sequence, std::uint64_t dropped)
    {
        auto c = camera_.capture(soon());
        ASSERT_TRUE(c);
        EXPECT_EQ(c->depth->sequence, sequence);
        EXPECT_EQ(camera_.framesDropped(), dropped);
    }

    platform::ManualClock clock_;
    MockDepthCamera camera_{clock_};
};

TEST_F(MockDepthCameraTest, framesArePacedAtTheFrameRate)
{
    start(qqvga());
    const platform::TimePoint t0 = clock_.now();
    for (std::uint64_t k = 0; k < 4; ++k) {
        auto c = camera_.capture(soon());
        ASSERT_TRUE(c);
        EXPECT_EQ(c->depth->sequence, k);
        EXPECT_EQ(c->depth->time, t0 + platform::fromSeconds(static_cast<double>(k) / 30.0));
        EXPECT_EQ(c->depth->pts, c->depth->time - t0);
        EXPECT_EQ(clock_.now(), c->depth->time);
    }
    EXPECT_EQ(camera_.framesDropped(), 0u);
}

TEST_F(MockDepthCameraTest, depthShowsTheSphereInFrontOfTheWall)
{
    start(qqvga());
    auto c = camera_.capture(soon());
    ASSERT_TRUE(c);
    const hal::ImageView &d = c->depth->image;
    const hal::CameraIntrinsics k = camera_.intrinsics();
    // The pixel through the sphere centre sees its front surface.
    const hal::Vec3 centre = mockSphereCentre(0.0);
    const int u = static_cast<int>(std::lround(k.cx + k.fx * centre.x / centre.z));
    const int v = static_cast<int>(std::lround(k.cy + k.fy * centre.y / centre.z));
    const double expected = (hal::norm(centre) - kMockSphereRadius) * centre.z / hal::norm(centre);
    EXPECT_NEAR(sample(d, u, v), expected * 1000.0, 3.0);
    // A corner sees the wall.
    EXPECT_EQ(sample(d, 0, 0), 1200);
    EXPECT_EQ(sample(d, 159, 119), 1200);
    // Some wall pixels next to the sphere are shadowed (no measurement).
    int holes = 0;
    for (int y = 0; y < d.height; ++y)
        for (int x = 0; x < d.width; ++x)
            holes += sample(d, x, y) == 0 ? 1 : 0;
    EXPECT_GT(holes, 0);
    EXPECT_LT(holes, d.width * d.height / 20);
    // Color: the sphere is red, the wall gray.
    const std::uint8_t *sphere = c->color->image.row(0, v) + 3 * u;
    EXPECT_GT(sphere[0], 2 * sphere[1]);
    const std::uint8_t *wall = c->color->image.row(0, 0);
    EXPECT_EQ(wall[0], wall[1]);
}

TEST_F(MockDepthCameraTest, sphereMovesOverTime)
{
    start(qqvga());
    auto first = camera_.capture(soon());
    clock_.advance(milliseconds(500)); // a quarter of the motion period
    auto later = camera_.capture(soon());
    ASSERT_TRUE(first);
    ASSERT_TRUE(later);
    int differing = 0;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x)
            differing +=
                sample(first->depth->image, x, y) != sample(later->depth->image, x, y) ? 1 : 0;
    EXPECT_GT(differing, 500);
}

TEST_F(MockDepthCameraTest, nearnessFollowsTheInverseDepthMapping)
{
    hal::CameraConfig cfg = qqvga(hal::PixelFormat::Gray16);
    cfg.nearMetres = 0.5;
    cfg.farMetres = 2.0;
    start(cfg);
    auto c = camera_.capture(soon());
    ASSERT_TRUE(c);
    const double expected = 65535.0 * (1.0 / 1.2 - 1.0 / 2.0) / (1.0 / 0.5 - 1.0 / 2.0);
    EXPECT_EQ(sample(c->depth->image, 0, 0), std::lround(expected));
    cfg.nearMetres = 3.0;
    ASSERT_TRUE(camera_.stop());
    *c = hal::Capture{};
    EXPECT_EQ(errcOf(camera_.configure(cfg)), Errc::InvalidArgument);
}

TEST_F(MockDepthCameraTest, lateConsumerGetsTheNewestFrame)
{
    start(qqvga());
    ASSERT_TRUE(camera_.capture(soon()));
    clock_.advance(milliseconds(110)); // frames 1, 2, 3 exposed
    expectNextFrame(3, 2);
}

TEST_F(MockDepthCameraTest, droppedFramesLeaveASequenceGap)
{
    start(qqvga());
    ASSERT_TRUE(camera_.capture(soon()));
    camera_.dropFrames(2);
    expectNextFrame(3, 2);
}

TEST_F(MockDepthCameraTest, unplugAndReplug)
{
    start(qqvga());
    camera_.unplug();
    EXPECT_EQ(errcOf(camera_.capture(soon())), Errc::NoDevice);
    ASSERT_TRUE(camera_.stop());
    EXPECT_EQ(errcOf(camera_.configure(qqvga())), Errc::NoDevice);
    camera_.replug();
    ASSERT_TRUE(camera_.start());
    EXPECT_TRUE(camera_.capture(soon()));
}

TEST_F(MockDepthCameraTest, colorOnlyAndDepthOnly)
{
    hal::CameraConfig cfg = qqvga();
    cfg.depth = false;
    start(cfg);
    auto c = camera_.capture(soon());
    ASSERT_TRUE(c);
    EXPECT_FALSE(c->depth);
    EXPECT_TRUE(c->color);
    ASSERT_TRUE(camera_.stop());
    *c = hal::Capture{};
    cfg = qqvga();
    cfg.color = false;
    start(cfg);
    c = camera_.capture(soon());
    ASSERT_TRUE(c);
    EXPECT_TRUE(c->depth);
    EXPECT_FALSE(c->color);
}

} // namespace
} // namespace depthtouch::drivers
