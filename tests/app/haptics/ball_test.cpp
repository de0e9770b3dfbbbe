/// \file
/// \brief The ball fingertip (ball_surface.h, ball_renderer.h): the swept surface against the
/// geometry of a ball on a plane, a slope, a groove, a hole and a step; the renderer's force
/// against the spring law on a table, against a wall met from the side, across a groove narrower
/// than the finger, at a cut and for a HIP that is not a number.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "app/haptics/finger_press.h"
#include "app/haptics/synthetic.h"
#include "app/haptics/video.h"
#include "depthtouch/haptics/ball_renderer.h"
#include "depthtouch/haptics/ball_surface.h"
#include "depthtouch/haptics/renderer_table.h"

namespace depthtouch::haptics {
namespace {

using test::OwnedFrame;
using test::SyntheticVideo;

constexpr SceneBox kBox{};
constexpr int kW = 320;
constexpr int kH = 240;
constexpr double kTable = -0.005; ///< m
constexpr double kR = 0.0015;     ///< the default fingertip radius in the default box, m

/// A 16-bit still frame of \a z(x, y) (m) in the default box.
OwnedFrame still(const std::function<double(double, double)> &z)
{
    return test::makeFrame(kBox, kW, kH, 0.0, z);
}

/// \return the swept surface of \a frame at (\a x, \a y) for a ball of radius kR.
BallPoint sweptAt(const OwnedFrame &frame, double x, double y)
{
    HeightField field(kBox);
    EXPECT_TRUE(field.setFrames(frame.view(), nullptr));
    field.setTime(0.0, true);
    return BallSurface(kR).at(field, x, y);
}

TEST(BallSurfaceTest, onAPlaneItIsThePlaneWithANormalUp)
{
    const BallPoint b = sweptAt(still([](double, double) { return kTable; }), 0.001, -0.002);
    EXPECT_NEAR(b.height, kTable, 2e-6); // 16-bit quantisation of a 0.1 m box: 1.5 µm
    EXPECT_NEAR(b.normal.z, 1.0, 1e-9);
}

// A ball on a slope θ rests r(1/cos θ − 1) above it, its normal the slope's: S is the plane lifted
// by a constant, whatever the taps' pattern, so both hold to the 16-bit quantisation (the normal
// to 0.2°; averaged over the taps' contacts it leant toward +z by half the slope's angle).
TEST(BallSurfaceTest, onASlopeItRestsAboveItAndTiltsWithIt)
{
    for (const double degrees : {10.0, 25.0, 40.0}) {
        const double slope = std::tan(degrees * std::numbers::pi / 180.0);
        const BallPoint b =
            sweptAt(still([slope](double x, double) { return kTable + slope * x; }), 0.002, 0.0);
        const double plane = kTable + slope * 0.002;
        const double lift = kR * (1.0 / std::cos(degrees * std::numbers::pi / 180.0) - 1.0);
        EXPECT_NEAR(b.height - plane, lift, 5e-6) << degrees << "°";
        const glm::dvec3 n = glm::normalize(glm::dvec3(-slope, 0.0, 1.0));
        EXPECT_GT(glm::dot(b.normal, n), std::cos(0.2 * std::numbers::pi / 180.0))
            << degrees << "°";
    }
}

// A groove w = 2 mm wide and 3 mm deep, narrower than the ball (3 mm across): the ball bridges it.
// Exactly it would sink r − √(r² − w²/4) = 0.38 mm; the surface is linear between taps r/2 apart,
// so a rim between two is met lower down its wall: the ball never sinks less than exactly, and
// stays in the groove's upper half, not on its floor 3 mm down.
TEST(BallSurfaceTest, aGrooveNarrowerThanTheBallIsBridged)
{
    const double w = 0.002;
    const BallPoint b = sweptAt(
        still([w](double x, double) { return std::fabs(x) < 0.5 * w ? kTable - 0.003 : kTable; }),
        0.0, 0.0);
    const double sink = kR - std::sqrt(kR * kR - 0.25 * w * w);
    std::printf("a ball of r = 1.5 mm over a 2 mm groove sinks %.2f mm (exactly %.2f mm)\n",
                (kTable - b.height) * 1e3, sink * 1e3);
    EXPECT_LE(b.height, kTable - sink + 2e-6);
    EXPECT_GT(b.height, kTable - 0.0015);
    EXPECT_NEAR(b.normal.z, 1.0, 0.05); // resting on both rims, straight up
}

TEST(BallSurfaceTest, holesHoldNothingAndASmallOneIsCoveredByItsRim)
{
    // Holes (code 0 under the threshold 24, test::tableWithHoles()): a patch 1 mm across under
    // the ball's centre, and a frame of holes only.
    auto frame = [](double radius) {
        return test::tableWithHoles(
            [radius](double x, double y) { return std::hypot(x, y) < radius; }, 24);
    };
    const BallPoint small = sweptAt(frame(0.0005), 0.0, 0.0);
    EXPECT_NEAR(small.height, kTable, 0.0006); // 8-bit: 0.4 mm a step
    EXPECT_TRUE(small.measured());
    const BallPoint none = sweptAt(frame(1.0), 0.0, 0.0);
    EXPECT_FALSE(none.measured());
    EXPECT_TRUE(std::isnan(none.height));
}

// A step 10 mm tall at x = 0 (taller than r): the ball 2r in front is on the table; 0.5r in front
// it rests on the step's edge, higher than the table by more than r and under the top, its normal
// turned away from the step (−x).
TEST(BallSurfaceTest, aStepTallerThanTheBallIsAFaceInFrontOfIt)
{
    const OwnedFrame frame = still([](double x, double) { return x >= 0.0 ? 0.005 : kTable; });
    EXPECT_NEAR(sweptAt(frame, -2.0 * kR, 0.0).height, kTable, 2e-6);
    const BallPoint edge = sweptAt(frame, -0.5 * kR, 0.0);
    EXPECT_GT(edge.height, kTable + kR);
    EXPECT_LT(edge.height, 0.005);
    EXPECT_LT(edge.normal.x, -0.3);
}

/// A ball renderer (the default config, \a reengage) along \a hip(t) over \a video, 1 kHz.
struct BallRun {
    std::vector<glm::dvec3> hip;
    std::vector<HapticOutput> out;
    std::vector<FingerState> state;
};

BallRun stroke(SyntheticVideo video, const std::function<glm::dvec3(double)> &hip, double duration,
               Reengage reengage = Reengage::Release)
{
    RendererConfig config = RendererConfig::forMethod(Method::Ball);
    config.reengage = reengage;
    BallRenderer ball(config);
    ball.reset(hip(0.0));
    BallRun run;
    const long n = std::lround(duration * 1000.0);
    for (long k = 0; k < n; ++k) {
        const double t = static_cast<double>(k) / 1000.0;
        if (video.advance(t))
            video.feed(ball);
        run.hip.push_back(hip(t));
        run.out.push_back(ball.update(run.hip.back(), t));
        run.state.push_back(ball.state());
    }
    return run;
}

SyntheticVideo table(const std::function<double(double, double)> &z = nullptr)
{
    return SyntheticVideo(kBox, kW, kH, 30.0,
                          [z](double x, double y, int) { return z ? z(x, y) : kTable; });
}

// Pressed 2 mm into a table and held: the force is k·2 mm straight up (800 N/m: 1.6 N), in
// contact; lifted 1 mm above it, zero and free.
TEST(BallRendererTest, aPressIsTheSpringStraightUpAndALiftIsFree)
{
    const BallRun run = stroke(
        table(),
        [](double t) {
            const double z = t < 0.1   ? kTable + 0.001 - 0.03 * t
                             : t < 0.3 ? kTable - 0.002
                                       : kTable + 0.001;
            return glm::dvec3(0.001, 0.0, z);
        },
        0.35);
    const HapticOutput &held = run.out[250];
    EXPECT_TRUE(held.contact);
    EXPECT_EQ(run.state[250], FingerState::Touching);
    EXPECT_NEAR(held.force.z, 800.0 * 0.002, 0.01);
    EXPECT_NEAR(std::hypot(held.force.x, held.force.y), 0.0, 1e-3);
    EXPECT_FALSE(run.out.back().contact);
    EXPECT_EQ(run.state.back(), FingerState::Free);
    EXPECT_EQ(glm::length(run.out.back().force), 0.0);
}

// A ridge narrower than the fingertip (a cable: 0.8 r wide, 6 mm over the table) pressed 6 mm
// into at 5 cm/s and held: the ball rests on its top, so the force is the spring's to the ridge's
// top all the way in (k·6 mm, 4.8 N, when held) and never nothing while the finger is inside it.
// The finger renderer's plane, fitted across 2r, was the table's there and the force vanished for
// up to 320 ms of such presses, until the plane was kept on what was measured at its centre
// (finger_ridge_test.cpp; docs/benchmarks.md, "A scene with tops narrower than a fingertip").
TEST(BallRendererTest, aRidgeNarrowerThanTheFingerIsFeltAtItsTop)
{
    constexpr double kRidge = 0.006;
    const double half = 0.4 * kR;
    const auto ridge = [half](double x, double) {
        return kTable +
               kRidge * 0.5 * (std::tanh((x + half) / 2e-4) - std::tanh((x - half) / 2e-4));
    };
    const double top = kTable + kRidge;
    const BallRun run = stroke(
        table(ridge),
        [top](double t) { return glm::dvec3(0.0, 0.0, top + 0.003 - 0.05 * std::min(t, 0.18)); },
        0.4);
    int inside = 0;
    int felt = 0;
    for (std::size_t k = 0; k < run.out.size(); ++k)
        if (top - run.hip[k].z > 1e-3) {
            ++inside;
            felt += glm::length(run.out[k].force) >= 0.1 ? 1 : 0;
        }
    EXPECT_GT(inside, 200);
    EXPECT_EQ(felt, inside);
    EXPECT_NEAR(run.out.back().force.z, 800.0 * 0.006, 0.15);
    EXPECT_EQ(run.state.back(), FingerState::Touching);
}

// The frame is wider than tall (0.1 m × 0.075 m): pressed 2 mm at x = 45 mm, inside the frame but
// farther out than its half height, the finger is felt as at the centre (x and y are not swapped).
TEST(BallRendererTest, aPressNearTheFramesSideIsFeltAsAtItsCentre)
{
    for (const double x : {0.0, 0.045}) {
        const BallRun run = stroke(
            table(),
            [x](double t) {
                return glm::dvec3(x, 0.0, t < 0.1 ? kTable + 0.001 - 0.03 * t : kTable - 0.002);
            },
            0.3);
        EXPECT_TRUE(run.out.back().contact) << "x = " << x;
        EXPECT_NEAR(run.out.back().force.z, 800.0 * 0.002, 0.01) << "x = " << x;
    }
}

// A free finger 1 mm above the table swipes at 20 cm/s into a box's side 10 mm tall and stays 2 mm
// past where the face stands for the ball (r in front of the side): the force points back out,
// −x, with no rule for walls: the solve from the last proxy meets the face; and never down.
TEST(BallRendererTest, aSwipeIntoAnObjectsSideMeetsItsFace)
{
    const BallRun run = stroke(
        table([](double x, double) { return x >= 0.0 ? 0.005 : kTable; }),
        [](double t) {
            return glm::dvec3(std::min(-0.010 + 0.2 * t, 0.0005), 0.0, kTable + 0.001);
        },
        0.1);
    // The ball's proxy beside the HIP floats at the HIP's height: the face pushes back, never
    // down (a height field's surface holds a finger up or off, it does not pull it in).
    for (const HapticOutput &o : run.out)
        ASSERT_GE(o.force.z, 0.0) << "a downward force at x = " << o.hip.x;
    const HapticOutput &last = run.out.back();
    std::printf("into a side: force (%.2f, %.2f, %.2f) N, state %s\n", last.force.x, last.force.y,
                last.force.z, fingerStateName(run.state.back()));
    EXPECT_TRUE(last.contact);
    EXPECT_LT(last.force.x, -0.5 * 800.0 * 0.002);
    EXPECT_LT(std::fabs(last.force.z), 0.5 * std::fabs(last.force.x));
}

// Swiped across grooves 1 mm wide, 2 mm deep, every 4 mm (a keyboard's gaps), 0.5 mm into the
// keys at 20 cm/s: the ball bridges them, so contact never comes and goes.
TEST(BallRendererTest, aSwipeAcrossGroovesNarrowerThanTheFingerStaysInContact)
{
    const auto keys = [](double x, double) {
        return std::fmod(x + 0.1, 0.004) < 0.001 ? kTable - 0.002 : kTable;
    };
    const BallRun run = stroke(
        table(keys),
        [](double t) {
            const double z = t < 0.05 ? kTable + 0.0005 - 0.02 * t : kTable - 0.0005;
            return glm::dvec3(-0.02 + 0.2 * std::max(0.0, t - 0.05), 0.0, z);
        },
        0.25);
    int toggles = 0;
    double least = 1e9;
    for (std::size_t k = 60; k < run.out.size(); ++k) {
        toggles += run.out[k].contact != run.out[k - 1].contact ? 1 : 0;
        least = std::min(least, run.out[k].force.z);
    }
    std::printf("across 1 mm grooves: %d contact changes, least upward force %.3f N\n", toggles,
                least);
    EXPECT_EQ(toggles, 0);
    EXPECT_GT(least, 0.0);
}

// The table rises 9 mm in a frame (under the cut threshold: interpolated, 0.27 mm an update)
// under a finger resting 1 mm in: the bounded push lets the force grow by at most k·pushDepth an
// update (0.125 N at the defaults), where the rise alone would add 0.22 N an update.
TEST(BallRendererTest, aSurfaceRisingUnderARestingFingerPushesItAtABoundedRate)
{
    SyntheticVideo video(kBox, kW, kH, 30.0, [](double, double, int frame) {
        return frame <= 3 ? kTable : kTable + 0.009;
    });
    const BallRun run = stroke(
        std::move(video),
        [](double t) {
            return glm::dvec3(0.0, 0.0, t < 0.05 ? kTable + 0.001 - 0.04 * t : kTable - 0.001);
        },
        0.14);
    const FingerParameters p = fingerParameters(RendererConfig::forMethod(Method::Ball));
    double steepest = 0.0;
    for (std::size_t k = 101; k < run.out.size(); ++k)
        steepest =
            std::max(steepest, glm::length(run.out[k].force) - glm::length(run.out[k - 1].force));
    std::printf(
        "a 9 mm rise under a resting finger: force %.2f → %.2f N, at most %.3f N an update\n",
        glm::length(run.out[99].force), glm::length(run.out.back().force), steepest);
    EXPECT_GT(glm::length(run.out.back().force), glm::length(run.out[99].force) + 1.0);
    EXPECT_LE(steepest, 800.0 * p.pushDepth * 1.02);
}

// The table drops 30 mm (a scene cut) under a finger pressed 2 mm into it: with Reengage::Release
// the update of the cut trips and the force is let go.
TEST(BallRendererTest, aCutUnderThePressedFingerTrips)
{
    SyntheticVideo video(kBox, kW, kH, 30.0,
                         [](double, double, int frame) { return frame < 5 ? 0.01 : -0.02; });
    const BallRun run = stroke(
        std::move(video),
        [](double t) { return glm::dvec3(0.0, 0.0, t < 0.05 ? 0.0105 - 0.09 * t : 0.008); }, 0.3);
    int trips = 0;
    for (const HapticOutput &o : run.out)
        trips += o.released ? 1 : 0;
    EXPECT_EQ(trips, 1);
    EXPECT_FALSE(run.out.back().contact);
    EXPECT_EQ(glm::length(run.out.back().force), 0.0);
}

// A HIP that is not a number (a device's garbage) gives no force and no contact, and the finger
// is back on the table the next update it is a number again; every force is finite.
TEST(BallRendererTest, aHipThatIsNotANumberGivesNoForce)
{
    const double nan = std::nan("");
    const BallRun run = stroke(
        table(),
        [nan](double t) {
            if (t >= 0.1 && t < 0.102)
                return glm::dvec3(nan, 0.0, nan);
            return glm::dvec3(0.0, 0.0, kTable - 0.001);
        },
        0.2);
    for (const HapticOutput &o : run.out)
        ASSERT_TRUE(std::isfinite(o.force.x) && std::isfinite(o.force.y) &&
                    std::isfinite(o.force.z));
    EXPECT_EQ(glm::length(run.out[100].force), 0.0);
    EXPECT_FALSE(run.out[100].contact);
    EXPECT_TRUE(run.out.back().contact);
    EXPECT_GT(run.out.back().force.z, 0.0);
}

TEST(BallRendererTest, isARowOfTheRendererTable)
{
    const RendererEntry *row = findRenderer("ball");
    ASSERT_NE(row, nullptr);
    EXPECT_EQ(row->method, Method::Ball);
    auto r = makeRenderer(Method::Ball, RendererConfig::forMethod(Method::Ball), 64, 48);
    ASSERT_TRUE(r);
    EXPECT_EQ((*r)->method(), Method::Ball);
}

} // namespace
} // namespace depthtouch::haptics
