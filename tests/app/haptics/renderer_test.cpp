#include "depthtouch/haptics/renderer.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "app/haptics/crossing_agreement.h"
#include "app/haptics/synthetic.h"
#include "depthtouch/haptics/mesh_bvh.h"

namespace depthtouch::haptics {
namespace {

using test::makeFrame;
using test::OwnedFrame;

constexpr SceneBox kBox{0.10, 0.04};

double bumpy(double x, double y)
{
    return 0.006 * std::sin(90.0 * x) * std::cos(70.0 * y) + 0.003 * std::sin(150.0 * x + 3.0 * y);
}

/// Moves the HIP from 5 mm above (x, y, zSurface) down to \a depth below it in 1 kHz steps.
HapticOutput pressDown(HapticRenderer &r, double x, double y, double zSurface, double depth,
                       double &t)
{
    HapticOutput out;
    for (double z = zSurface + 0.005; z > zSurface - depth; z -= 0.0001) {
        out = r.update({x, y, z}, t);
        t += 0.001;
    }
    out = r.update({x, y, zSurface - depth}, t);
    t += 0.001;
    return out;
}

TEST(RendererTest, pressingIntoAFlatSurfaceGivesASpringForce)
{
    // GIVEN a flat surface and the modified renderer
    const OwnedFrame f = makeFrame(kBox, 64, 48, 0.0, [](double, double) { return 0.002; });
    RendererConfig cfg;
    ProxyGraphRenderer r(cfg);
    ASSERT_TRUE(r.setFrames(f.view(), nullptr));
    const double z = r.surface().vertexZ(0, 0);
    double t = 0.0;
    r.reset({0.01, 0.005, z + 0.005});
    // WHEN the HIP is pressed 3 mm in
    const HapticOutput out = pressDown(r, 0.01, 0.005, z, 0.003, t);
    // THEN F = k·(proxy − HIP) = 800 N/m · 3 mm along +z, proxy on the surface
    EXPECT_TRUE(out.contact);
    EXPECT_NEAR(out.force.z, 800.0 * 0.003, 1e-9);
    EXPECT_NEAR(out.force.x, 0.0, 1e-12);
    EXPECT_NEAR(out.proxy.z, z, 1e-12);
    EXPECT_FALSE(out.released);
    // WHEN it lifts off (at 0.1 m/s) THEN the force is zero and the proxy follows the HIP
    HapticOutput free;
    for (double hz = z - 0.003; hz < z + 0.0002; hz += 0.0001, t += 0.001)
        free = r.update({0.01, 0.005, hz}, t);
    EXPECT_FALSE(free.released);
    EXPECT_FALSE(free.contact);
    EXPECT_EQ(free.force, glm::dvec3(0.0));
    EXPECT_EQ(free.proxy, free.hip);
}

TEST(RendererTest, forceIsClampedToTheDeviceMaximum)
{
    const OwnedFrame f = makeFrame(kBox, 32, 24, 0.0, [](double, double) { return 0.0; });
    RendererConfig cfg;
    cfg.safety = false;
    ProxyGraphRenderer r(cfg);
    ASSERT_TRUE(r.setFrames(f.view(), nullptr));
    const double z = r.surface().vertexZ(0, 0);
    double t = 0.0;
    r.reset({0.0, 0.0, z + 0.005});
    const HapticOutput out = pressDown(r, 0.0, 0.0, z, 0.015, t); // k·15 mm = 12 N
    EXPECT_NEAR(glm::length(out.force), 8.5, 1e-12);
    EXPECT_NEAR(out.proxy.z - out.hip.z, 0.015, 1e-12);
}

TEST(RendererTest, aStiffnessSetWhilePressingIsFeltInSlewedStepsWithoutATrip)
{
    // GIVEN each method pressing a flat surface 2 mm deep at the configured 800 N/m (1.6 N)
    const OwnedFrame f = makeFrame(kBox, 64, 48, 0.0, [](double, double) { return 0.002; });
    for (const Method m : {Method::Modified, Method::MeshBvh, Method::Finger}) {
        SCOPED_TRACE(methodName(m));
        RendererConfig cfg;
        auto made = makeRenderer(m, cfg, 64, 48);
        ASSERT_TRUE(made);
        HapticRenderer &r = **made;
        ASSERT_TRUE(r.setFrames(f.view(), nullptr));
        double t = 0.0;
        const double z = 0.002;
        r.reset({0.01, 0.005, z + 0.005});
        HapticOutput out = pressDown(r, 0.01, 0.005, z, 0.002, t);
        for (int i = 0; i < 50; ++i, t += 0.001)
            out = r.update({0.01, 0.005, z - 0.002}, t);
        ASSERT_NEAR(out.force.z, 800.0 * 0.002, 0.02);
        // WHEN the stiffness becomes 3000 N/m (6 N at the same depth: a jump of 4.4 N, over
        // the 2 N force-jump threshold) and then values outside the one range (stiffness.h)
        r.setStiffness(3000.0);
        r.setStiffness(3500.0);
        r.setStiffness(50.0);
        r.setStiffness(-1.0);
        r.setStiffness(std::nan(""));
        double last = out.force.z;
        double largest = 0.0;
        bool released = false;
        for (int i = 0; i < 10; ++i, t += 0.001) {
            out = r.update({0.01, 0.005, z - 0.002}, t);
            largest = std::max(largest, std::fabs(out.force.z - last));
            last = out.force.z;
            released = released || out.released;
        }
        // THEN the force is k·depth at the new k, reached in steps of at most maxForceStep,
        // and the change itself never tripped safety (the contact held)
        EXPECT_NEAR(out.force.z, 3000.0 * 0.002, 0.03);
        EXPECT_LE(largest, cfg.maxForceStep + 1e-9);
        EXPECT_GT(largest, 1.0) << "the force rose in a few steps";
        EXPECT_FALSE(released);
        EXPECT_TRUE(out.contact);
    }
}

TEST(RendererTest, dampingOpposesTheHipVelocityInContact)
{
    const OwnedFrame f = makeFrame(kBox, 32, 24, 0.0, [](double, double) { return 0.0; });
    RendererConfig cfg;
    cfg.damping = 2.0; // N·s/m
    ProxyGraphRenderer r(cfg);
    ASSERT_TRUE(r.setFrames(f.view(), nullptr));
    const double z = r.surface().vertexZ(0, 0);
    r.reset({0.0, 0.0, z + 0.001});
    (void)r.update({0.0, 0.0, z - 0.0010}, 0.000);
    // WHEN the HIP moves down at 0.1 m/s while in contact
    const HapticOutput out = r.update({0.0, 0.0, z - 0.0011}, 0.001);
    // THEN F = k·1.1 mm + b·0.1 m/s, upward
    EXPECT_NEAR(out.force.z, 800.0 * 0.0011 + 2.0 * 0.1, 1e-9);
}

TEST(RendererTest, strokingATiltedPlaneKeepsTheForceAlongItsNormal)
{
    // GIVEN an exact tilted plane (nearness linear in c, r)
    OwnedFrame f(101, 81, SampleFormat::Gray16, 0.0);
    for (int r = 0; r < 81; ++r)
        for (int c = 0; c < 101; ++c)
            f.set(c, r, static_cast<std::uint32_t>(15000 + 300 * c + 120 * r));
    ProxyGraphRenderer rend(RendererConfig{});
    ASSERT_TRUE(rend.setFrames(f.view(), nullptr));
    const HeightField &hf = rend.surface();
    const glm::dvec3 n = glm::normalize(
        glm::cross(hf.vertex(0, 1) - hf.vertex(0, 0), hf.vertex(1, 0) - hf.vertex(0, 0)));
    ASSERT_GT(n.z, 0.0);
    const double depth = 0.002;
    glm::dvec3 p(-0.03, 0.0, 0.0);
    p.z = hf.heightAt(p.x, p.y) + 0.003;
    rend.reset(p);
    double t = 0.0;
    double worst = 0.0;
    // WHEN the HIP presses 2 mm in (along −n) and strokes 60 mm across at 0.1 m/s
    for (int i = 0; i < 700; ++i, t += 0.001) {
        const double x = -0.03 + 0.0001 * std::max(0, i - 100);
        const double d = std::min(1.0, i / 100.0) * (depth + 0.003) - 0.003;
        const glm::dvec3 onSurface(x, 0.004, hf.heightAt(x, 0.004));
        const HapticOutput out = rend.update(onSurface - d * n, t);
        if (i > 100) {
            ASSERT_TRUE(out.contact) << i;
            worst = std::max(worst, glm::length(out.force - 800.0 * depth * n));
        }
    }
    // THEN the force is k·depth along the normal at every update
    EXPECT_LT(worst, 1e-9);
}

TEST(ForceStageTest, releasesOnAForceJumpAndNeverStepsAboveTheThreshold)
{
    RendererConfig cfg;
    cfg.maxForceStep = 1.0;
    ForceStage fs(cfg);
    bool contact = true;
    bool released = false;
    glm::dvec3 hip(0.0, 0.0, -0.004);
    glm::dvec3 proxy(0.0, 0.0, 0.0); // 4 mm: 3.2 N
    glm::dvec3 f = fs.apply(hip, proxy, contact, 0.0, 0.0, released);
    EXPECT_FALSE(released);
    EXPECT_NEAR(f.z, 1.0, 1e-12); // slew-limited from zero on the very first update
    for (int i = 1; i < 5; ++i)
        f = fs.apply(hip, proxy, contact, 0.001 * i, 0.0, released);
    EXPECT_NEAR(f.z, 3.2, 1e-12);
    // WHEN the proxy is thrown 10 mm up (a cut)
    proxy = glm::dvec3(0.0, 0.0, 0.010);
    f = fs.apply(hip, proxy, contact, 0.005, 0.010, released);
    // THEN safety releases the proxy to the HIP and the force unloads by at most 1 N per update
    EXPECT_TRUE(released);
    EXPECT_FALSE(contact);
    EXPECT_EQ(proxy, hip);
    EXPECT_NEAR(f.z, 2.2, 1e-12);
}

TEST(ForceStageTest, rampReseatsTheProxyAboveTheHipAndRampsTheForceIn)
{
    RendererConfig cfg;
    cfg.reengage = Reengage::Ramp;
    cfg.rampTime = 0.1;
    ForceStage fs(cfg);
    bool contact = false;
    bool released = false;
    glm::dvec3 hip(0.001, 0.002, -0.003);
    glm::dvec3 proxy = hip;
    (void)fs.apply(hip, proxy, contact, 0.0, std::nan(""), released);
    // WHEN the surface appears 5 mm above the HIP with the proxy thrown onto it elsewhere
    proxy = glm::dvec3(0.004, 0.002, 0.002);
    contact = true;
    glm::dvec3 f = fs.apply(hip, proxy, contact, 0.001, 0.002, released);
    // THEN the proxy is re-seated straight above the HIP and the force starts from zero
    EXPECT_TRUE(released);
    EXPECT_TRUE(contact);
    EXPECT_EQ(proxy, glm::dvec3(hip.x, hip.y, 0.002));
    EXPECT_NEAR(glm::length(f), 0.0, 1e-12);
    // AND ramps linearly to k·5 mm = 4 N over 0.1 s
    for (int i = 1; i <= 50; ++i)
        f = fs.apply(hip, proxy, contact, 0.001 + 0.001 * i, 0.002, released);
    EXPECT_FALSE(released);
    EXPECT_NEAR(f.z, 2.0, 1e-9);
    for (int i = 51; i <= 120; ++i)
        f = fs.apply(hip, proxy, contact, 0.001 + 0.001 * i, 0.002, released);
    EXPECT_NEAR(f.z, 4.0, 1e-12);
}

TEST(MeshBvhTest, treeQueriesAgreeWithTheGridWalk)
{
    const OwnedFrame f = makeFrame(kBox, 40, 30, 0.0, bumpy);
    MeshBvhRenderer mesh(RendererConfig::forMethod(Method::MeshBvh), 64, 64);
    ASSERT_TRUE(mesh.setFrames(f.view(), nullptr));
    EXPECT_GT(mesh.nodeCount(), 2u * 39u * 29u / 4u);
    HeightField hf(kBox);
    ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
    std::uniform_real_distribution<double> ux(-0.05, 0.05);
    std::uniform_real_distribution<double> uz(-0.01, 0.01);
    std::uniform_real_distribution<double> step(-0.004, 0.004);
    const auto segment = [&](int, std::mt19937_64 &rng) {
        const glm::dvec3 a(ux(rng), 0.7 * ux(rng), uz(rng));
        return std::pair{a, a + glm::dvec3(step(rng), step(rng), step(rng))};
    };
    const test::CrossingAgreement n = test::countAgreement(
        3, 2000, segment, [&](auto a, auto b) { return firstCrossing(hf, a, b); },
        [&](auto a, auto b) { return mesh.firstCrossingBvh(a, b); },
        [](const Crossing &grid, const Crossing &tree, glm::dvec3, glm::dvec3) {
            return grid.hit != tree.hit || (grid.hit && std::fabs(grid.t - tree.t) > 1e-9);
        });
    EXPECT_EQ(n.mismatches, 0);
    EXPECT_GT(n.hits, 50);
}

TEST(MeshBvhTest, countsTheTreeNodesItVisits)
{
    // GIVEN a 3×3 frame: 2·2·2 = 8 triangles, more than a leaf holds (4), so the root is split at
    // the median into two leaves of four
    const OwnedFrame f = makeFrame(kBox, 3, 3, 0.0, [](double, double) { return 0.002; });
    MeshBvhRenderer mesh(RendererConfig::forMethod(Method::MeshBvh), 3, 3);
    ASSERT_TRUE(mesh.setFrames(f.view(), nullptr));
    ASSERT_EQ(mesh.nodeCount(), 3u);
    // WHEN a segment passes beside the box (x beyond its half width of 5 cm)
    const Crossing beside = mesh.firstCrossingBvh({0.08, 0.0, 0.01}, {0.08, 0.0, -0.01});
    // THEN only the root was looked at, and no triangle was tested
    EXPECT_FALSE(beside.hit);
    EXPECT_EQ(beside.cellsVisited, 1);
    EXPECT_EQ(beside.cellsTested, 0);
    // WHEN a segment goes straight down through the surface at the middle sample, a corner of
    // every cell
    const Crossing through = mesh.firstCrossingBvh({0.0, 0.0, 0.01}, {0.0, 0.0, -0.01});
    // THEN the root met it and both its children were taken: three nodes; the triangles tested
    // are those of the leaves whose boxes hold the middle sample: both, eight
    EXPECT_TRUE(through.hit);
    EXPECT_EQ(through.cellsVisited, 3);
    EXPECT_EQ(through.cellsTested, 8);
}

TEST(MeshBvhTest, rendersTheSameForcesAsTheProxyGraphOnAStillFrame)
{
    const OwnedFrame f = makeFrame(kBox, 48, 36, 0.0, bumpy);
    auto mesh = makeRenderer(Method::MeshBvh, RendererConfig::forMethod(Method::MeshBvh), 48, 36);
    auto grid =
        makeRenderer(Method::ProxyGraph, RendererConfig::forMethod(Method::ProxyGraph), 48, 36);
    ASSERT_TRUE(mesh && grid);
    ASSERT_TRUE((*mesh)->setFrames(f.view(), nullptr));
    ASSERT_TRUE((*grid)->setFrames(f.view(), nullptr));
    (*mesh)->reset({-0.03, 0.0, 0.02});
    (*grid)->reset({-0.03, 0.0, 0.02});
    double worst = 0.0;
    int contacts = 0;
    for (int i = 0; i < 3000; ++i) {
        const double t = 0.001 * i;
        const glm::dvec3 hip(-0.03 + 0.00002 * i, 0.01 * std::sin(3.0 * t), 0.02 - 0.00001 * i);
        const HapticOutput a = (*mesh)->update(hip, t);
        const HapticOutput b = (*grid)->update(hip, t);
        contacts += b.contact ? 1 : 0;
        worst = std::max(worst, glm::length(a.force - b.force));
    }
    EXPECT_LT(worst, 1e-9);
    EXPECT_GT(contacts, 500);
}

TEST(RendererConfigTest, rejectsOutOfRangeParameters)
{
    RendererConfig c;
    EXPECT_TRUE(c.validate());
    c.stiffness = -1.0;
    EXPECT_FALSE(c.validate());
    c = RendererConfig{};
    c.maxForceStep = std::nan("");
    EXPECT_FALSE(c.validate());
    EXPECT_EQ(*parseMethod("mesh-bvh"), Method::MeshBvh);
    EXPECT_FALSE(parseMethod("bvh"));
    EXPECT_FALSE(makeRenderer(Method::Modified, RendererConfig{}, 1, 10));
}

TEST(RendererConfigTest, theFingerContactsAreNamedAsTouchTakesThem)
{
    // touch --finger-contact: the three names of the README's touch row, nothing else; god-object
    // is the default of a renderer's configuration, as the README's touch row says.
    EXPECT_EQ(RendererConfig{}.fingerContact, FingerContact::GodObject);
    EXPECT_EQ(*parseFingerContact("god-object"), FingerContact::GodObject);
    EXPECT_EQ(*parseFingerContact("penalty"), FingerContact::Penalty);
    EXPECT_EQ(*parseFingerContact("adaptive"), FingerContact::Adaptive);
    for (const char *bad : {"", "godobject", "Penalty", "adaptive "})
        EXPECT_FALSE(parseFingerContact(bad)) << bad;
}

} // namespace
} // namespace depthtouch::haptics

namespace depthtouch::haptics {
namespace {

// The one force limit of the renderers and the haptic task: a NaN or infinite force is zero,
// never passed on; the slew moves by at most the step and ends within the maximum.
TEST(ForceLimitTest, nonFiniteForcesBecomeZeroAndTheSlewIsBounded)
{
    const double nan = std::nan("");
    EXPECT_EQ(limitForce({nan, 0.0, 1.0}, 8.5), glm::dvec3(0.0));
    EXPECT_EQ(limitForce({0.0, INFINITY, 0.0}, 8.5), glm::dvec3(0.0));
    EXPECT_NEAR(glm::length(limitForce({30.0, 40.0, 0.0}, 8.5)), 8.5, 1e-12);
    EXPECT_EQ(limitForce({1.0, 2.0, 2.0}, 8.5), glm::dvec3(1.0, 2.0, 2.0));
    const glm::dvec3 prev(0.0, 0.0, 4.0);
    // toward NaN: toward zero, by at most the step
    const glm::dvec3 a = slewForce(prev, {nan, nan, nan}, 2.0, 8.5);
    EXPECT_NEAR(a.z, 2.0, 1e-12);
    const glm::dvec3 b = slewForce(prev, {0.0, 0.0, 100.0}, 10.0, 8.5);
    EXPECT_NEAR(b.z, 8.5, 1e-12);
}

} // namespace
} // namespace depthtouch::haptics
