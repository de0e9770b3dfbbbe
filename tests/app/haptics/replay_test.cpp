#include "depthtouch/haptics/replay.h"

#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "app/haptics/synthetic.h"

namespace depthtouch::haptics {
namespace {

TEST(TrajectoryCsvTest, parsesColumnsInAnyOrderWithExtras)
{
    std::size_t line = 99;
    const auto r = parseTrajectoryCsv("z, t,x,y,note\n0.01,0,0.001,0.002,a\r\n0.0,0.5,0.002,0.002,b\n\n",
                                      &line);
    ASSERT_TRUE(r) << r.error().what;
    EXPECT_EQ(line, 0u);
    ASSERT_EQ(r->size(), 2u);
    EXPECT_DOUBLE_EQ((*r)[1].t, 0.5);
    EXPECT_DOUBLE_EQ((*r)[0].z, 0.01);
    const TrajectorySample mid = sampleTrajectory(*r, 0.25);
    EXPECT_DOUBLE_EQ(mid.x, 0.0015);
    EXPECT_DOUBLE_EQ(mid.z, 0.005);
    EXPECT_DOUBLE_EQ(sampleTrajectory(*r, 7.0).x, 0.002);
}

TEST(TrajectoryCsvTest, rejectsBadInputWithTheLine)
{
    struct Case {
        const char *text;
        std::size_t line;
    } cases[] = {
        {"t,x,y\n0,0,0\n", 1},                  // missing column
        {"t,x,y,z\n0,0,0,0\n0,1,1,1\n", 3},     // time not increasing
        {"t,x,y,z\n0,0,0,0\n0.1,nan,0,0\n", 3}, // NaN
        {"t,x,y,z\n0,0,0\n", 2},                // missing field
        {"t,x,y,z\n0,0,0,0x\n", 2},             // trailing garbage
        {"t,x,y,z\n", 1},                       // no rows
        {"", 0},                                // empty
    };
    for (const Case &c : cases) {
        std::size_t line = 0;
        const auto r = parseTrajectoryCsv(c.text, &line);
        ASSERT_FALSE(r) << c.text;
        EXPECT_EQ(r.error().code, Errc::InvalidArgument);
        if (c.line > 1) {
            EXPECT_EQ(line, c.line) << c.text;
        }
    }
}

std::vector<std::uint8_t> rawVideo(int w, int h, int frames)
{
    // 16-bit frames: a plane rising 1 mm per frame
    std::vector<std::uint8_t> bytes;
    const SceneBox box{};
    for (int i = 0; i < frames; ++i) {
        const auto f = test::makeFrame(box, w, h, 0.0, [i](double, double) { return -0.01 + 0.001 * i; });
        const DepthFrameView v = f.view();
        bytes.insert(bytes.end(), v.data, v.data + v.strideBytes * static_cast<std::size_t>(h));
    }
    return bytes;
}

TEST(ReplayTest, replaysDeterministicallyAtTheHapticRate)
{
    // GIVEN 10 frames at 30 fps and a trajectory pressing 3 mm into the first frame's surface
    auto traj = parseTrajectoryCsv("t,x,y,z\n0,0.001,0.002,0.0\n0.05,0.001,0.002,-0.013\n0.2,0.004,0.002,-0.013\n");
    ASSERT_TRUE(traj);
    ReplayOptions opt;
    RawVideoFrameProvider a(rawVideo(32, 24, 10), 32, 24, SampleFormat::Gray16, 30.0);
    RawVideoFrameProvider b(rawVideo(32, 24, 10), 32, 24, SampleFormat::Gray16, 30.0);
    ASSERT_TRUE(a.validate());
    const auto r1 = replay(a, *traj, opt);
    const auto r2 = replay(b, *traj, opt);
    ASSERT_TRUE(r1 && r2);
    // THEN one row per 1 ms from 0 to 0.2 s, identical text for identical inputs
    EXPECT_EQ(r1->size(), 201u);
    const std::string log = formatForceLog(*r1);
    EXPECT_EQ(log, formatForceLog(*r2));
    EXPECT_EQ(log.substr(0, log.find('\n')),
              "t,hip_x,hip_y,hip_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,contact,released");
    // AND the force follows the rising surface: k·(surface − HIP) at t = 0.1 s (frame 3 + 0.0 → 3 mm
    // rise interpolated), HIP at −13 mm
    const ForceLogRow &row = (*r1)[100];
    EXPECT_DOUBLE_EQ(row.t, 0.1);
    EXPECT_TRUE(row.out.contact);
    const double surface = -0.01 + 0.001 * 3.0;
    EXPECT_NEAR(row.out.force.z, 800.0 * (surface + 0.013), 800.0 * 2e-6);
}

TEST(ReplayTest, rejectsBadOptionsAndVideos)
{
    auto traj = parseTrajectoryCsv("t,x,y,z\n0,0,0,0\n0.01,0,0,0\n");
    ASSERT_TRUE(traj);
    RawVideoFrameProvider ok(rawVideo(8, 8, 2), 8, 8, SampleFormat::Gray16, 30.0);
    ReplayOptions opt;
    opt.rate = -1.0;
    EXPECT_FALSE(replay(ok, *traj, opt));
    opt.rate = 1000.0;
    opt.config.stiffness = 0.0;
    EXPECT_FALSE(replay(ok, *traj, opt));
    RawVideoFrameProvider truncated(std::vector<std::uint8_t>(8 * 8 * 2 + 3), 8, 8, SampleFormat::Gray16, 30.0);
    EXPECT_FALSE(truncated.validate());
    EXPECT_FALSE(replay(truncated, *traj, ReplayOptions{}));
}

} // namespace
} // namespace depthtouch::haptics
