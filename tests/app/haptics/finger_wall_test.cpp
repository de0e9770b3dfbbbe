/// \file
/// \brief The fingertip renderer's wall contact (finger_wall.cpp): a free finger that moves into
/// an object's silhouette from the side meets the object's side, and its force turns over the
/// object's upper edge without a step. Before, a finger that came under an object's top deeper
/// than the capture depth was *behind* the surface and free: it fell into the object with no
/// force until it rose above the top (the swipes of `bench feel` across silhouettes: up to 64 ms
/// of pop-through a stroke). Depth is 8-bit at 30 fps, a still table with a box on it.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "app/haptics/finger_press.h"
#include "app/haptics/synthetic.h"
#include "app/haptics/video.h"
#include "depthtouch/haptics/finger_renderer.h"

namespace depthtouch::haptics {
namespace {

using test::SyntheticVideo;

constexpr SceneBox kBox{};
constexpr double kTable = -0.005;    ///< m
constexpr double kTop = 0.010;       ///< the box's top, m; its side at x = 0
constexpr double kStiffness = 800.0; ///< N/m, the default config's

/// A table at kTable and a box up to kTop for x ≥ \a side(frame) (m; its side a tanh 0.2 mm
/// wide), 8-bit.
SyntheticVideo tableAndBox(const std::function<double(int)> &side = [](int) { return 0.0; })
{
    return SyntheticVideo(
        kBox, 320, 240, 30.0,
        [side](double x, double, int frame) {
            return kTable + (kTop - kTable) * 0.5 * (1.0 + std::tanh((x - side(frame)) / 0.0002));
        },
        SampleFormat::Gray8);
}

struct StrokeLog {
    std::vector<glm::dvec3> hip;
    std::vector<HapticOutput> out;
};

/// A new finger (the default config; with \a smoothOffset false, the force on the search's own
/// proxy) along \a hip(t), t from 0 to \a duration at 1 kHz, on \a video.
StrokeLog stroke(const std::function<glm::dvec3(double)> &hip, double duration,
                 SyntheticVideo video = tableAndBox(), bool smoothOffset = true)
{
    RendererConfig config = RendererConfig::forMethod(Method::Finger);
    config.smoothOffset = smoothOffset;
    FingerRenderer finger(config);
    finger.reset(hip(0.0));
    StrokeLog run;
    const long n = std::lround(duration * 1000.0);
    for (long k = 0; k < n; ++k) {
        const double t = static_cast<double>(k) / 1000.0;
        if (video.advance(t))
            video.feed(finger);
        run.hip.push_back(hip(t));
        run.out.push_back(finger.update(run.hip.back(), t));
    }
    return run;
}

/// \return x (m) where the box's side, as the renderer sees it (8-bit, interpolated between
/// pixels), rises through height \a z (m): the wall a finger at that height meets.
double sideAt(double z)
{
    SyntheticVideo video = tableAndBox();
    video.advance(0.0);
    const HeightField &surface = video.reference(0.0);
    double out = -0.002;
    double in = 0.002;
    for (int i = 0; i < 40; ++i) {
        const double mid = 0.5 * (out + in);
        (surface.heightAt(mid, 0.0) < z ? out : in) = mid;
    }
    return out;
}

/// The HIP at height \a z (m), from x = −10 mm at 20 cm/s to \a stop (m), then held there.
std::function<glm::dvec3(double)> swipeTo(double z, double stop)
{
    return [=](double t) { return glm::dvec3(std::min(-0.010 + 0.2 * t, stop), 0.0, z); };
}

// A free finger 1 mm above the table swipes into the box's side, 14 mm under its top (deeper than
// a new contact may be caught), and stays at x = 3 mm. The side is a wall: the force points back
// out along −x, k times the depth past the side (where the 8-bit surface, interpolated between
// pixels, rises through the finger's height), and never down. Before: no force at all.
TEST(FingerWallTest, aFreeSwipeIntoAnObjectsSideMeetsItsWall)
{
    const double z = kTable + 0.001;
    const double side = sideAt(z);
    const StrokeLog run = stroke(swipeTo(z, 0.003), 0.1);
    int free = 0;
    for (std::size_t k = 0; k < run.out.size(); ++k) {
        const double past = run.hip[k].x - side; // m
        if (past <= 0.0001)
            continue;
        const glm::dvec3 &f = run.out[k].force;
        free += run.out[k].contact ? 0 : 1;
        EXPECT_LT(f.x, -0.5 * kStiffness * past) << "at x = " << run.hip[k].x;
        EXPECT_LE(std::fabs(f.y) + std::fabs(f.z), 0.1 * std::fabs(f.x) + 0.05)
            << "at x = " << run.hip[k].x;
    }
    const glm::dvec3 last = run.out.back().force;
    std::printf("free swipe into a 15 mm side (at x = %.2f mm), held 3 mm in: %d updates free past "
                "the side, force (%.2f, %.2f, %.2f) N\n",
                side * 1e3, free, last.x, last.y, last.z);
    EXPECT_EQ(free, 0);
    EXPECT_NEAR(last.x, -kStiffness * (0.003 - side), 0.02);
    EXPECT_FALSE(run.out.back().released);
}

/// A free finger 1 mm above a still 8-bit table (test::tableWithHoles()) from (-10, 1) mm toward
/// +x and -y (5:1) at 20 cm/s for 13 mm, then held: \return its log.
test::Log obliqueSwipe(const test::OwnedFrame &frame)
{
    FingerRenderer finger = test::makeFinger();
    const auto hip = [](double t) {
        const double s = std::min(0.2 * t, 0.013); // m along the path
        return glm::dvec3(-0.010 + s, 0.001 - 0.2 * s, -0.004);
    };
    finger.reset(hip(0.0));
    EXPECT_TRUE(finger.setFrames(frame.view(), nullptr));
    test::Log log;
    for (int k = 0; k < 100; ++k) {
        log.t.push_back(k / 1000.0);
        log.out.push_back(finger.update(hip(log.t.back()), log.t.back()));
    }
    return log;
}

// A stereo camera leaves a band of holes along an object's side (the backdrop its second view
// cannot see). A free finger 1 mm above the table swipes obliquely across such a band (x from
// -1 mm to the side) into a box 15 mm tall whose side is slanted (x >= 0.3 y). The side is the
// same wall as without the band: the finger is in contact on the same updates but the first two
// (the band's cliff, interpolated from a hole's vertex, rises through the finger's height a pixel
// later than the table's: 0.3 mm, 1.5 updates of the swipe), and its force points the same way
// (within 10 degrees) with the same magnitude (within 10 % and k times a pixel's diagonal).
// Before, the side's normal was read off the hole's own cliff (its vertices 1 m under the box):
// it pointed along the band, the force pushed the finger along the side (6.5 N sideways, at 47
// degrees to the wall's), and where the path leaned the other way the finger was taken as behind
// the box without force (bench feel's synthetic-occluder-stereo circles at 30 cm/s: 15 ms of
// pop-through).
TEST(FingerWallTest, aSideBehindABandOfHolesIsTheSameWall)
{
    const auto band = [](double x, double y) { return x >= -0.001 && x < 0.3 * y; };
    const auto box = [](double x, double y) { return x >= 0.3 * y ? 0.015 : 0.0; };
    const test::Log banded = obliqueSwipe(test::tableWithHoles(band, 24, box));
    const test::Log plain =
        obliqueSwipe(test::tableWithHoles([](double, double) { return false; }, 24, box));
    const double diagonal = std::sqrt(2.0) * kBox.width / test::kStillW; // a pixel's, m
    int contacts = 0;
    int late = 0;
    double worst = 0.0;
    for (std::size_t k = 0; k < plain.out.size(); ++k) {
        EXPECT_FALSE(banded.out[k].contact && !plain.out[k].contact) << "update " << k;
        late += plain.out[k].contact && !banded.out[k].contact ? 1 : 0;
        const glm::dvec3 a = banded.out[k].force;
        const glm::dvec3 b = plain.out[k].force;
        if (!plain.out[k].contact || glm::length(b) < 0.5)
            continue;
        ++contacts;
        const double angle = std::acos(
            std::clamp(glm::dot(a, b) / (glm::length(a) * glm::length(b) + 1e-12), -1.0, 1.0));
        worst = std::max(worst, angle);
        EXPECT_LT(angle, 10.0 * M_PI / 180.0) << "update " << k;
        EXPECT_NEAR(glm::length(a), glm::length(b), 0.1 * glm::length(b) + kStiffness * diagonal)
            << "update " << k;
    }
    const glm::dvec3 a = banded.out.back().force;
    const glm::dvec3 b = plain.out.back().force;
    std::printf("oblique swipe across a band of holes into a slanted side: %d updates compared, "
                "%d late, worst angle %.1f deg; held: (%.2f, %.2f, %.2f) N, without the band "
                "(%.2f, %.2f, %.2f) N\n",
                contacts, late, worst * 180.0 / M_PI, a.x, a.y, a.z, b.x, b.y, b.z);
    EXPECT_GT(contacts, 20);
    EXPECT_LE(late, 2);
    EXPECT_LT(b.x, 0.0); // the wall's own force points out of the box
}

// A free finger 2 mm under the box's top swipes across its upper edge onto it. The force turns from
// the side (−x) to the top (+z) over the rounded corner: no update past the side without contact,
// no step of the force over 0.5 N (the feel bench's spike), and on the top k times 2 mm up.
TEST(FingerWallTest, theForceTurnsOverAnObjectsUpperEdgeWithoutAStep)
{
    // Also unfiltered: the corner's own rounding, without the offset filter's bound on the force.
    for (const bool smooth : {true, false}) {
        const StrokeLog run = stroke(swipeTo(kTop - 0.002, 0.008), 0.12, tableAndBox(), smooth);
        double largest = 0.0;
        int free = 0;
        for (std::size_t k = 1; k < run.out.size(); ++k) {
            largest = std::max(largest, glm::length(run.out[k].force - run.out[k - 1].force));
            free += run.hip[k].x > 0.0005 && !run.out[k].contact ? 1 : 0;
        }
        const glm::dvec3 last = run.out.back().force;
        std::printf("free swipe 2 mm under a box's top across its edge: largest step %.2f N, %d "
                    "updates free past the side, force on the top (%.2f, %.2f, %.2f) N\n",
                    largest, free, last.x, last.y, last.z);
        EXPECT_EQ(free, 0) << smooth;
        EXPECT_LE(largest, 0.5) << smooth;
        EXPECT_NEAR(last.z, kStiffness * 0.002, 0.25) << smooth;
        EXPECT_LT(std::fabs(last.x), 0.1) << smooth;
    }
}

// The finger swipes into the box's side 1 mm above the table and stays 1 mm past it; from the
// third frame the box moves toward it at 30 cm/s (10 mm a frame: between two frames the side's
// heights blend, and the wall found along its normal jumps 10 mm in one update). The wall pushes
// the held finger out at a bounded rate: the force grows by at most maxForceStep / 16 an update
// (the bounded push, finger_renderer.h: 0.125 N at the defaults), always back out along −x,
// until the device maximum lets the finger go. Without the bound: a step of several newtons.
TEST(FingerWallTest, aSideThatSweepsOntoAHeldFingerPushesItOutAtABoundedRate)
{
    const RendererConfig config = RendererConfig::forMethod(Method::Finger);
    const double z = kTable + 0.001;
    auto side = [](int frame) { return frame < 3 ? 0.0 : -0.010 * (frame - 3); };
    const StrokeLog run = stroke(swipeTo(z, 0.001), 0.25, tableAndBox(side));
    double largest = 0.0; // the largest growth of |F| in one update while held, N
    double most = 0.0;
    bool letGo = false;
    for (std::size_t k = 100; k < run.out.size() && !letGo; ++k) {
        const glm::dvec3 &f = run.out[k].force;
        letGo = run.out[k].released;
        if (letGo)
            break;
        largest = std::max(largest, glm::length(f) - glm::length(run.out[k - 1].force));
        most = std::max(most, glm::length(f));
        EXPECT_LT(f.x, 0.0) << "at t = " << k << " ms";
        EXPECT_LE(std::fabs(f.y) + std::fabs(f.z), 0.1 * std::fabs(f.x) + 0.05)
            << "at t = " << k << " ms";
    }
    std::printf("a side sweeping onto a held finger at 30 cm/s: largest growth %.3f N an update, "
                "up to %.2f N, let go: %s\n",
                largest, most, letGo ? "yes" : "no");
    EXPECT_LE(largest, config.maxForceStep / 16.0 + 0.01);
    EXPECT_GE(most, 0.99 * config.maxForce); // it did push, up to the device maximum
    EXPECT_TRUE(letGo);
}

// A finger held 1 mm past an object's ragged side (its edge juts out and back by 0.3 mm every
// millimetre along y, as an 8-bit silhouette's pixels do) slides along it at 50 cm/s. The side's
// depth grows by the HIP's motion into the side plus the bounded push, so where the side juts out
// the force grows by at most maxForceStep / 16 an update (0.125 N) and k times the slide's share
// into the side (its found normal is tilted 4 degrees: 0.03 mm of the 0.5 mm an update). Before,
// the depth could grow by the HIP's whole motion along the side: a 0.47 N step at each jut (the
// feel bench's swipes across silhouettes had their spikes there).
TEST(FingerWallTest, slidingAlongARaggedSideGrowsTheForceNoFasterThanTheBoundedPush)
{
    const RendererConfig config = RendererConfig::forMethod(Method::Finger);
    SyntheticVideo ragged(
        kBox, 320, 240, 30.0,
        [](double x, double y, int) {
            const double side = std::fmod(y + 1.0, 0.002) < 0.001 ? 0.0003 : -0.0003;
            return kTable + (kTop - kTable) * 0.5 * (1.0 + std::tanh((x - side) / 0.0002));
        },
        SampleFormat::Gray8);
    const double z = kTable + 0.001;
    const auto hip = [z](double t) {
        const glm::dvec3 in = swipeTo(z, 0.001)(t);
        return in + glm::dvec3(0.0, 0.5 * std::max(0.0, t - 0.1), 0.0);
    };
    const StrokeLog run = stroke(hip, 0.14, ragged, false); // the search's own proxy
    double largest = 0.0; // the largest growth of |F| in one update while sliding, N
    for (std::size_t k = 101; k < run.out.size(); ++k) {
        ASSERT_TRUE(run.out[k].contact) << "at t = " << k << " ms";
        EXPECT_LT(run.out[k].force.x, 0.0) << "at t = " << k << " ms"; // back out of the side
        largest =
            std::max(largest, glm::length(run.out[k].force) - glm::length(run.out[k - 1].force));
    }
    std::printf("sliding along a ragged side at 50 cm/s: largest growth %.3f N an update\n",
                largest);
    EXPECT_LE(largest, config.maxForceStep / 16.0 + kStiffness * 0.1 * 0.0005);
    EXPECT_GT(largest, 0.5 * config.maxForceStep / 16.0); // the juts did push
}

// A slot one sample wide (0.16 mm) cut down to the table into a box 15 mm tall, 1 mm in from its
// side: a point lowered into it is free there, 5 mm under the box's top; a fingertip (r = 1.5 mm)
// could not be, it was on the box either side. Moved on into the box at 50 cm/s, it meets the
// slot's far side: no wall, for the fingertip does not fit in front of it (roomBefore()), and it
// is caught though deeper than the capture depth (4 mm): touching, its force growing at the
// bounded push's rate. Before, it was on a wall (with the room check alone, behind the surface
// with no force: `bench feel`'s finger-r1mm had 14 ms of pop-through on a time-of-flight
// occluder's notched edge).
TEST(FingerWallTest, aFingerOutOfASlotNarrowerThanItIsOnTheSurfaceEitherSide)
{
    const double sample = kBox.width / 639.0;
    const double slot = 0.001 + 0.5 * sample; // a sample's x: (c − 319.5)·sample
    SyntheticVideo video(kBox, 640, 480, 30.0, [=](double x, double, int) {
        return x >= 0.0 && std::fabs(x - slot) > 0.5 * sample ? kTop : kTable;
    });
    FingerRenderer finger(RendererConfig::forMethod(Method::Finger));
    video.advance(0.0);
    video.feed(finger);
    const glm::dvec3 above{slot, 0.0, kTop + 0.003};
    finger.reset(above);
    finger.update(above, 0.0);
    const glm::dvec3 inSlot{slot, 0.0, kTop - 0.005};
    EXPECT_FALSE(finger.update(inSlot, 0.001).contact); // free in the slot, as a point
    glm::dvec3 force{};
    for (int k = 1; k <= 10; ++k) {
        force = finger.update(inSlot + glm::dvec3(0.0005 * k, 0.0, 0.0), 0.001 + k / 1000.0).force;
        EXPECT_EQ(finger.state(), FingerState::Touching) << "update " << k;
    }
    std::printf("10 updates out of the slot, 5 mm under the top: force (%.2f, %.2f, %.2f) N\n",
                force.x, force.y, force.z);
    EXPECT_GT(force.z, 0.5);
    EXPECT_GT(force.z, std::fabs(force.x));
}

} // namespace
} // namespace depthtouch::haptics
