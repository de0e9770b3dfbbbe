/// \file
/// \brief The fingertip renderer (finger_renderer.h) where the surface under a pressed finger
/// changes in one update: a surface that falls away is unloaded at a bounded rate, not ramped
/// down over a quarter second; a step up under a finger that barely touches grows at the bounded
/// push's rate, not from a ramp that holds it near zero; a few pixels read far back under the
/// fingertip (time-of-flight flying pixels, a stereo mismatch, a ragged Kinect edge) do not let
/// it go while the surface within its reach stays above it, nor does that surface's noise while
/// the HIP stays still; a hole that opens while a fall is
/// unloaded goes on unloading at the same rate, and so does a surface that falls away during a
/// ramped step; a finger sliding off a rim unloads as it rolls off, and is free once the rim is
/// out of its reach; one gliding along a surface that rises under it is not pressed in by its
/// motion along it. Still 8-bit tables (finger_press.h).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "app/haptics/finger_log.h"
#include "app/haptics/finger_press.h"
#include "depthtouch/haptics/finger_output.h"
#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics::test {
namespace {

constexpr double kStiffness = 800.0; ///< N/m, the default config's.

/// \return the height the table at -5 mm raised by \a lift (m) has once coded in 8 bits (the
/// nearness code rounded, as tableWithHoles() codes it without holes), m.
double coded(double lift)
{
    const double n = std::round(((-0.005 + lift) / kBox.depth + 0.5) * 255.0);
    return (n / 255.0 - 0.5) * kBox.depth;
}

/// The table raised by \a lift (m) everywhere, no holes.
OwnedFrame raisedTable(double lift)
{
    return tableWithHoles([](double, double) { return false; }, 0u,
                          [lift](double, double) { return lift; });
}

/// What a finger pressed at \a hipZ (m) on the still table raised by \a before (m) felt once the
/// table, pressed 300 updates, was raised by \a after instead (printed as \a what): the largest
/// fall and rise of |F| from one update to the next over the next 40 updates, |F| 20 updates
/// after the change and k times the depth then, N.
struct TableStep {
    double fall = 0.0;
    double rise = 0.0;
    double after20 = 0.0;
    double expected = 0.0; ///< k times the HIP's depth under the changed table, N.
    double pressed = 0.0;  ///< |F| before the change, N.
    bool contact = false;  ///< In contact at the end.
};

TableStep stepUnder(const char *what, double hipZ, double before, double after)
{
    FramePress press({0.0, 0.0, hipZ});
    press.run(raisedTable(before), 300);
    TableStep s;
    s.pressed = press.force();
    const std::size_t from = press.log.out.size();
    press.run(raisedTable(after), 40);
    for (std::size_t i = from; i < press.log.out.size(); ++i) {
        const double d =
            glm::length(press.log.out[i].force) - glm::length(press.log.out[i - 1].force);
        s.fall = std::max(s.fall, -d);
        s.rise = std::max(s.rise, d);
    }
    s.after20 = glm::length(press.log.out[from + 20].force);
    s.expected = kStiffness * (coded(after) - hipZ);
    s.contact = press.log.out.back().contact;
    std::printf("%s: %.2f N pressed, 20 updates later %.2f N (k times the depth %.2f N), largest "
                "fall %.3f N and rise %.3f N an update\n",
                what, s.pressed, s.after20, s.expected, s.fall, s.rise);
    EXPECT_NEAR(s.pressed, kStiffness * (coded(before) - hipZ), 0.01);
    return s;
}

// A finger pressed 4 mm into a table that falls 3 mm in one update (an object it pressed moves
// off, a frame of a slower camera): 1 mm is left, k·1 mm. Before, the step was ramped like a
// step up, over 0.25 s: 20 updates later the force was still 3.0 N for the 0.8 N the surface
// gives (a force that is not there, felt as the surface sinking slowly). Now it unloads at
// 2·pushDepth_ an update (0.25 N at the default stiffness, the rate a hold over a hole unloads
// at): no knock either.
TEST(FingerReleaseTest, aSurfaceThatFallsAwayUnderAPressedFingerUnloadsAtABoundedRate)
{
    const TableStep s = stepUnder("table falling 3 mm under a 4 mm press", -0.006, 0.003, 0.0);
    EXPECT_TRUE(s.contact);
    EXPECT_NEAR(s.after20, s.expected, 0.01);
    EXPECT_LE(s.fall, RendererConfig{}.maxForceStep / 8.0 + 1e-6);
}

// A finger resting 0.2 mm into a table (0.16 N) when the table steps up 1 mm in one update. A
// step is ramped from the force before it over 0.25 s: from 0.16 N that held the force near
// zero with the HIP 1.2 mm in (on a forearm's rim in the feel bench: 15 ms of pop-through). A
// step from a force under the step's own size is not ramped: the bounded push grows it at
// maxForceStep/16 an update to k·1.2 mm.
TEST(FingerReleaseTest, aStepUpUnderAFingerThatBarelyTouchesGrowsAtTheBoundedPushRate)
{
    const TableStep s =
        stepUnder("table stepping up 1 mm under a 0.2 mm touch", -0.0052, 0.0, 0.001);
    ASSERT_LT(s.pressed, 0.25 * RendererConfig{}.maxForceStep); // under the step's own size
    EXPECT_NEAR(s.after20, s.expected, 0.01);
    EXPECT_LE(s.rise, RendererConfig{}.maxForceStep / 16.0 + 1e-6);
}

// A finger pressed 1 mm into a table; for 30 updates a patch 0.6 mm across under its centre reads
// the far plane (time-of-flight flying pixels at an edge, an active-stereo mismatch): code 0 of a
// file without holes, -20 mm, a measured surface far back, not a hole. The surface within the
// fingertip's reach (r/2 around the HIP) is still the table above the HIP, and the stencil's
// plane is the table's: the press goes on at k·1 mm. Before, the HIP above the sensor surface at
// its own x-y was free: the force fell to zero and came back, two knocks.
TEST(FingerReleaseTest, aFewPixelsReadFarBackUnderAPressedFingertipDoNotLetItGo)
{
    FramePress press({0.0, 0.0, -0.006});
    const OwnedFrame table = raisedTable(0.0);
    const OwnedFrame dropout =
        tableWithHoles([](double x, double y) { return std::hypot(x, y) < 0.0003; }, 0u);
    press.run(table, 300);
    const double pressed = kStiffness * (coded(0.0) + 0.006);
    ASSERT_NEAR(press.force(), pressed, 0.01);
    const std::size_t from = press.log.out.size();
    press.run(dropout, 30);
    press.run(table, 30);
    double least = 1e9;
    for (std::size_t i = from; i < press.log.out.size(); ++i)
        least = std::min(least, glm::length(press.log.out[i].force));
    std::printf("far pixels under a 1 mm press: least force %.2f N (k times the depth %.2f N)\n",
                least, pressed);
    EXPECT_NEAR(least, pressed, 0.01);
}

// The same far pixels under a still fingertip pressed 1 mm in, while the table around them reads
// a code higher and back again every few frames (a depth camera's noise on a still surface:
// time-of-flight multipath beside a typing hand in the feel bench). Each rise deepens the
// contact with the HIP still: the surface's doing, taken at the bounded push's rate. Before, a
// contact held by its reach alone ended wherever it grew deeper, as if the HIP pressed on beside
// a rim: the force fell to zero and was regained 52 ms later. Then the HIP itself presses down
// 2 mm beside the far patch, the case that ending is for (a press down a cabinet's side held up
// by the top's plane): it is let go, not held deeper and deeper.
TEST(FingerReleaseTest, aSurfaceThatReadsHigherUnderAFingertipHeldByItsReachKeepsTheContact)
{
    FramePress press({0.0, 0.0, -0.006});
    const auto far = [](double x, double y) { return std::hypot(x, y) < 0.0003; };
    const double code = coded(0.001) - coded(0.0); // one nearness code, m
    const OwnedFrame still = tableWithHoles(far, 0u);
    const OwnedFrame higher = tableWithHoles(far, 0u, [code](double, double) { return code; });
    press.run(raisedTable(0.0), 300);
    const std::size_t from = press.log.out.size();
    for (int i = 0; i < 10; ++i) {
        press.run(still, 33);
        press.run(higher, 33);
    }
    bool always = true;
    double least = 1e9;
    for (std::size_t i = from; i < press.log.out.size(); ++i) {
        always = always && press.log.out[i].contact;
        least = std::min(least, glm::length(press.log.out[i].force));
    }
    const double pressed = kStiffness * (coded(0.0) + 0.006);
    std::printf("far pixels under a still 1 mm press on a table reading a code (%.3f mm) higher "
                "and back: in contact throughout %d, least force %.2f N (k times the depth %.2f "
                "N)\n",
                code * 1e3, always ? 1 : 0, least, pressed);
    EXPECT_TRUE(always);
    EXPECT_GT(least, 0.9 * pressed);
    press.run(still, 200, 0.0, -0.002);
    const double pressedOn = press.force();
    std::printf("then pressed on 2 mm beside the far patch: %.2f N, in contact %d\n", pressedOn,
                press.log.out.back().contact ? 1 : 0);
    EXPECT_LT(pressedOn, pressed);
}

// A finger resting 5 mm into the table (4 N) lifts off at 40 cm/s, 0.32 N of depth an update, more
// than the offset filter unloads by (maxForceStep/8, 0.25 N: the bound is for a surface that falls
// away). The filtered force lagged the rising finger: 1.07 N on the last update in contact,
// dropped at once (in the demo, a hand the turning head had pushed to 4 N rose out at 40 cm/s and
// its force dropped by 2 N, the step limit, twice). Now the HIP's own move out unloads the force
// too, as a spring's: it follows the finger down and no update drops more than 1 N.
TEST(FingerReleaseTest, aFingerLiftingOffFastIsUnloadedAsItRisesNotAtTheEnd)
{
    FramePress press({0.0, 0.0, -0.010});
    const OwnedFrame table = raisedTable(0.0);
    press.run(table, 300);
    const double pressed = press.force();
    ASSERT_NEAR(pressed, kStiffness * (coded(0.0) + 0.010), 0.01);
    const std::size_t from = press.log.out.size();
    press.run(table, 40, 0.0, 0.016); // 0.4 mm an update
    double fall = 0.0;
    double atEnd = 0.0; // |F| on the last update in contact
    for (std::size_t i = from; i < press.log.out.size(); ++i) {
        fall = std::max(fall, glm::length(press.log.out[i - 1].force) -
                                  glm::length(press.log.out[i].force));
        if (press.log.out[i].contact)
            atEnd = glm::length(press.log.out[i].force);
    }
    std::printf("a 4 N rest lifting off at 40 cm/s: %.2f N on its last update in contact, largest "
                "fall %.3f N an update\n",
                atEnd, fall);
    EXPECT_FALSE(press.log.out.back().contact);
    EXPECT_LE(fall, 0.5 * RendererConfig{}.maxForceStep);
}

// A finger resting 5 mm into the table (4 N) lifts off at 80 cm/s, 0.64 N of spring an update:
// more than the offset filter's step bound (3·pushDepth, 0.375 N), which is for what the surface
// does. Filtered with the rest, the hand's own rise left the force behind the spring by up to
// 0.27 N more each update, and the zero-order hold charged a hand that had already left with it
// (most of the energy `bench feel` measured over the ideal penalty's). Now the hand's move along
// the offset passes at once, as a spring's: from the second update of the rise on, the force is
// never above k times the depth under the table.
TEST(FingerReleaseTest, aHandRisingFasterThanTheFiltersStepIsFollowedByTheSpring)
{
    FramePress press({0.0, 0.0, -0.010});
    const OwnedFrame table = raisedTable(0.0);
    press.run(table, 300);
    ASSERT_NEAR(press.force(), kStiffness * (coded(0.0) + 0.010), 0.01);
    const std::size_t from = press.log.out.size();
    press.run(table, 20, 0.0, 0.016); // 0.8 mm an update
    double over = -1e9;               // |F| above the spring k·depth, the worst update, N
    int inContact = 0;
    for (std::size_t i = from + 2; i < press.log.out.size(); ++i) {
        const double depth = coded(0.0) - press.log.out[i].hip.z;
        if (!press.log.out[i].contact || depth <= 0.0)
            break;
        over = std::max(over, glm::length(press.log.out[i].force) - kStiffness * depth);
        ++inContact;
    }
    std::printf("a 4 N rest lifting off at 80 cm/s: %d updates in contact after the first two, "
                "|F| at most %.3f N above the spring\n",
                inContact, over);
    ASSERT_GE(inContact, 3);
    EXPECT_LE(over, 0.02);
}

// The same rest pressed in at 20 cm/s (0.16 N an update), then pulled out at 1.5 m/s: the hand's
// move along the offset over the turning update (the mean of its last two, 0.65 mm) would turn
// the force by 0.52 N against its last change, a sign reversal the hand feels as a knock. The
// filtered offset turns back by at most its step bound (3·pushDepth, 0.375 N at the default
// stiffness) in that update; the next updates follow the rise.
TEST(FingerReleaseTest, aHandThatTurnsBackTurnsTheForceAtMostTheFiltersStep)
{
    FramePress press({0.0, 0.0, -0.010});
    const OwnedFrame table = raisedTable(0.0);
    press.run(table, 300);
    press.run(table, 10, 0.0, -0.002); // in, 0.2 mm an update
    const std::size_t turn = press.log.out.size();
    press.run(table, 4, -0.0003, 0.0057); // out, 1.5 mm an update
    const auto size = [&](std::size_t i) { return glm::length(press.log.out[i].force); };
    const double before = size(turn - 1) - size(turn - 2);
    const double atTurn = size(turn - 1) - size(turn);
    const double next = size(turn) - size(turn + 1);
    const double step = 3.0 * RendererConfig{}.maxForceStep / 16.0; // 3·pushDepth of force, N
    std::printf("turning back at 1.5 m/s: +%.3f N, then -%.3f N in the turning update, -%.3f N "
                "in the next\n",
                before, atTurn, next);
    ASSERT_GT(before, 0.05); // the force was rising
    EXPECT_GT(atTurn, 0.0);
    EXPECT_LE(atTurn, step + 1e-3);
    EXPECT_GT(next, step); // then at the spring's rate
}

// The same ramped step under friction (μs = μd = 0.6): the finger slides 3 mm sideways at 10
// cm/s during the ramp, so that the cone holds the proxy behind it and the ramp blends toward a
// tilted spring, then lifts off at 40 cm/s as it goes on sliding. The ramp's force is handed to
// the spring once it holds more than the spring gives; the hand-over was made before friction,
// whose anchor then took the proxy back to its own direction: the force turned by up to 1.5 N in
// that update (the feel bench's typing desk edge, the demo's head as the finger lifted off). Now
// the hand-over takes the proxy the spring uses, and the cone holds it there: no update changes
// the force by more than 1 N, the demo's goal for a step (handed over before friction, this
// stroke stepped 2.0 N, the step limit; now 0.94 N, where the contact ends at the rise).
TEST(FingerReleaseTest, aFingerLiftingOffARampedStepUnderFrictionIsHandedOverWithoutAKnock)
{
    RendererConfig config = RendererConfig::forMethod(Method::Finger);
    config.staticFriction = 0.6;
    config.dynamicFriction = 0.6;
    FramePress press({0.0, 0.0, -0.010});
    press.finger = FingerRenderer(config);
    press.finger.reset(press.hip + glm::dvec3(0.0, 0.0, 0.004));
    press.run(raisedTable(0.0), 300);
    const OwnedFrame stepped = raisedTable(0.001);
    ASSERT_TRUE(press.finger.setFrames(stepped.view(), nullptr));
    glm::dvec3 hip = press.hip;
    double largest = 0.0;    // the largest |ΔF| from one update to the next, N
    double tangential = 0.0; // the largest |Fx| / |Fz| while sliding in contact
    glm::dvec3 last = press.log.out.back().force;
    bool ended = false;
    for (int i = 0; i < 80; ++i, ++press.k) {
        hip.x += 1e-4;                 // 10 cm/s sideways throughout
        hip.z += i >= 30 ? 4e-4 : 0.0; // 40 cm/s up from the 30th update
        const HapticOutput out = press.finger.update(hip, press.k / kRate);
        largest = std::max(largest, glm::length(out.force - last));
        if (out.contact && std::fabs(out.force.z) > 0.1)
            tangential = std::max(tangential, std::fabs(out.force.x) / std::fabs(out.force.z));
        last = out.force;
        ended = !out.contact;
    }
    std::printf("a 4 N press sliding at 10 cm/s under friction 0.6 during a ramped 1 mm step, "
                "lifting off at 40 cm/s: largest step %.3f N an update, Ft/Fn up to %.2f\n",
                largest, tangential);
    EXPECT_TRUE(ended);
    EXPECT_GT(tangential, 0.2); // friction held the proxy behind the sliding finger
    EXPECT_LE(largest, 0.5 * RendererConfig{}.maxForceStep);
}

// A finger pressed 5 mm into the table (4 N) when the table steps up 1 mm in one update: a step
// up under a pressed finger, ramped in from the 4 N over the ramp time (0.25 s). Ten updates into
// the ramp the finger lifts off at 40 cm/s. The ramp held the force it started from while the
// finger rose out, and the force dropped in 2 N steps (the step limit) when the contact ended (in
// the demo, a hand the turning head had pushed to 3 N rose out at 40 cm/s: 2.2 N -> 0.2 N in an
// update). A finger lifting off leaves the ramp to the filter, which unloads the force as it
// rises: no update drops more than 1 N.
TEST(FingerReleaseTest, aFingerLiftingOffDuringARampedStepIsUnloadedAsItRises)
{
    FramePress press({0.0, 0.0, -0.010});
    press.run(raisedTable(0.0), 300);
    ASSERT_NEAR(press.force(), kStiffness * (coded(0.0) + 0.010), 0.01);
    const OwnedFrame stepped = raisedTable(0.001);
    press.run(stepped, 10); // the step, ramped in
    const std::size_t from = press.log.out.size();
    press.run(stepped, 40, 0.0, 0.016); // 0.4 mm an update
    double fall = 0.0;
    for (std::size_t i = from; i < press.log.out.size(); ++i)
        fall = std::max(fall, glm::length(press.log.out[i - 1].force) -
                                  glm::length(press.log.out[i].force));
    std::printf("a 4 N press lifting off at 40 cm/s during a ramped 1 mm step: largest fall %.3f N "
                "an update\n",
                fall);
    EXPECT_FALSE(press.log.out.back().contact);
    EXPECT_LE(fall, 0.5 * RendererConfig{}.maxForceStep);
}

// A finger pressed 4 mm into a table that falls 3 mm (the filter unloads the force at its
// bounded rate), and two updates later the spot under the finger turns to a hole (the shadow band
// beside the object that fell away): the hold over the hole takes the unload on from where the
// force is, at the same bounded rate. Before, the hold reset the filter to its own 1 mm offset:
// the force dropped 2.2 N at once, in the two steps the force's step limit allows (on the feel
// bench's synthetic occluder, a tap beside the occluder: 6.9 N to 0.85 N, three spikes).
TEST(FingerReleaseTest, aHoleOpeningWhileAFallIsUnloadedGoesOnUnloadingAtTheBoundedRate)
{
    FramePress press({0.0, 0.0, -0.006});
    press.run(raisedTable(0.003), 300);
    const double pressed = press.force();
    ASSERT_NEAR(pressed, kStiffness * (coded(0.003) + 0.006), 0.01);
    const std::size_t from = press.log.out.size();
    press.run(raisedTable(0.0), 2);
    press.run(tableWithHoles([](double x, double y) { return std::hypot(x, y) < 0.004; }, 24u), 60);
    double fall = 0.0;
    for (std::size_t i = from; i < press.log.out.size(); ++i)
        fall = std::max(fall, glm::length(press.log.out[i - 1].force) -
                                  glm::length(press.log.out[i].force));
    const double afterFall = glm::length(press.log.out[from + 1].force);
    const double inHole = glm::length(press.log.out[from + 2].force);
    std::printf("hole opening 2 updates after a 3 mm fall under a 4 mm press: %.2f N pressed, "
                "%.2f N then %.2f N, largest fall %.3f N an update\n",
                pressed, afterFall, inHole, fall);
    EXPECT_GT(inHole, pressed - 3.0 * RendererConfig{}.maxForceStep / 8.0); // still unloading
    EXPECT_LE(fall, RendererConfig{}.maxForceStep / 8.0 + 1e-6);
    EXPECT_LT(press.force(), 0.5 * pressed); // and unloaded, not held
}

// A finger pressed 2 mm into a table that steps up 2 mm (the step is ramped in over 0.25 s),
// and 50 updates into the ramp falls back 3.5 mm, 0.5 mm over the HIP: the ramp blended from
// the force before the step toward the new target over its whole time, and held about 1.3 N for
// the 0.4 N the surface gives 20 updates on (on the feel bench's living room, a tap's pushed
// proxy snapping back to the table kept 2.7 N with the proxy 0.1 mm from the HIP, then dropped it
// in 2 N steps as the finger lifted off). Now the filter takes the ramp's force over and unloads
// it at its bounded rate.
TEST(FingerReleaseTest, aSurfaceThatFallsAwayDuringARampedStepUnloadsAtTheBoundedRate)
{
    FramePress press({0.0, 0.0, -0.007});
    press.run(raisedTable(0.0), 300);
    ASSERT_NEAR(press.force(), kStiffness * (coded(0.0) + 0.007), 0.01);
    press.run(raisedTable(0.002), 50);
    const double ramped = press.force();
    const double target = kStiffness * (coded(0.002) + 0.007);
    ASSERT_LT(ramped, target - 0.2); // still ramping up
    const std::size_t from = press.log.out.size();
    press.run(raisedTable(-0.0015), 40);
    double fall = 0.0;
    for (std::size_t i = from; i < press.log.out.size(); ++i)
        fall = std::max(fall, glm::length(press.log.out[i - 1].force) -
                                  glm::length(press.log.out[i].force));
    const double after20 = glm::length(press.log.out[from + 20].force);
    const double expected = kStiffness * (coded(-0.0015) + 0.007);
    std::printf("table falling 3.5 mm during a ramped 2 mm step: %.2f N ramping to %.2f N, 20 "
                "updates after the fall %.2f N (k times the depth %.2f N), largest fall %.3f N\n",
                ramped, target, after20, expected, fall);
    EXPECT_NEAR(after20, expected, 0.05);
    EXPECT_LE(fall, RendererConfig{}.maxForceStep / 8.0 + 1e-6);
}

/// What a finger slid at \a speed (m/s) \a depth (m) under the top of a block 5 mm high (the
/// table beyond its edge at x = 0) off that edge felt, rising \a rise (m) an update past the
/// edge: |F| before the slide, each fall of |F| in an update past the edge while some force is
/// left (N), the share of the force along z just before the first fall, and the most |F| once
/// the edge is a pixel's vertex beyond 3r/4 behind the HIP (N).
struct RimSlide {
    double pressed = 0.0;
    std::vector<double> falls;
    std::vector<double> before; ///< |F| before each fall, N.
    double firstUp = 0.0;
    double outOfReach = 0.0;
};

RimSlide slideOffRim(double speed, double depth, double rise = 0.0, double stiffness = 0.0)
{
    const OwnedFrame block = tableWithHoles([](double, double) { return false; }, 0u,
                                            [](double x, double) { return x < 0.0 ? 0.005 : 0.0; });
    FingerRenderer finger = makeFinger();
    if (stiffness > 0.0)
        finger.setStiffness(stiffness); // the forces only, not the geometry
    RimSlide out;
    EXPECT_TRUE(finger.setFrames(block.view(), nullptr));
    const double r = RendererConfig::forMethod(Method::Finger).fingerRadiusInBox();
    const double top = coded(0.005);
    glm::dvec3 hip{-0.010, 0.0, top + 0.004};
    finger.reset(hip);
    double last = 0.0;
    glm::dvec3 lastForce{};
    for (int k = 0; k < 500; ++k) {
        if (k <= 50)
            hip.z = top + 0.004 - (0.004 + depth) * k / 50.0;
        if (k >= 300)
            hip.x = std::min(hip.x + speed / kRate, 0.005);
        if (hip.x > 0.0)
            hip.z += rise;
        const glm::dvec3 force = finger.update(hip, k / kRate).force;
        const double f = glm::length(force);
        if (k == 299)
            out.pressed = f;
        if (k >= 300 && hip.x > 0.0 && f > 0.0 && f < last - 1e-3) {
            if (out.falls.empty())
                out.firstUp = lastForce.z / last;
            out.falls.push_back(last - f);
            out.before.push_back(last);
        }
        lastForce = force;
        if (hip.x > 0.75 * r + 2.0 * kBox.width / kStillW) // a pixel's vertex beyond 3r/4
            out.outOfReach = std::max(out.outOfReach, f);
        last = f;
    }
    std::printf("sliding off a rim %.0f mm under its top at %.0f cm/s: %.2f N pressed, %zu "
                "updates unloading past the edge (falls",
                depth * 1e3, speed * 1e2, out.pressed, out.falls.size());
    for (const double fall : out.falls)
        std::printf(" %.3f", fall);
    std::printf(" N), %.3f N once out of reach\n", out.outOfReach);
    return out;
}

// A finger slid off a block's edge 2 mm under its top at 50 cm/s, and 3 and 5 mm under it at
// 20 cm/s.
// Free once the edge is more than half its radius behind it, it was let go in one update, a force
// the fingertip still rests on the rim with (on the kitchen's ragged cabinet edge, 0.8 N up on
// each 3 mm tooth and down at once in each gap: 33 sign reversals a second). Now the force
// unloads from maxForceStep/8, the step doubling to maxForceStep/4 but never more than the
// offset filter's share kFingerOffsetAlpha of what is left, while the rim is within 3/4 of the
// radius, and is 0 once it is not.
TEST(FingerReleaseTest, aFingerSlidingOffARimUnloadsAsItRollsOffAndIsFreeOutOfReach)
{
    const double step = RendererConfig{}.maxForceStep;
    const RimSlide fast = slideOffRim(0.5, 0.002);
    EXPECT_NEAR(fast.pressed, kStiffness * 0.002, 0.05);
    ASSERT_GE(fast.falls.size(), 2u);
    EXPECT_NEAR(fast.falls[0], step / 8.0, 1e-6);
    EXPECT_NEAR(fast.falls[1], 2.0 * fast.falls[0], 1e-6);
    EXPECT_EQ(fast.outOfReach, 0.0);
    const RimSlide slow = slideOffRim(0.2, 0.003);
    int atCap = 0; // falls of maxForceStep/4: doubled no further
    for (std::size_t i = 0; i < slow.falls.size(); ++i) {
        EXPECT_LE(slow.falls[i], std::min(step / 4.0, kFingerOffsetAlpha * slow.before[i]) + 1e-6);
        atCap += std::fabs(slow.falls[i] - step / 4.0) < 1e-6 ? 1 : 0;
    }
    EXPECT_GE(atCap, 1);
    EXPECT_EQ(slow.outOfReach, 0.0);
    // 5 mm under the top (4 N): α of what is left stays over maxForceStep/4, so the doubling's
    // cap is what bounds each fall, and it holds there for more than one update.
    const RimSlide heavy = slideOffRim(0.2, 0.005);
    int heavyAtCap = 0;
    for (std::size_t i = 0; i < heavy.falls.size(); ++i) {
        EXPECT_LE(heavy.falls[i],
                  std::min(step / 4.0, kFingerOffsetAlpha * heavy.before[i]) + 1e-6);
        heavyAtCap += std::fabs(heavy.falls[i] - step / 4.0) < 1e-6 ? 1 : 0;
    }
    EXPECT_GE(heavyAtCap, 2);
}

// The first slide off the rim (2 mm under the top at 50 cm/s) with the stiffness turned down to
// 100 N/m (a viewer's remote: the forces change, not the geometry), so that the finger rests on
// the rim with 0.2 N. The release's first step, maxForceStep/8, was larger than the whole force,
// and it went in one update: on a keyboard's keys, whose gaps the sensor sees and a fingertip
// does not sink into, a contact that light ended at each gap and began again at the next key, an
// alternating run of 5-7 updates in `bench feel`. Now it unloads by the offset filter's share of
// what is left, as the filter takes a surface that falls away, over the updates the rim is in
// reach.
TEST(FingerReleaseTest, aLightlyPressedFingerSlidingOffARimUnloadsOverSeveralUpdates)
{
    const double k = 100.0;
    const RimSlide light = slideOffRim(0.5, 0.002, 0.0, k);
    EXPECT_NEAR(light.pressed, k * 0.002, 0.01);
    ASSERT_GE(light.falls.size(), 2u);
    for (std::size_t i = 0; i < light.falls.size(); ++i)
        EXPECT_NEAR(light.falls[i], kFingerOffsetAlpha * light.before[i], 1e-6) << "fall " << i;
    EXPECT_EQ(light.outOfReach, 0.0);
}

// The same slide off the rim with the hand also rising 0.2 mm an update past the edge: the
// release unloads the rise's part along the force as the spring would, k · 0.2 mm · F̂z, on top
// of its own schedule, never by more than maxForceStep/4 an update (no spike). Before, a hand
// lifting off a rim at the bench's climb rate (2 mm an update) was pushed 2 mm at 1.33 N after it
// was out: 2.7 mJ into the hand at each lift-off of synthetic-head/8's 50 cm/s swipe.
TEST(FingerReleaseTest, aFingerLiftingOffARimIsUnloadedAsItRises)
{
    const double step = RendererConfig{}.maxForceStep;
    const double rise = 0.2e-3;
    const RimSlide lifted = slideOffRim(0.5, 0.002, rise);
    ASSERT_GE(lifted.falls.size(), 2u);
    ASSERT_GT(lifted.firstUp, 0.5); // the force leans up at the rim, as a ball's does
    EXPECT_NEAR(lifted.falls[0],
                std::min(step / 8.0 + kStiffness * rise * lifted.firstUp, step / 4.0), 1e-6);
    EXPECT_GT(lifted.falls[0], step / 8.0 + 0.05); // faster than the sideways slide's first step
    for (const double fall : lifted.falls)
        EXPECT_LE(fall, step / 4.0 + 1e-6);
    EXPECT_EQ(lifted.outOfReach, 0.0);
    // Unloaded in no more updates than the slide that does not rise (from a force as large).
    const RimSlide level = slideOffRim(0.5, 0.002);
    EXPECT_LE(lifted.falls.size(), level.falls.size());
}

// A table that rises 2.8 mm in one frame under a finger gliding 1 mm over it at 50 cm/s (an
// object's top arriving under it): the finger, 1.8 mm under the new top, is caught and pushed out
// at the bounded push's rate. Its motion along the table does not press it in: the depth may grow
// by the HIP's motion into the surface only. Before, it grew by all of the HIP's 0.5 mm an update
// too: 0.53 N on the first update (on the kitchen's ragged cabinet edge, a swipe caught by each
// 3 mm tooth after the last one's force had unloaded: a sign reversal on every tooth).
TEST(FingerReleaseTest, aFingerGlidingAlongASurfaceThatRisesUnderItIsNotPressedInByItsMotion)
{
    FingerRenderer finger = makeFinger();
    const RendererConfig cfg = RendererConfig::forMethod(Method::Finger);
    const OwnedFrame low = raisedTable(0.0);
    const OwnedFrame high = raisedTable(0.0028);
    glm::dvec3 hip{-0.020, 0.0, coded(0.0) + 0.001};
    finger.reset(hip);
    double first = 0.0; // |F| on the first update in contact, N
    double rise = 0.0;  // the largest rise of |F| in one update, N
    double last = 0.0;
    for (int k = 0; k < 80; ++k) {
        if (k == 0 || k == 20) {
            ASSERT_TRUE(finger.setFrames((k == 0 ? low : high).view(), nullptr));
        }
        hip.x = -0.020 + 0.0005 * k; // 50 cm/s at 1 kHz
        const HapticOutput out = finger.update(hip, k / kRate);
        const double f = glm::length(out.force);
        if (first == 0.0 && out.contact)
            first = f;
        rise = std::max(rise, f - last);
        last = f;
    }
    const double push = cfg.maxForceStep / 16.0; // the bounded push's growth an update, N
    const double expected = kStiffness * (coded(0.0028) - hip.z);
    std::printf("a table rising 1.8 mm over a finger gliding at 50 cm/s: %.3f N on the first "
                "update in contact, largest rise %.3f N an update (the bounded push %.3f N), "
                "%.2f N at the end (k times the depth %.2f N)\n",
                first, rise, push, last, expected);
    EXPECT_GT(first, 0.0);
    EXPECT_LE(first, push + 1e-6);
    EXPECT_LE(rise, push + 1e-6);
    EXPECT_NEAR(last, expected, 0.05);
}

} // namespace
} // namespace depthtouch::haptics::test
