// What the run-time controls of the haptic task do to the force and the HIP, on simulated time
// (task_rig.h): the stiffness set while playing scales the force, the clutch button holds the HIP
// and re-centres the handle's workspace, and the device mapping places the handle in the scene
// box. Each test reads the effect (force, HIP) rather than a setting read back.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "app/haptic_task/task_rig.h"

namespace depthtouch::haptic_task {
namespace {

using namespace std::chrono_literals;
using test::pressScript;
using test::Rig;

/// Largest change of the z force between consecutive entries of \a f, N.
double largestStep(const std::vector<double> &f)
{
    double step = 0.0;
    for (std::size_t i = 1; i < f.size(); ++i)
        step = std::max(step, std::fabs(f[i] - f[i - 1]));
    return step;
}

/// The rig's HIP of the last rendered update (fails the test when there is none).
glm::dvec3 hipOf(HapticTask &task)
{
    glm::dvec3 hip{};
    glm::dvec3 proxy{};
    EXPECT_TRUE(task.lastPose(hip, proxy)) << "no rendered update yet";
    return hip;
}

TEST(HapticTaskEffectsTest, theStiffnessSetWhilePlayingScalesTheForceAtTheSamePenetration)
{
    // GIVEN the mock fingertip held 5 mm inside a flat surface: 4 N at the configured 800 N/m
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock());
    pressScript(mock, rig.clock().now());
    rig.publishFlat(0.0);
    const HapticTaskConfig c = Rig::baseConfig();
    ASSERT_DOUBLE_EQ(c.renderer.stiffness, 800.0);
    rig.start(mock, c);
    rig.runMs(300);
    const double base = rig.task().lastForce().z;
    ASSERT_NEAR(base, 4.0, 0.01);
    const glm::dvec3 hipBefore = hipOf(rig.task());
    const double perUpdate = c.maxForceRate / c.servoRateHz; // the rate limit, N per update
    for (const double k : {1600.0, 400.0}) {
        SCOPED_TRACE(k);
        // WHEN the stiffness changes at run time, the finger not moving
        rig.task().setStiffness(k);
        std::vector<double> f{rig.task().lastForce().z};
        for (int i = 0; i < 20; ++i) {
            rig.runMs(1);
            f.push_back(rig.task().lastForce().z);
        }
        // THEN the force is k/800 times what it was (F = k·penetration, the same penetration),
        // within 0.01 N, and it got there within the force-rate limit, not as a step
        EXPECT_NEAR(f.back(), base * k / 800.0, 0.01);
        EXPECT_LE(largestStep(f), perUpdate + 1e-9);
        const glm::dvec3 hip = hipOf(rig.task());
        EXPECT_NEAR(hip.z, hipBefore.z, 1e-12) << "the penetration did not change";
    }
    // AND a stiffness outside the one range (scene/stiffness.h) is ignored: the force stays
    for (const double bad : {-5.0, 99.0, 3001.0, 1e9})
        rig.task().setStiffness(bad);
    rig.runMs(10);
    EXPECT_DOUBLE_EQ(rig.task().stiffness(), 400.0);
    EXPECT_NEAR(rig.task().lastForce().z, base * 0.5, 0.01);
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

TEST(HapticTaskEffectsTest, theClutchHoldsTheHipAndReleasingItContinuesFromThere)
{
    // GIVEN clutch button 0 and a fingertip 5 mm inside a flat surface (4 N) at 50 ms; at 300 ms
    // the clutch is pressed and the handle moved 20 mm up and 10 mm right (as a viewer re-centres
    // the handle), released at 500 ms, then from 550 ms the handle goes 2 mm down
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock());
    const platform::TimePoint t0 = rig.clock().now();
    mock.setWaypoints({{t0, {0.0, 0.0, 0.01}, 0},
                       {t0 + 20ms, {0.0, 0.0, 0.01}, 0},
                       {t0 + 50ms, {0.0, 0.0, -0.005}, 0},
                       {t0 + 300ms, {0.0, 0.0, -0.005}, 1},
                       {t0 + 400ms, {0.01, 0.0, 0.015}, 1},
                       {t0 + 500ms, {0.01, 0.0, 0.015}, 0},
                       {t0 + 550ms, {0.01, 0.0, 0.015}, 0},
                       {t0 + 650ms, {0.01, 0.0, 0.013}, 0}});
    rig.publishFlat(0.0);
    HapticTaskConfig c = Rig::baseConfig();
    c.mapping.clutchButton = 0;
    rig.start(mock, c);
    rig.runMs(299);
    ASSERT_NEAR(rig.task().lastForce().z, 4.0, 0.01);
    const glm::dvec3 held = hipOf(rig.task());
    ASSERT_NEAR(held.z, -0.005, 1e-12);
    std::vector<double> f{rig.task().lastForce().z};
    // WHEN the clutch is held (updates at 300 .. 499 ms)
    for (int ms = 300; ms < 500; ++ms) {
        rig.runMs(1);
        f.push_back(rig.task().lastForce().z);
        // THEN the HIP stays where it was while the handle moves, and the force is zero once
        // the rate limit (2 N per update) has brought it down
        const glm::dvec3 hip = hipOf(rig.task());
        ASSERT_NEAR(hip.x, held.x, 1e-12) << ms;
        ASSERT_NEAR(hip.z, held.z, 1e-12) << ms;
        if (ms >= 302) {
            ASSERT_EQ(f.back(), 0.0) << ms;
        }
    }
    // WHEN it is released  THEN the HIP continues from where it was held (the workspace offset
    // took up the handle's 20 mm), so the finger is pressed 5 mm in again with 4 N, the force
    // back within the rate limit and no step beyond it
    for (int ms = 500; ms < 520; ++ms) {
        rig.runMs(1);
        f.push_back(rig.task().lastForce().z);
    }
    EXPECT_NEAR(hipOf(rig.task()).x, held.x, 1e-12);
    EXPECT_NEAR(hipOf(rig.task()).z, held.z, 1e-12);
    EXPECT_NEAR(rig.task().lastForce().z, 4.0, 0.01);
    EXPECT_LE(largestStep(f), c.maxForceRate / c.servoRateHz + 1e-9);
    // AND moving the handle 2 mm down moves the HIP 2 mm down from there: 5.6 N
    rig.runMs(180);
    EXPECT_NEAR(hipOf(rig.task()).z, held.z - 0.002, 1e-9);
    EXPECT_NEAR(hipOf(rig.task()).x, held.x, 1e-9);
    EXPECT_NEAR(rig.task().lastForce().z, 800.0 * 0.007, 0.01);
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

TEST(HapticTaskEffectsTest, theDeviceMappingPlacesTheHandleInTheSceneBox)
{
    // GIVEN HIP = 2·p + (10, −20, 1) mm and the handle resting at p = (3, 4, −2) mm from 50 ms on
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock());
    const platform::TimePoint t0 = rig.clock().now();
    const hal::Vec3 p{0.003, 0.004, -0.002};
    mock.setWaypoints(
        {{t0, {p.x, p.y, 0.01}, 0}, {t0 + 20ms, {p.x, p.y, 0.01}, 0}, {t0 + 50ms, p, 0}});
    rig.publishFlat(0.0);
    HapticTaskConfig c = Rig::baseConfig();
    c.mapping.scale = 2.0;
    c.mapping.offset = {0.01, -0.02, 0.001};
    rig.start(mock, c);
    rig.runMs(300);
    // THEN the HIP is at the scene point (16, −12, −3) mm
    const glm::dvec3 hip = hipOf(rig.task());
    EXPECT_NEAR(hip.x, 0.016, 1e-12);
    EXPECT_NEAR(hip.y, -0.012, 1e-12);
    EXPECT_NEAR(hip.z, -0.003, 1e-12);
    // AND the force is the scene's: 3 mm (not the handle's 2 mm) under the surface, k = 800 N/m,
    // pushing straight up (a flat surface)
    const double surface = test::heightOf(test::nearness16(0.0));
    const glm::dvec3 f = rig.task().lastForce();
    EXPECT_NEAR(f.z, 800.0 * (surface - hip.z), 0.01);
    EXPECT_NEAR(f.x, 0.0, 0.01);
    EXPECT_NEAR(f.y, 0.0, 0.01);
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

} // namespace
} // namespace depthtouch::haptic_task
