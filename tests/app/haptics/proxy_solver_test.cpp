#include "depthtouch/haptics/proxy_solver.h"

#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <gtest/gtest.h>

#include "app/haptics/synthetic.h"
#include "depthtouch/haptics/collision.h"

namespace depthtouch::haptics {
namespace {

using test::OwnedFrame;

constexpr SceneBox kBox{0.10, 0.04};

/// A 16-bit frame whose nearness is an exact function of (c, r).
template <class F>
OwnedFrame gridFrame(int w, int h, F v)
{
    OwnedFrame f(w, h, SampleFormat::Gray16, 0.0);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c)
            f.set(c, r, static_cast<std::uint32_t>(v(c, r)));
    return f;
}

ProxySolution solveFrom(const HeightField &hf, const glm::dvec3 &above, const glm::dvec3 &hip)
{
    const Crossing c = firstCrossing(hf, above, hip);
    EXPECT_TRUE(c.hit);
    return solveProxy(hf, c.triangle, hip);
}

TEST(ProxySolverTest, closestPointRegionsOfATriangle)
{
    const glm::dvec3 a(0, 0, 0);
    const glm::dvec3 b(1, 0, 0);
    const glm::dvec3 c(0, 1, 0);
    TriangleRegion rg{};
    EXPECT_LT(glm::length(closestPointOnTriangle({0.2, 0.2, -1}, a, b, c, rg) -
                          glm::dvec3(0.2, 0.2, 0)),
              1e-15);
    EXPECT_EQ(rg, TriangleRegion::Face);
    EXPECT_EQ(closestPointOnTriangle({0.5, -1, 0}, a, b, c, rg), glm::dvec3(0.5, 0, 0));
    EXPECT_EQ(rg, TriangleRegion::EdgeAB);
    closestPointOnTriangle({1, 1, 0}, a, b, c, rg);
    EXPECT_EQ(rg, TriangleRegion::EdgeBC);
    EXPECT_EQ(closestPointOnTriangle({-1, -1, 3}, a, b, c, rg), a);
    EXPECT_EQ(rg, TriangleRegion::VertexA);
    EXPECT_EQ(closestPointOnTriangle({2, -0.5, 0}, a, b, c, rg), b);
    EXPECT_EQ(rg, TriangleRegion::VertexB);
}

TEST(ProxySolverTest, slidesToTheOrthogonalProjectionOnATiltedPlane)
{
    // GIVEN an exact plane (nearness linear in column and row)
    const OwnedFrame f = gridFrame(21, 15, [](int c, int r) { return 20000 + 900 * c + 400 * r; });
    HeightField hf(kBox);
    ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
    const glm::dvec3 p0 = hf.vertex(0, 0);
    const glm::dvec3 n =
        glm::normalize(glm::cross(hf.vertex(1, 0) - p0, hf.vertex(0, 1) - p0)) * -1.0;
    ASSERT_GT(n.z, 0.0);
    // WHEN the HIP is 3 mm under the plane far from where it entered
    const glm::dvec3 onPlane = hf.vertex(12, 6) + glm::dvec3(0.0011, -0.0007, 0.0);
    const glm::dvec3 surfacePoint(onPlane.x, onPlane.y, hf.heightAt(onPlane.x, onPlane.y));
    const glm::dvec3 hip = surfacePoint - 0.003 * n;
    const ProxySolution sol = solveFrom(hf, hf.vertex(5, 5) + glm::dvec3(0, 0, 0.001), hip);
    // THEN the proxy is the orthogonal projection: on one face, exactly k-independent geometry
    EXPECT_NEAR(glm::length(sol.point - surfacePoint), 0.0, 1e-12);
    EXPECT_EQ(sol.constraints, 1);
    EXPECT_GT(sol.steps, 3); // it slid across several triangles within this one update
}

TEST(ProxySolverTest, restsInAConcaveCreaseWithTwoConstraints)
{
    // GIVEN a V-shaped valley along column 10
    const OwnedFrame f =
        gridFrame(21, 15, [](int c, int) { return 20000 + 1500 * std::abs(c - 10); });
    HeightField hf(kBox);
    ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
    const glm::dvec3 bottom = hf.vertex(10, 7);
    // WHEN the HIP presses straight down under the valley line
    const glm::dvec3 hip = bottom + glm::dvec3(0.0, 0.001, -0.004);
    const ProxySolution sol = solveFrom(hf, bottom + glm::dvec3(0.003, 0.001, 0.01), hip);
    // THEN the proxy sits on the crease above the HIP
    EXPECT_NEAR(sol.point.x, bottom.x, 1e-12);
    EXPECT_NEAR(sol.point.y, hip.y, 1e-12);
    EXPECT_NEAR(sol.point.z, bottom.z, 1e-12);
    EXPECT_EQ(sol.constraints, 2);
}

TEST(ProxySolverTest, restsInAConcaveCornerWithThreeConstraints)
{
    // GIVEN a pit whose lowest point is vertex (10, 7)
    const OwnedFrame f = gridFrame(21, 15, [](int c, int r) {
        return 20000 + 1500 * std::abs(c - 10) + 1300 * std::abs(r - 7);
    });
    HeightField hf(kBox);
    ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
    const glm::dvec3 pit = hf.vertex(10, 7);
    const glm::dvec3 hip = pit + glm::dvec3(0.0, 0.0, -0.005);
    const ProxySolution sol = solveFrom(hf, pit + glm::dvec3(-0.004, 0.003, 0.02), hip);
    EXPECT_NEAR(glm::length(sol.point - pit), 0.0, 1e-12);
    EXPECT_EQ(sol.constraints, 3);
}

TEST(ProxySolverTest, staysOnAConvexRidgeWhenPressedUnderIt)
{
    // GIVEN a roof whose ridge runs along column 10
    const OwnedFrame f =
        gridFrame(21, 15, [](int c, int) { return 40000 - 1500 * std::abs(c - 10); });
    HeightField hf(kBox);
    ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
    const glm::dvec3 top = hf.vertex(10, 7);
    // WHEN pressed straight under the ridge THEN the proxy slides off the ridge onto a face: inside
    // a convex wedge the nearest surface point is on a face, at 1 mm·cos(slope), never on the edge
    const glm::dvec3 hipUnder = top + glm::dvec3(0.0, 0.0013, -0.001);
    const ProxySolution onRidge = solveFrom(hf, top + glm::dvec3(0.0, 0.0, 0.01), hipUnder);
    const double slope = (hf.vertex(10, 7).z - hf.vertex(11, 7).z) / hf.spacing();
    EXPECT_NEAR(glm::length(onRidge.point - hipUnder), 0.001 / std::sqrt(1.0 + slope * slope),
                1e-12);
    EXPECT_EQ(onRidge.constraints, 1);
    EXPECT_NEAR(onRidge.point.z, hf.heightAt(onRidge.point.x, onRidge.point.y), 1e-12);
    // WHEN pressed under one side THEN it slides down onto that side's face
    const glm::dvec3 side = hf.vertex(14, 7);
    const ProxySolution onFace =
        solveFrom(hf, top + glm::dvec3(0.0, 0.0, 0.01), side + glm::dvec3(0.0, 0.0003, -0.002));
    EXPECT_EQ(onFace.constraints, 1);
    EXPECT_GT(onFace.point.x, top.x);
    EXPECT_NEAR(onFace.point.z, hf.heightAt(onFace.point.x, onFace.point.y), 1e-12);
}

/// Amplitude of smoothWave(), m.
constexpr double kWaveA = 0.004;

/// z = 4 mm · sin(60 x) · cos(50 y) sampled at 3840 × 400 in 16 bits over kBox (26 µm spacing).
OwnedFrame smoothWave()
{
    return test::makeFrame(kBox, 3840, 400, 0.0, [](double x, double y) {
        return kWaveA * std::sin(60.0 * x) * std::cos(50.0 * y);
    });
}

/// The renderer's default coarse stride on \a hf (RendererConfig::coarseSpacing).
int defaultStride(const HeightField &hf)
{
    return static_cast<int>(std::floor((kBox.width / 719.0) / hf.spacing()));
}

TEST(ProxySolverTest, coarseToFineGivesTheFullGridDescentsForceOnASmoothSurface)
{
    // GIVEN a smooth 16-bit surface at 3840 × 400 over the default box (spacing 26 µm), and HIPs
    // pressed 2 mm in at 0.2–1.5 mm (8–58 cells) from the proxy's start triangle
    const OwnedFrame f = smoothWave();
    HeightField hf(kBox);
    ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
    const int stride = defaultStride(hf);
    ASSERT_EQ(stride, 5);
    int compared = 0;
    long fullSteps = 0;
    long coarseSteps = 0;
    for (int i = 0; i < 200; ++i) {
        const double x0 = -0.03 + 0.0003 * i;
        const double y0 = -0.002 + 0.00002 * i;
        const double step = 0.0002 + 0.0013 * (i % 7) / 6.0;
        const double ang = 0.7 * i;
        const double x1 = x0 + step * std::cos(ang);
        const double y1 = y0 + step * std::sin(ang);
        const TriangleId start = hf.triangleAt(x0, y0);
        const glm::dvec3 hip(x1, y1, hf.heightAt(x1, y1) - 0.002);
        // WHEN the proxy slides from the start triangle with and without the coarse pass
        const ProxySolution full = solveProxy(hf, start, hip);
        const ProxySolution fast = solveProxyCoarseToFine(hf, start, hip, stride, 2.0 * stride);
        // THEN both end at a god-object optimum of the same depth: a faceted surface has shallow
        // local optima along its concave edges, so the two may stop a few pixels apart, but the
        // force they give differs by < 0.1 % in magnitude and < 2° in direction
        const double dFull = glm::length(full.point - hip);
        const double dFast = glm::length(fast.point - hip);
        EXPECT_LT(std::abs(dFull - dFast), 1e-3 * dFull) << "stroke " << i;
        EXPECT_LT(glm::length(full.point - fast.point), 3.0 * hf.spacing()) << "stroke " << i;
        const double cosAngle = glm::dot(full.point - hip, fast.point - hip) / (dFull * dFast);
        EXPECT_GT(cosAngle, std::cos(2.0 * 3.14159265358979 / 180.0)) << "stroke " << i;
        EXPECT_GE(fast.point.z, hf.heightAt(fast.point.x, fast.point.y) - 1e-9 * hf.spacing());
        fullSteps += full.steps;
        coarseSteps += fast.steps;
        ++compared;
    }
    // AND the two-pass descent crossed far fewer triangles
    EXPECT_EQ(compared, 200);
    EXPECT_LT(coarseSteps * 2, fullSteps)
        << "full " << fullSteps << " coarse-to-fine " << coarseSteps;
}

TEST(ProxySolverTest, tangentPlaneGuessStepsOverTheLocalOptimaOfAQuantisedFineGrid)
{
    // GIVEN z = 4 mm · sin(60 x) · cos(50 y) at 3840 × 400 in 16 bits (26 µm cells; each facet's
    // normal is off by up to about a degree from rounding), HIPs held 3 mm under it, and the
    // previous proxy 3 cells from the optimum (where a moving surface leaves it after one update)
    constexpr double kA = kWaveA; // short name for the derivatives below
    const OwnedFrame f = smoothWave();
    HeightField hf(kBox);
    ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
    const int stride = defaultStride(hf);
    ASSERT_EQ(stride, 5);
    // The optimum of the smooth surface: Newton on |(x, y, z(x, y)) − hip|².
    auto optimum = [&](const glm::dvec3 &hip) {
        double x = hip.x;
        double y = hip.y;
        for (int it = 0; it < 20; ++it) {
            const double sx = std::sin(60.0 * x), cx = std::cos(60.0 * x);
            const double sy = std::sin(50.0 * y), cy = std::cos(50.0 * y);
            const double e = kA * sx * cy - hip.z;
            const double fx = 60.0 * kA * cx * cy, fy = -50.0 * kA * sx * sy;
            const double fxx = -3600.0 * kA * sx * cy, fyy = -2500.0 * kA * sx * cy;
            const double fxy = -3000.0 * kA * cx * sy;
            const double gx = (x - hip.x) + e * fx, gy = (y - hip.y) + e * fy;
            const double hxx = 1.0 + fx * fx + e * fxx, hyy = 1.0 + fy * fy + e * fyy;
            const double hxy = fx * fy + e * fxy;
            const double det = hxx * hyy - hxy * hxy;
            x -= (hyy * gx - hxy * gy) / det;
            y -= (hxx * gy - hxy * gx) / det;
        }
        return glm::dvec2(x, y);
    };
    double plainErr = 0.0;
    double guessErr = 0.0;
    int n = 0;
    for (int i = 0; i < 200; ++i) {
        const double x = -0.04 + 0.0004 * i;
        const double y = -0.004 + 0.00004 * i;
        const glm::dvec3 hip(x, y, hf.heightAt(x, y) - 0.003);
        const glm::dvec2 best = optimum(hip);
        const TriangleId start = hf.triangleAt(best.x + 3.0 * hf.spacing(), best.y);
        // WHEN the descent starts from the previous proxy, or at the tangent-plane guess
        const ProxySolution plain = solveProxy(hf, start, hip);
        const ProxySolution guessed = solveProxyCoarseToFine(hf, start, hip, stride, stride);
        plainErr += glm::length(glm::dvec2(plain.point) - best);
        guessErr += glm::length(glm::dvec2(guessed.point) - best);
        EXPECT_GE(guessed.point.z,
                  hf.heightAt(guessed.point.x, guessed.point.y) - 1e-9 * hf.spacing());
        ++n;
    }
    plainErr /= n;
    guessErr /= n;
    // THEN the plain descent stops in the noise's local optima on its way (about a cell from the
    // smooth optimum); the guessed one ends nearer (about 0.6 cells)
    EXPECT_LT(guessErr, 0.75 * plainErr) << "mean distance to the optimum, cells: guessed "
                                        << guessErr / hf.spacing() << ", plain "
                                        << plainErr / hf.spacing();
    EXPECT_LT(guessErr, 1.0 * hf.spacing());
    std::printf("mean distance to the smooth optimum: from the previous proxy %.2f cells, from the "
                "tangent-plane guess %.2f cells\n",
                plainErr / hf.spacing(), guessErr / hf.spacing());
}

TEST(ProxySolverTest, coarseToFineFallsBackToTheFullGridOnSmallGridsAndGuessesShortMoves)
{
    // GIVEN a tilted plane on a small grid
    const OwnedFrame f = gridFrame(16, 12, [](int c, int r) { return 20000 + 300 * c + 100 * r; });
    HeightField hf(kBox);
    ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
    const TriangleId start = hf.triangleAt(0.0, 0.0);
    const glm::dvec3 hip(0.01, 0.004, hf.heightAt(0.01, 0.004) - 0.001);
    // WHEN the grid is smaller than two coarse cells
    const ProxySolution full = solveProxy(hf, start, hip);
    const ProxySolution small = solveProxyCoarseToFine(hf, start, hip, 8, 1.0);
    // THEN the result is the full-grid descent's, step for step
    EXPECT_EQ(small.point, full.point);
    EXPECT_EQ(small.steps, full.steps);
    // WHEN the move is shorter than minCells THEN the descent starts at the tangent-plane guess,
    // which on a plane is the optimum itself: the same point, no triangle crossed
    const ProxySolution shortMove = solveProxyCoarseToFine(hf, start, hip, 2, 1000.0);
    EXPECT_LT(glm::length(shortMove.point - full.point), 1e-9 * hf.spacing());
    EXPECT_EQ(shortMove.steps, 0);
    EXPECT_GT(full.steps, 0);
}

} // namespace
} // namespace depthtouch::haptics
