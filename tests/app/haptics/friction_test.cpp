/// \file
/// \brief Friction on the proxy (friction.h, Ruspini et al. 1997's friction cone): the cone on its
/// own, the configuration's checks, and the scenario of docs/materials.md: on a tilted plane with
/// μs = 0.5, μd = 0.3 the proxy holds under a HIP pushed sideways until the tangential force
/// reaches 0.5·Fn, then slides at 0.3·Fn (within 1 %), in the `finger`, `ball` and `modified`
/// renderers.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "app/haptics/synthetic.h"
#include "depthtouch/haptics/friction.h"
#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics {
namespace {

constexpr double kStatic = 0.5;
constexpr double kDynamic = 0.3;

TEST(FrictionConeTest, sticksWithinTheStaticConeThenSlidesOnTheDynamicOne)
{
    // GIVEN a flat surface z = 0 pressed 2 mm deep, μs = 0.5, μd = 0.3
    FrictionCone cone(kStatic, kDynamic);
    ASSERT_TRUE(cone.enabled());
    const double depth = 2e-3;
    // WHEN the HIP first touches at x = 0, the proxy is the goal
    glm::dvec3 p = cone.apply({0.0, 0.0, 0.0}, {0.0, 0.0, -depth}, 0.0);
    EXPECT_EQ(p, glm::dvec3(0.0, 0.0, 0.0));
    // THEN it stays while the HIP is within μs·depth = 1 mm to the side
    p = cone.apply({0.9e-3, 0.0, 0.0}, {0.9e-3, 0.0, -depth}, 0.001);
    EXPECT_EQ(p.x, 0.0);
    EXPECT_FALSE(cone.sliding());
    // AND beyond it the proxy slides to μd·depth = 0.6 mm behind the goal
    p = cone.apply({1.1e-3, 0.0, 0.0}, {1.1e-3, 0.0, -depth}, 0.002);
    EXPECT_TRUE(cone.sliding());
    EXPECT_NEAR(p.x, 1.1e-3 - kDynamic * depth, 1e-15);
    EXPECT_NEAR(p.z, 0.0, 1e-18);
    // AND a HIP that stops is held there, under the dynamic cone for kRestickTime
    double t = 0.003;
    for (; t < 0.003 + kRestickTime - 1e-9; t += 0.001) {
        p = cone.apply({1.1e-3, 0.0, 0.0}, {1.1e-3, 0.0, -depth}, t);
        EXPECT_NEAR(p.x, 1.1e-3 - kDynamic * depth, 1e-15);
        EXPECT_TRUE(cone.sliding()) << t;
    }
    // AND then under the static one: a push within μs·depth of the held proxy does not move it
    p = cone.apply({1.1e-3, 0.0, 0.0}, {1.1e-3, 0.0, -depth}, t);
    EXPECT_FALSE(cone.sliding());
    p = cone.apply({1.4e-3, 0.0, 0.0}, {1.4e-3, 0.0, -depth}, t + 0.001);
    EXPECT_NEAR(p.x, 1.1e-3 - kDynamic * depth, 1e-15);
    EXPECT_FALSE(cone.sliding());
    // AND after release() the next contact starts at its own goal
    cone.release();
    p = cone.apply({5e-3, 0.0, 0.0}, {5e-3, 0.0, -depth}, t + 0.002);
    EXPECT_EQ(p.x, 5e-3);
}

TEST(FrictionConeTest, zeroCoefficientsAreOffAndNonFiniteInputIsPassedThrough)
{
    EXPECT_FALSE(FrictionCone(0.0, 0.0).enabled());
    EXPECT_TRUE(FrictionCone(0.0, 0.2).enabled());
    FrictionCone cone(kStatic, kDynamic);
    (void)cone.apply({0.0, 0.0, 0.0}, {0.0, 0.0, -1e-3}, 0.0);
    const glm::dvec3 bad(std::nan(""), 0.0, 0.0);
    const glm::dvec3 p = cone.apply(bad, {0.0, 0.0, -1e-3}, 0.001);
    EXPECT_TRUE(std::isnan(p.x)); // the goal as given: the force stage turns it into zero force
    // and the cone starts again at the next finite goal
    EXPECT_EQ(cone.apply({2e-3, 0.0, 0.0}, {2e-3, 0.0, -1e-3}, 0.002).x, 2e-3);
}

TEST(FrictionConfigTest, coefficientsOutsideZeroToTwoAreRefused)
{
    RendererConfig c;
    EXPECT_TRUE(c.validate());
    c.staticFriction = 2.0;
    c.dynamicFriction = 0.0;
    EXPECT_TRUE(c.validate());
    for (double bad : {-0.1, 2.01, std::nan(""), HUGE_VAL}) {
        c.staticFriction = bad;
        EXPECT_FALSE(c.validate()) << bad;
        c.staticFriction = 0.5;
        c.dynamicFriction = bad;
        EXPECT_FALSE(c.validate()) << bad;
        c.dynamicFriction = 0.3;
    }
}

/// The tilted plane, m: z = s·x − 2 mm, s = 0.3 (a 16.7° slope).
constexpr double kSlope = 0.3;
double tilted(double x, double /*y*/)
{
    return kSlope * x - 2e-3;
}

struct PushFigures {
    bool slipped = false;
    double peakStickRatio = 0.0; ///< Largest Ft/Fn while the proxy held, before the first slip.
    double stickDrift = 0.0;     ///< Largest move of the proxy while it held, m.
    double slideRatioMin = 1e9;  ///< Ft/Fn while sliding.
    double slideRatioMax = 0.0;
    double maxTangentAlongPush = -1e9; ///< Largest F·u (the force must resist the push: < 0).
    int slideUpdates = 0;
};

/// Presses the HIP 2 mm (along the normal) into the tilted plane, then pushes it up the slope along
/// the plane's tangent at 2 mm/s for 2 s, keeping its depth. Forces are split along the plane's
/// true normal.
PushFigures pushSideways(Method method, double staticMu, double dynamicMu)
{
    const SceneBox box{};
    const test::OwnedFrame frame = test::makeFrame(box, 320, 240, 0.0, tilted);
    RendererConfig cfg = RendererConfig::forMethod(method);
    cfg.staticFriction = staticMu;
    cfg.dynamicFriction = dynamicMu;
    auto made = makeRenderer(method, cfg, 320, 240);
    EXPECT_TRUE(made);
    HapticRenderer &r = **made;
    const DepthFrameView view = frame.view();
    EXPECT_TRUE(r.setFrames(view, nullptr));
    const double norm = std::sqrt(1.0 + kSlope * kSlope);
    const glm::dvec3 n(-kSlope / norm, 0.0, 1.0 / norm); // out of the surface
    const glm::dvec3 u(1.0 / norm, 0.0, kSlope / norm);  // up the slope, in the surface
    const glm::dvec3 p0(0.0, 0.0, tilted(0.0, 0.0));
    const double depth = 2e-3;
    const double speed = 2e-3; // m/s
    r.reset(p0 + 3e-3 * n);
    PushFigures f;
    glm::dvec3 stuckAt(0.0);
    const int press = 200;
    const int hold = 50;
    const int push = 2000;
    for (int i = 0; i < press + hold + push; ++i) {
        const double t = i / 1000.0;
        glm::dvec3 hip;
        if (i < press)
            hip = p0 + (3e-3 - (3e-3 + depth) * (i + 1) / press) * n;
        else
            hip = p0 - depth * n + speed * std::max(0.0, t - (press + hold) / 1000.0) * u;
        const HapticOutput out = r.update(hip, t);
        if (i < press + hold) {
            stuckAt = out.proxy;
            continue;
        }
        EXPECT_TRUE(out.contact) << i;
        const double fn = glm::dot(out.force, n);
        const double ft = glm::length(out.force - fn * n);
        const double ratio = ft / fn;
        if (i > press + hold) // the HIP has moved
            f.maxTangentAlongPush = std::max(f.maxTangentAlongPush, glm::dot(out.force, u));
        if (!f.slipped && glm::length(out.proxy - stuckAt) > 5e-6)
            f.slipped = true;
        if (!f.slipped) {
            f.peakStickRatio = std::max(f.peakStickRatio, ratio);
            f.stickDrift = std::max(f.stickDrift, glm::length(out.proxy - stuckAt));
        } else {
            f.slideRatioMin = std::min(f.slideRatioMin, ratio);
            f.slideRatioMax = std::max(f.slideRatioMax, ratio);
            ++f.slideUpdates;
        }
    }
    std::printf("%s mu_s %.2f mu_d %.2f: peak stick Ft/Fn %.5f, drift %.2e m, slide Ft/Fn "
                "%.5f..%.5f over %d updates\n",
                methodName(method), staticMu, dynamicMu, f.peakStickRatio, f.stickDrift,
                f.slideRatioMin, f.slideRatioMax, f.slideUpdates);
    return f;
}

class FrictionScenarioTest : public ::testing::TestWithParam<Method> {};

TEST_P(FrictionScenarioTest, tiltedPlaneHoldsUntilStaticConeThenSlidesAtDynamic)
{
    // GIVEN a 16.7° plane, μs = 0.5, μd = 0.3, the HIP 2 mm in (Fn ≈ 1.6 N)
    // WHEN the HIP is pushed up the slope at 2 mm/s (its tangential force grows 0.2 % of 0.5·Fn
    // an update)
    const PushFigures f = pushSideways(GetParam(), kStatic, kDynamic);
    // THEN the proxy held (moved < 5 µm) until the tangential force reached 0.5·Fn (within 1 %)
    ASSERT_TRUE(f.slipped);
    EXPECT_NEAR(f.peakStickRatio, kStatic, 0.01 * kStatic);
    EXPECT_LT(f.stickDrift, 5e-6);
    // AND then slid with the tangential force at 0.3·Fn (within 1 %) for the rest of the push
    EXPECT_GT(f.slideUpdates, 1000);
    EXPECT_NEAR(f.slideRatioMin, kDynamic, 0.01 * kDynamic);
    EXPECT_NEAR(f.slideRatioMax, kDynamic, 0.01 * kDynamic);
    // AND the tangential force resisted the push
    EXPECT_LT(f.maxTangentAlongPush, 0.0);
}

TEST_P(FrictionScenarioTest, withoutFrictionTheProxyFollowsTheHip)
{
    const PushFigures f = pushSideways(GetParam(), 0.0, 0.0);
    // The frictionless god-object slides at once: the tangential force stays near zero.
    ASSERT_TRUE(f.slipped);
    EXPECT_LT(f.slideRatioMax, 0.02);
}

INSTANTIATE_TEST_SUITE_P(Renderers, FrictionScenarioTest,
                         ::testing::Values(Method::Finger, Method::Ball, Method::Modified),
                         [](const ::testing::TestParamInfo<Method> &param) {
                             return std::string(methodName(param.param));
                         });

} // namespace
} // namespace depthtouch::haptics
