/// \file
/// \brief The fingertip model's parameter table (finger_renderer.h FingerParameters): every
/// threshold derived from the physical parameters, and a run-time stiffness change that changes
/// the forces, not when the finger is in contact or where its proxy is.

#include <cmath>
#include <functional>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "app/haptics/synthetic.h"
#include "depthtouch/haptics/finger_renderer.h"
#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics {
namespace {

using test::makeFrame;
using test::OwnedFrame;

TEST(FingerParametersTest, TheTableIsDerivedFromThePhysicalParameters)
{
    // The defaults: a 0.1 m × 0.04 m box, r = 1.5 % of its width, k = 800 N/m, ΔF = 2 N.
    const FingerParameters p = fingerParameters(RendererConfig::forMethod(Method::Finger));
    EXPECT_DOUBLE_EQ(p.radius, 1.5e-3);
    EXPECT_DOUBLE_EQ(p.stiffness, 800.0);
    EXPECT_DOUBLE_EQ(p.maxForceStep, 2.0);
    EXPECT_DOUBLE_EQ(p.boxDepth, 0.04);
    // ΔF/k = 2.5 mm; the capture depth is the larger of it and a tenth of the box (4 mm).
    EXPECT_DOUBLE_EQ(p.captureDepth, 4e-3);
    EXPECT_DOUBLE_EQ(p.stepDepth, 2.5e-3 / 4);
    EXPECT_DOUBLE_EQ(p.pushDepth, 2.5e-3 / 16);
    EXPECT_DOUBLE_EQ(p.unloadDepth, 2.5e-3 / 8);
    // The offset filter's step: three bounded pushes, 0.375 N of force at k.
    EXPECT_DOUBLE_EQ(p.filterStep, 3 * 2.5e-3 / 16);
    EXPECT_NEAR(p.stiffness * p.filterStep, 0.375, 1e-12);
    EXPECT_DOUBLE_EQ(p.unloadForce, 0.25);
    EXPECT_DOUBLE_EQ(p.glideReach, 1.5e-3 / 4);
    EXPECT_DOUBLE_EQ(p.holdReach, 1.5e-3 / 2);
    EXPECT_DOUBLE_EQ(p.rimReach, 1.5e-3 * 3 / 4);
    // An unload step of the depth is the force's unload step at k.
    EXPECT_NEAR(p.stiffness * p.unloadDepth, p.unloadForce, 1e-12);
    // The adaptive contact's speeds: the radius over the depth memory (0.1 s), twice that, and
    // the time a glide reach takes at the rest speed.
    EXPECT_DOUBLE_EQ(p.restSpeed, 1.5e-3 / 0.1);
    EXPECT_DOUBLE_EQ(p.slideSpeed, 2 * 1.5e-3 / 0.1);
    EXPECT_NEAR(p.speedTime, 0.025, 1e-15);
    // A wall is located to ΔF/(1024k): a force error under ΔF/1024.
    EXPECT_NEAR(p.stiffness * p.searchResolution, 2.0 / 1024, 1e-15);

    // A stiff surface and a coarse step limit: ΔF/k = 10 mm is deeper than a tenth of the box.
    RendererConfig c = RendererConfig::forMethod(Method::Finger);
    c.stiffness = 400.0;
    c.maxForceStep = 4.0;
    c.fingerRadius = 2e-3;
    const FingerParameters q = fingerParameters(c);
    EXPECT_DOUBLE_EQ(q.captureDepth, 10e-3);
    EXPECT_DOUBLE_EQ(q.pushDepth, 10e-3 / 16);
    EXPECT_DOUBLE_EQ(q.filterStep, 3 * 10e-3 / 16);
    EXPECT_DOUBLE_EQ(q.unloadForce, 0.5);
    EXPECT_DOUBLE_EQ(q.rimReach, 1.5e-3);
}

/// A finger pressed 1 mm into a table at z = 0, then a surface that rises under it: 1 mm in one
/// frame (a ramped step), then 0.5 mm a frame for 4 frames (each a step the bounded push follows
/// at pushDepth an update). 4 mm deep at the end: 6.4 N at 1600 N/m, under the device maximum.
/// \a stiffen: the viewer doubles the stiffness once the finger rests.
std::vector<HapticOutput> pressUnderARisingSurface(bool stiffen)
{
    constexpr SceneBox box{};
    FingerRenderer finger(RendererConfig::forMethod(Method::Finger));
    std::vector<HapticOutput> out;
    long n = 0;
    OwnedFrame frame;
    const auto show = [&](double z) {
        frame = makeFrame(
            box, 320, 240, 0.0, [z](double, double) { return z; }, SampleFormat::Gray16);
        EXPECT_TRUE(finger.setFrames(frame.view(), nullptr));
    };
    const glm::dvec3 hip(0.0, 0.0, -0.001);
    const auto step = [&](const glm::dvec3 &at) {
        out.push_back(finger.update(at, static_cast<double>(n++) * 1e-3));
    };
    show(0.0);
    finger.reset(hip + glm::dvec3(0, 0, 0.005));
    for (int k = 1; k <= 50; ++k)
        step(hip + glm::dvec3(0, 0, 0.005 * (1.0 - k / 50.0)));
    for (int k = 0; k < 100; ++k)
        step(hip);
    if (stiffen)
        finger.setStiffness(1600.0);
    for (int k = 0; k < 100; ++k)
        step(hip);
    show(0.001);
    for (int k = 0; k < 300; ++k)
        step(hip);
    for (int f = 1; f <= 4; ++f) {
        show(0.001 + 0.0005 * f);
        for (int k = 0; k < 50; ++k)
            step(hip);
    }
    return out;
}

TEST(FingerParametersTest, AStiffnessChangeChangesTheForceNotTheContactNorTheProxy)
{
    // GIVEN the same press and the same rising surface, once at 800 N/m throughout and once with
    // the stiffness doubled while the finger rests
    const std::vector<HapticOutput> same = pressUnderARisingSurface(false);
    const std::vector<HapticOutput> stiff = pressUnderARisingSurface(true);
    ASSERT_EQ(same.size(), stiff.size());
    // THEN the contact and the proxy are the same at every update (when the finger is in contact,
    // how deep a step is ramped in and how fast the push grows are geometry: the parameter table),
    std::size_t compared = 0;
    for (std::size_t i = 0; i < same.size(); ++i) {
        ASSERT_EQ(same[i].contact, stiff[i].contact) << i;
        ASSERT_EQ(same[i].released, stiff[i].released) << i;
        ASSERT_NEAR(glm::length(same[i].proxy - stiff[i].proxy), 0.0, 1e-12) << i;
        // AND once the force stage's step limit has brought the command to the new stiffness, the
        // force is twice as large.
        if (i > 200 && same[i].contact && glm::length(same[i].force) > 0.1 &&
            glm::length(stiff[i].force) < 8.0) {
            const double ratio = glm::length(stiff[i].force) / glm::length(same[i].force);
            EXPECT_NEAR(ratio, 2.0, 0.02) << i;
            ++compared;
        }
    }
    EXPECT_GT(compared, 300u);
    // AND the surface did push the finger: the depth grew over the run.
    EXPECT_GT(glm::length(same.back().proxy - same.back().hip), 0.003);
}

} // namespace
} // namespace depthtouch::haptics
