/// \file
/// \brief Per-pixel haptic materials (scene/material.h, haptics/material_field.h): the coding, the
/// lookup interpolated in space and time (paper Eq. 1), and the scenarios of docs/materials.md in
/// the `finger`, `ball` and `modified` renderers: a stiffness boundary (400 → 1200 N/m) crossed at
/// 10 cm/s with no force step above the safety threshold, and the friction cone driven by the
/// material's μs and μd as it is by the renderer's own (within 1 %).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "app/haptics/synthetic.h"
#include "depthtouch/haptics/material_field.h"
#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics {
namespace {

/// A W×H material image (RGB24 codes) whose codes are chosen per column.
class OwnedMaterial {
public:
    OwnedMaterial(int w, int h, const std::function<Material(int c)> &byColumn)
        : w_(w), bytes_(static_cast<std::size_t>(w) * 3 * static_cast<std::size_t>(h))
    {
        for (int r = 0; r < h; ++r)
            for (int c = 0; c < w; ++c)
                scene::encodeMaterial(byColumn(c),
                                      &bytes_[static_cast<std::size_t>(r * w + c) * 3]);
    }
    [[nodiscard]] scene::MaterialView view() const
    {
        return {bytes_.data(), static_cast<std::size_t>(w_) * 3};
    }

private:
    int w_;
    std::vector<std::uint8_t> bytes_;
};

TEST(MaterialCodingTest, codesRoundTripAndClampAtTheEdgesOfTheRange)
{
    std::uint8_t rgb[3];
    scene::encodeMaterial({3.0, 0.5, 0.3}, rgb);
    EXPECT_EQ(rgb[0], 192);
    EXPECT_EQ(rgb[1], 50);
    EXPECT_EQ(rgb[2], 30);
    const Material m = scene::decodeMaterial(rgb[0], rgb[1], rgb[2]);
    EXPECT_DOUBLE_EQ(m.stiffnessScale, 3.0);
    EXPECT_DOUBLE_EQ(m.staticFriction, 0.5);
    EXPECT_DOUBLE_EQ(m.dynamicFriction, 0.3);
    scene::encodeMaterial({9.0, -1.0, std::nan("")}, rgb);
    EXPECT_EQ(rgb[0], 255);
    EXPECT_EQ(rgb[1], 0);
    EXPECT_EQ(rgb[2], 0);
    EXPECT_EQ(scene::kUnitStiffnessCode, 64);
    EXPECT_DOUBLE_EQ(scene::decodeMaterial(scene::kUnitStiffnessCode, 0, 0).stiffnessScale, 1.0);
}

TEST(MaterialFieldTest, bilinearInSpaceAndEq1InTime)
{
    const SceneBox box{};
    const int w = 11;
    const int h = 9;
    test::OwnedFrame d0 = test::makeFrame(box, w, h, 0.0, [](double, double) { return 0.0; });
    test::OwnedFrame d1 = test::makeFrame(box, w, h, 0.1, [](double, double) { return 0.0; });
    // Frame i: stiffness scale 1 left of column 5, 2 from it; frame i+1: 3 everywhere.
    const OwnedMaterial m0(w, h, [](int c) { return Material{c < 5 ? 1.0 : 2.0, 0.2, 0.1}; });
    const OwnedMaterial m1(w, h, [](int) { return Material{3.0, 0.6, 0.5}; });
    DepthFrameView v0 = d0.view();
    DepthFrameView v1 = d1.view();
    HeightField field(box);
    const Material fallback{1.0, 0.7, 0.4};
    ASSERT_TRUE(field.setFrames(v0, &v1));
    // GIVEN frames without material THEN the fallback
    EXPECT_DOUBLE_EQ(materialAt(field, 0.0, 0.0, fallback).staticFriction, 0.7);
    v0.material = m0.view();
    v1.material = m1.view();
    ASSERT_TRUE(field.setFrames(v0, &v1));
    field.setTime(0.0, true);
    // WHEN half-way between columns 4 and 5 THEN the mean of 1 and 2
    const double x45 = 0.5 * (test::sampleX(box, w, 4) + test::sampleX(box, w, 5));
    EXPECT_NEAR(materialAt(field, x45, 0.0, fallback).stiffnessScale, 1.5, 1e-12);
    EXPECT_NEAR(materialAt(field, test::sampleX(box, w, 2), 0.0, fallback).stiffnessScale, 1.0,
                1e-12);
    // AND a quarter of the way to frame i+1 (t = 0.025 s) a quarter of the way to its codes
    field.setTime(0.025, true);
    const Material q = materialAt(field, test::sampleX(box, w, 2), 0.0, fallback);
    EXPECT_NEAR(q.stiffnessScale, 1.0 + 0.25 * (3.0 - 1.0), 1e-12);
    EXPECT_NEAR(q.staticFriction, 0.2 + 0.25 * (0.6 - 0.2), 1e-12);
    EXPECT_NEAR(q.dynamicFriction, 0.1 + 0.25 * (0.5 - 0.1), 1e-12);
    // AND sample-and-hold without interpolation; points off the grid take the border
    field.setTime(0.025, false);
    EXPECT_NEAR(materialAt(field, 1.0, 1.0, fallback).stiffnessScale, 2.0, 1e-12);
    // AND a material row stride shorter than a row is refused
    v0.material.strideBytes = 3 * w - 1;
    EXPECT_FALSE(field.setFrames(v0, &v1));
}

std::string methodLabel(const ::testing::TestParamInfo<Method> &param)
{
    return methodName(param.param);
}

class MaterialScenarioTest : public ::testing::TestWithParam<Method> {};

/// What a finger felt crossing a material boundary (Crossing::cross()).
struct Crossing {
    double leftFz = 0.0;  ///< Fz on the left half (scale 1), N.
    double fz = 0.0;      ///< Fz at the end, on the right half, N.
    double maxStep = 0.0; ///< Largest |ΔF| an update, N.
    bool released = false;
};

/// GIVEN a flat surface, --stiffness \a k (N/m), the left half at material scale 1 and the right
/// at \a right, the HIP pressed \a depth (m) in; WHEN it glides 4 cm along +x at \a speed (m/s)
/// across the boundary at x = 0 at 1 kHz. Every update is in contact (EXPECT).
Crossing cross(Method method, double k, double right, double depth, double speed)
{
    const SceneBox box{};
    const int w = 320;
    const int h = 240;
    const test::OwnedFrame frame =
        test::makeFrame(box, w, h, 0.0, [](double, double) { return 0.0; });
    const OwnedMaterial mat(w, h, [w, right](int c) {
        return Material{c < w / 2 ? 1.0 : right, 0.0, 0.0};
    });
    RendererConfig cfg = RendererConfig::forMethod(method);
    cfg.stiffness = k;
    cfg.damping = 0.0;
    auto made = makeRenderer(method, cfg, w, h);
    EXPECT_TRUE(made);
    if (!made)
        return {};
    HapticRenderer &r = **made;
    DepthFrameView view = frame.view();
    view.material = mat.view();
    EXPECT_TRUE(r.setFrames(view, nullptr));
    const double x0 = -0.02;
    r.reset({x0, 0.0, 3e-3});
    Crossing c;
    glm::dvec3 prev(0.0);
    int t = 0;
    for (; t < 100; ++t) { // press in 0.1 s
        const HapticOutput out =
            r.update({x0, 0.0, 3e-3 - (3e-3 + depth) * (t + 1) / 100.0}, t / 1000.0);
        prev = out.force;
    }
    const int updates = static_cast<int>(0.04 / speed * 1000.0);
    for (int i = 0; i < updates; ++i, ++t) { // 4 cm across the boundary at x = 0
        const double x = x0 + speed * i / 1000.0;
        const HapticOutput out = r.update({x, 0.0, -depth}, t / 1000.0);
        EXPECT_TRUE(out.contact) << i;
        c.released = c.released || out.released;
        c.maxStep = std::max(c.maxStep, glm::length(out.force - prev));
        prev = out.force;
        c.fz = out.force.z;
        if (x < -0.005)
            c.leftFz = c.fz;
    }
    return c;
}

TEST_P(MaterialScenarioTest, stiffnessBoundaryCrossedAtTenCmPerSecondStaysUnderTheSafetyStep)
{
    // GIVEN --stiffness 400 N/m, the right half at scale 3 (1200 N/m), the HIP pressed 2 mm in
    const double depth = 2e-3;
    const Crossing c = cross(GetParam(), 400.0, 3.0, depth, 0.1);
    std::printf("%s: Fz %.4f N on 400 N/m, %.4f N on 1200 N/m, largest step %.4f N/update\n",
                methodName(GetParam()), c.leftFz, c.fz, c.maxStep);
    // THEN the force is k·depth on each side (within 1 %)
    EXPECT_NEAR(c.leftFz, 400.0 * depth, 0.01 * 400.0 * depth);
    EXPECT_NEAR(c.fz, 1200.0 * depth, 0.01 * 1200.0 * depth);
    // AND no step of the force reached the safety threshold, nothing tripped
    EXPECT_LT(c.maxStep, RendererConfig{}.maxForceStep);
    EXPECT_FALSE(c.released);
}

// The fingertip renderer under a deep press: 6.8 mm into a surface whose material goes from 675 to
// 525 N/m (the demo's head beside its curtain), crossed at 30 cm/s. The bilinear material changes
// over a pixel, in about one update: the force stepped by Δk·depth = 1.04 N. The material's scale
// now moves at most by what changes the force by maxForceStep/8 an update (the rate the output
// stage takes a surface changing under a pressed finger); the force still ends at k·depth.
TEST(MaterialFingerTest, aDeepPressCrossingASofterMaterialChangesItsForceAtTheUnloadRate)
{
    const double depth = 6.8e-3;
    const Crossing c = cross(Method::Finger, 675.0, 525.0 / 675.0, depth, 0.3);
    std::printf("finger 6.8 mm deep at 30 cm/s: Fz %.3f N on 675 N/m, %.3f N on 525 N/m, largest "
                "step %.3f N/update\n",
                c.leftFz, c.fz, c.maxStep);
    EXPECT_NEAR(c.leftFz, 675.0 * depth, 0.01 * 675.0 * depth);
    EXPECT_NEAR(c.fz, 525.0 * depth, 0.01 * 525.0 * depth);
    EXPECT_LE(c.maxStep, RendererConfig{}.maxForceStep / 8.0 + 0.01);
    EXPECT_FALSE(c.released);
}

/// Presses 2 mm into a flat surface whose material is \a mat (per column), then pushes the HIP
/// along +x at 2 mm/s for 2 s. \return the largest Ft/Fn before the first slip and the range of
/// Ft/Fn while sliding.
struct Push {
    double stickPeak = 0.0;
    double slideMin = 1e9;
    double slideMax = 0.0;
    int slideUpdates = 0;
};
Push pushAcross(Method method, const RendererConfig &cfg, const std::function<Material(int)> &mat)
{
    const SceneBox box{};
    const int w = 320;
    const int h = 240;
    const test::OwnedFrame frame =
        test::makeFrame(box, w, h, 0.0, [](double, double) { return -2e-3; });
    const OwnedMaterial m(w, h, mat);
    auto made = makeRenderer(method, cfg, w, h);
    EXPECT_TRUE(made);
    HapticRenderer &r = **made;
    DepthFrameView view = frame.view();
    view.material = m.view();
    EXPECT_TRUE(r.setFrames(view, nullptr));
    Push p;
    glm::dvec3 stuck(0.0);
    bool slipped = false;
    r.reset({0.0, 0.0, 1e-3});
    for (int i = 0; i < 2250; ++i) {
        const double t = i / 1000.0;
        const double z = i < 200 ? 1e-3 - 5e-3 * (i + 1) / 200.0 : -4e-3;
        const double x = 2e-3 * std::max(0.0, t - 0.25);
        const HapticOutput out = r.update({x, 0.0, z}, t);
        if (i < 250) {
            stuck = out.proxy;
            continue;
        }
        const double ratio = std::hypot(out.force.x, out.force.y) / out.force.z;
        slipped = slipped || glm::length(out.proxy - stuck) > 5e-6;
        if (!slipped) {
            p.stickPeak = std::max(p.stickPeak, ratio);
        } else {
            p.slideMin = std::min(p.slideMin, ratio);
            p.slideMax = std::max(p.slideMax, ratio);
            ++p.slideUpdates;
        }
    }
    return p;
}

TEST_P(MaterialScenarioTest, materialFrictionHoldsAndSlidesAsTheRenderersOwn)
{
    // GIVEN the renderer frictionless and the material μs = 0.5, μd = 0.3 everywhere
    RendererConfig cfg = RendererConfig::forMethod(GetParam());
    cfg.damping = 0.0;
    const Push p = pushAcross(GetParam(), cfg, [](int) { return Material{1.0, 0.5, 0.3}; });
    std::printf("%s: material friction stick peak %.5f, slide %.5f..%.5f over %d updates\n",
                methodName(GetParam()), p.stickPeak, p.slideMin, p.slideMax, p.slideUpdates);
    // THEN the proxy held until Ft reached 0.5·Fn, then slid at 0.3·Fn (within 1 %)
    EXPECT_NEAR(p.stickPeak, 0.5, 0.005);
    EXPECT_GT(p.slideUpdates, 1000);
    EXPECT_NEAR(p.slideMin, 0.3, 0.003);
    EXPECT_NEAR(p.slideMax, 0.3, 0.003);
    // AND the same push with the renderer's own μs, μd and no material gives the same figures
    cfg.staticFriction = 0.5;
    cfg.dynamicFriction = 0.3;
    const Push own = pushAcross(GetParam(), cfg, [](int) { return Material{1.0, 0.5, 0.3}; });
    EXPECT_NEAR(own.stickPeak, p.stickPeak, 0.005);
    EXPECT_NEAR(own.slideMax, p.slideMax, 0.003);
}

TEST_P(MaterialScenarioTest, aFrictionlessMaterialOverridesTheRenderersFriction)
{
    // GIVEN --static-friction 0.5 but a material track with μ = 0 (ice)
    RendererConfig cfg = RendererConfig::forMethod(GetParam());
    cfg.damping = 0.0;
    cfg.staticFriction = 0.5;
    cfg.dynamicFriction = 0.3;
    const Push p = pushAcross(GetParam(), cfg, [](int) { return Material{1.0, 0.0, 0.0}; });
    // THEN the per-pixel material wins: the proxy follows with no tangential force
    EXPECT_LT(p.stickPeak, 0.02);
    EXPECT_LT(p.slideMax, 0.02);
}

INSTANTIATE_TEST_SUITE_P(Renderers, MaterialScenarioTest,
                         ::testing::Values(Method::Finger, Method::Ball, Method::Modified),
                         methodLabel);

} // namespace
} // namespace depthtouch::haptics
