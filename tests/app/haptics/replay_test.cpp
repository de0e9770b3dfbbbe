#include "depthtouch/haptics/replay.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <cstring>

#include <gtest/gtest.h>

#include "app/haptics/synthetic.h"

namespace depthtouch::haptics {
namespace {

TEST(TrajectoryCsvTest, parsesColumnsInAnyOrderWithExtras)
{
    std::size_t line = 99;
    const auto r = parseTrajectoryCsv(
        "z, t,x,y,note\n0.01,0,0.001,0.002,a\r\n0.0,0.5,0.002,0.002,b\n\n", &line);
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
        const auto f =
            test::makeFrame(box, w, h, 0.0, [i](double, double) { return -0.01 + 0.001 * i; });
        const DepthFrameView v = f.view();
        bytes.insert(bytes.end(), v.data, v.data + v.strideBytes * static_cast<std::size_t>(h));
    }
    return bytes;
}

TEST(ReplayTest, replaysDeterministicallyAtTheHapticRate)
{
    // GIVEN 10 frames at 30 fps and a trajectory pressing 3 mm into the first frame's surface
    auto traj = parseTrajectoryCsv(
        "t,x,y,z\n0,0.001,0.002,0.0\n0.05,0.001,0.002,-0.013\n0.2,0.004,0.002,-0.013\n");
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
    // AND the force follows the rising surface: k·(surface − HIP) at t = 0.1 s (frame 3 + 0.0 → 3
    // mm rise interpolated), HIP at −13 mm
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
    RawVideoFrameProvider truncated(std::vector<std::uint8_t>(8 * 8 * 2 + 3), 8, 8,
                                    SampleFormat::Gray16, 30.0);
    EXPECT_FALSE(truncated.validate());
    EXPECT_FALSE(replay(truncated, *traj, ReplayOptions{}));
}

TEST(TrajectoryCsvTest, rejectsPositionsAndTimesBeyondTheLimits)
{
    // GIVEN rows with a coordinate of 1.7e308 m, a time of 1e300 s or 1e9 s (once: NaN forces,
    // a one-row log, std::bad_alloc)
    const char *cases[] = {
        "t,x,y,z\n0,0,0,0\n0.1,1.7e308,0,0\n",
        "t,x,y,z\n0,0,0,0\n0.1,0,0,-1.7e308\n",
        "t,x,y,z\n0,0,0,0\n0.1,0,100.5,0\n",
        "t,x,y,z\n0,0,0,0\n1e300,0,0,0\n",
        "t,x,y,z\n0,0,0,0\n1e9,0,0,0\n",
    };
    for (const char *text : cases) {
        std::size_t line = 0;
        const auto r = parseTrajectoryCsv(text, &line);
        // THEN each is refused at its line
        ASSERT_FALSE(r) << text;
        EXPECT_EQ(line, 3u) << text;
    }
    // AND the limits themselves are accepted
    EXPECT_TRUE(parseTrajectoryCsv("t,x,y,z\n0,-100,100,-100\n1e6,0,0,0\n"));
}

TEST(ReplayTest, refusesATrajectoryTooLongForTheUpdateLimitOrEndingBeforeZero)
{
    RawVideoFrameProvider frames(rawVideo(8, 8, 2), 8, 8, SampleFormat::Gray16, 30.0);
    ReplayOptions opt;
    // GIVEN 100000 s at 1 kHz (1e8 updates) and the same at 10 kHz for 100.1 s
    auto longTraj = parseTrajectoryCsv("t,x,y,z\n0,0,0,0\n100000,0,0,0\n");
    ASSERT_TRUE(longTraj);
    auto r = replay(frames, *longTraj, opt);
    ASSERT_FALSE(r);
    EXPECT_NE(std::string(r.error().what).find("too long"), std::string::npos);
    opt.rate = 10'000.0;
    auto justOver = parseTrajectoryCsv("t,x,y,z\n0,0,0,0\n100.1,0,0,0\n");
    ASSERT_TRUE(justOver);
    EXPECT_FALSE(replay(frames, *justOver, opt));
    // AND a trajectory ending before t = 0 has nothing to replay
    opt.rate = 1000.0;
    auto negative = parseTrajectoryCsv("t,x,y,z\n-2,0,0,0\n-1,0,0,0\n");
    ASSERT_TRUE(negative);
    EXPECT_FALSE(replay(frames, *negative, opt));
}

TEST(ReplayTest, optionsOutsideTheirRangesAreRefused)
{
    const auto bad = [](auto change) {
        ReplayOptions o;
        change(o);
        return !validateReplayOptions(o);
    };
    EXPECT_FALSE(bad([](ReplayOptions &) {}));
    EXPECT_TRUE(bad([](ReplayOptions &o) { o.rate = 1e9; }));
    EXPECT_TRUE(bad([](ReplayOptions &o) { o.rate = 99.0; }));
    EXPECT_TRUE(bad([](ReplayOptions &o) { o.rate = std::nan(""); }));
    EXPECT_TRUE(bad([](ReplayOptions &o) { o.config.stiffness = 1e308; }));
    // the stiffness's one range (scene/stiffness.h), its ends included
    EXPECT_FALSE(bad([](ReplayOptions &o) { o.config.stiffness = 100.0; }));
    EXPECT_FALSE(bad([](ReplayOptions &o) { o.config.stiffness = 3000.0; }));
    EXPECT_TRUE(bad([](ReplayOptions &o) { o.config.stiffness = 99.5; }));
    EXPECT_TRUE(bad([](ReplayOptions &o) { o.config.stiffness = 3000.5; }));
    EXPECT_TRUE(bad([](ReplayOptions &o) { o.config.damping = 1e308; }));
    EXPECT_TRUE(bad([](ReplayOptions &o) { o.config.maxForce = 1e308; }));
    EXPECT_TRUE(bad([](ReplayOptions &o) { o.config.box.width = 1e300; }));
    EXPECT_TRUE(bad([](ReplayOptions &o) { o.config.maxForceStep = 1e300; }));
    EXPECT_TRUE(bad([](ReplayOptions &o) { o.config.rampTime = 1e300; }));
    EXPECT_TRUE(bad([](ReplayOptions &o) { o.config.fingerRadius = 1.0; }));
}

TEST(ReplayTest, forcesAreFiniteAndWithinTheMaximumAtTheExtremesOfEveryRange)
{
    // GIVEN the stiffest, most damped settings allowed, safety off, and a HIP swinging between the
    // position limits (once: NaN forces with exit 0)
    auto traj = parseTrajectoryCsv("t,x,y,z\n0,0,0,-0.01\n0.01,100,-100,-100\n0.02,-100,100,100\n"
                                   "0.03,0.001,0.001,-100\n0.05,0.001,0.001,-0.02\n");
    ASSERT_TRUE(traj);
    for (const Method m : {Method::Finger, Method::Modified, Method::ProxyGraph, Method::MeshBvh}) {
        for (const bool safety : {false, true}) {
            ReplayOptions opt;
            opt.method = m;
            opt.rate = ReplayLimits::kMaxRate;
            opt.config = RendererConfig::forMethod(m);
            opt.config.safety = safety;
            opt.config.stiffness = scene::kMaxStiffness;
            opt.config.damping = ReplayLimits::kMaxDamping;
            RawVideoFrameProvider frames(rawVideo(16, 12, 3), 16, 12, SampleFormat::Gray16, 30.0);
            const auto rows = replay(frames, *traj, opt);
            ASSERT_TRUE(rows) << rows.error().what;
            ASSERT_EQ(rows->size(), 501u);
            // THEN every force is finite and within the device maximum
            for (const ForceLogRow &r : *rows) {
                const glm::dvec3 &f = r.out.force;
                ASSERT_TRUE(std::isfinite(f.x) && std::isfinite(f.y) && std::isfinite(f.z))
                    << methodName(m) << " t=" << r.t;
                EXPECT_LE(glm::length(f), opt.config.maxForce * (1.0 + 1e-9)) << methodName(m);
                ASSERT_TRUE(std::isfinite(r.out.proxy.x) && std::isfinite(r.out.proxy.y) &&
                            std::isfinite(r.out.proxy.z))
                    << methodName(m) << " t=" << r.t;
            }
        }
    }
}

TEST(ForceLogTest, rowsAreWholeWhateverTheMagnitudes)
{
    // GIVEN rows holding -1e300 (each printed as over 300 digits by %f)
    std::vector<ForceLogRow> rows(500);
    for (ForceLogRow &r : rows)
        r.out.hip = r.out.proxy = r.out.force = glm::dvec3(-1e300);
    // WHEN formatted
    const std::string csv = formatForceLog(rows);
    // THEN there are 501 lines, each with 12 fields (once: rows were cut at 319 characters)
    std::size_t lines = 0;
    std::size_t start = 0;
    for (std::size_t nl = csv.find('\n'); nl != std::string::npos; nl = csv.find('\n', start)) {
        const std::string line = csv.substr(start, nl - start);
        EXPECT_EQ(std::count(line.begin(), line.end(), ','), 11) << lines;
        start = nl + 1;
        ++lines;
    }
    EXPECT_EQ(lines, 501u);
    EXPECT_EQ(start, csv.size());
}

} // namespace
} // namespace depthtouch::haptics
