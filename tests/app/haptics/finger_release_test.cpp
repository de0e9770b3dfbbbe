/// \file
/// \brief The fingertip renderer (finger_renderer.h) where the surface under a pressed finger
/// changes in one update: a surface that falls away is unloaded at a bounded rate, not ramped
/// down over a quarter second; a step up under a finger that barely touches grows at the bounded
/// push's rate, not from a ramp that holds it near zero; a few pixels read far back under the
/// fingertip (time-of-flight flying pixels, a stereo mismatch, a ragged Kinect edge) do not let
/// it go while the surface within its reach stays above it. Still 8-bit tables (finger_press.h).

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "app/haptics/finger_log.h"
#include "app/haptics/finger_press.h"
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

/// The largest fall and rise of |F| from one update to the next from update \a from on, N.
void largestSteps(const Log &log, std::size_t from, double &fall, double &rise)
{
    fall = 0.0;
    rise = 0.0;
    for (std::size_t i = std::max<std::size_t>(from, 1); i < log.out.size(); ++i) {
        const double d = glm::length(log.out[i].force) - glm::length(log.out[i - 1].force);
        fall = std::max(fall, -d);
        rise = std::max(rise, d);
    }
}

// A finger pressed 4 mm into a table that falls 3 mm in one update (an object it pressed moves
// off, a frame of a slower camera): 1 mm is left, k·1 mm. Before, the step was ramped like a
// step up, over 0.25 s: 20 updates later the force was still 3.0 N for the 0.8 N the surface
// gives (a force that is not there, felt as the surface sinking slowly). Now it unloads at
// 2·pushDepth_ an update (0.25 N at the default stiffness, the rate a hold over a hole unloads
// at): no knock either.
TEST(FingerReleaseTest, aSurfaceThatFallsAwayUnderAPressedFingerUnloadsAtABoundedRate)
{
    FramePress press({0.0, 0.0, -0.006});
    press.run(raisedTable(0.003), 300);
    ASSERT_NEAR(press.force(), kStiffness * (coded(0.003) + 0.006), 0.01);
    const std::size_t fell = press.log.out.size();
    press.run(raisedTable(0.0), 30);
    double fall = 0.0;
    double rise = 0.0;
    largestSteps(press.log, fell, fall, rise);
    const double after20 = glm::length(press.log.out[fell + 20].force);
    std::printf("table falling 3 mm under a 4 mm press: force 20 updates later %.2f N (k times the "
                "depth left %.2f N), largest fall %.3f N an update\n",
                after20, kStiffness * (coded(0.0) + 0.006), fall);
    EXPECT_TRUE(press.log.out.back().contact);
    EXPECT_NEAR(after20, kStiffness * (coded(0.0) + 0.006), 0.01);
    EXPECT_LE(fall, RendererConfig{}.maxForceStep / 8.0 + 1e-6);
}

// A finger resting 0.2 mm into a table (0.16 N) when the table steps up 1 mm in one update. A
// step is ramped from the force before it over 0.25 s: from 0.16 N that held the force near
// zero with the HIP 1.2 mm in (on a forearm's rim in the feel bench: 15 ms of pop-through). A
// step from a force under the step's own size is not ramped: the bounded push grows it at
// maxForceStep/16 an update to k·1.2 mm.
TEST(FingerReleaseTest, aStepUpUnderAFingerThatBarelyTouchesGrowsAtTheBoundedPushRate)
{
    FramePress press({0.0, 0.0, -0.0052});
    press.run(raisedTable(0.0), 300);
    ASSERT_NEAR(press.force(), kStiffness * (coded(0.0) + 0.0052), 0.01);
    ASSERT_LT(press.force(), 0.25 * RendererConfig{}.maxForceStep); // under the step's own size
    const std::size_t stepped = press.log.out.size();
    press.run(raisedTable(0.001), 40);
    double fall = 0.0;
    double rise = 0.0;
    largestSteps(press.log, stepped, fall, rise);
    const double after20 = glm::length(press.log.out[stepped + 20].force);
    const double deep = kStiffness * (coded(0.001) + 0.0052);
    std::printf("table stepping up 1 mm under a 0.2 mm touch: force 20 updates later %.2f N (k "
                "times the depth %.2f N), largest rise %.3f N an update\n",
                after20, deep, rise);
    EXPECT_NEAR(after20, deep, 0.01);
    EXPECT_LE(rise, RendererConfig{}.maxForceStep / 16.0 + 1e-6);
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
    const OwnedFrame dropout = tableWithHoles(
        [](double x, double y) { return std::hypot(x, y) < 0.0003; }, 0u);
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

} // namespace
} // namespace depthtouch::haptics::test
