// The proxy descent's shortcuts (one triangle across an edge, the star of a vertex computed once,
// triangles the HIP is not ahead of skipped, closest points from the corner) against the plain
// god-object descent that tries every triangle around the feature with the general closest-point
// routine: same optimum, on bumpy surfaces, flat plateaus and near the grid's borders.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "app/haptics/synthetic.h"
#include "depthtouch/haptics/proxy_solver.h"

namespace depthtouch::haptics {
namespace {

using test::OwnedFrame;

constexpr SceneBox kBox{0.10, 0.04};

/// The plain descent (the method documented in proxy_solver.h, with no shortcut): from the feature
/// the closest point lies on, every other triangle around its first vertex that also has its second
/// vertex (edge) is tried, and the proxy moves to the nearest by more than the tolerance.
ProxySolution plainDescent(const HeightField &surf, const TriangleId &start, const glm::dvec3 &hip)
{
    const int w = surf.columns();
    const int h = surf.rows();
    auto closestOn = [&](const TriangleId &tri, TriangleRegion &rg) {
        glm::dvec3 v[3];
        triangleVertices(surf, tri, v);
        return closestPointOnTriangle(hip, v[0], v[1], v[2], rg);
    };
    auto hasVertex = [](const TriangleId &tri, int vc, int vr) {
        for (int k = 0; k < 3; ++k) {
            int c = 0;
            int r = 0;
            triangleVertex(tri, k, c, r);
            if (c == vc && r == vr)
                return true;
        }
        return false;
    };
    ProxySolution sol;
    sol.triangle = start;
    TriangleRegion region{};
    sol.point = closestOn(start, region);
    double best = glm::dot(sol.point - hip, sol.point - hip);
    const double tol = kDescentTolerance * surf.spacing();
    for (; sol.steps < kMaxProxySteps && region != TriangleRegion::Face; ++sol.steps) {
        const int ka = region == TriangleRegion::EdgeAB || region == TriangleRegion::VertexA ? 0
                       : region == TriangleRegion::EdgeBC || region == TriangleRegion::VertexB
                           ? 1
                           : 2;
        const int kb = region == TriangleRegion::EdgeAB   ? 1
                       : region == TriangleRegion::EdgeBC ? 2
                       : region == TriangleRegion::EdgeCA ? 0
                                                          : -1;
        int ac = 0;
        int ar = 0;
        int bc = 0;
        int br = 0;
        triangleVertex(sol.triangle, ka, ac, ar);
        if (kb >= 0)
            triangleVertex(sol.triangle, kb, bc, br);
        const TriangleId around[6] = {{ac, ar, 0},         {ac, ar, 1},         {ac - 1, ar, 0},
                                      {ac - 1, ar - 1, 0}, {ac - 1, ar - 1, 1}, {ac, ar - 1, 1}};
        TriangleId bestTri = sol.triangle;
        glm::dvec3 bestPoint = sol.point;
        TriangleRegion bestRegion = region;
        double bestD = best;
        const double need = best * (1.0 - 1e-12) - tol * tol;
        for (const TriangleId &t : around) {
            if (t.c < 0 || t.c > w - 2 || t.r < 0 || t.r > h - 2 || t == sol.triangle)
                continue;
            if (kb >= 0 && !hasVertex(t, bc, br))
                continue;
            TriangleRegion rg{};
            const glm::dvec3 q = closestOn(t, rg);
            const double d = glm::dot(q - hip, q - hip);
            if (d < need && d < bestD) {
                bestD = d;
                bestTri = t;
                bestPoint = q;
                bestRegion = rg;
            }
        }
        if (bestTri == sol.triangle)
            break;
        sol.triangle = bestTri;
        sol.point = bestPoint;
        region = bestRegion;
        best = bestD;
    }
    sol.constraints = region == TriangleRegion::Face ? 1
                      : region == TriangleRegion::EdgeAB || region == TriangleRegion::EdgeBC ||
                              region == TriangleRegion::EdgeCA
                          ? 2
                          : 3;
    return sol;
}

TEST(ProxyDescentTest, shortcutsReachThePlainDescentsOptimum)
{
    // GIVEN 24×18 16-bit surfaces: random bumps, a random bumpy plateau with steps, and a tilted
    // plane (so the proxy slides into the borders and corners)
    std::mt19937 rng(12345);
    std::uniform_int_distribution<int> bump(0, 4000);
    const int w = 24;
    const int h = 18;
    const OwnedFrame frames[3] = {
        test::makeFrame(kBox, w, h, 0.0,
                        [&](double, double) { return 0.002 * (bump(rng) / 4000.0 - 0.5); }),
        test::makeFrame(kBox, w, h, 0.0,
                        [&](double x, double) {
                            return (x > 0.0 ? 0.003 : 0.0) + 0.0002 * (bump(rng) % 3);
                        }),
        test::makeFrame(kBox, w, h, 0.0,
                        [](double x, double y) { return 0.2 * x - 0.1 * y; }),
    };
    std::uniform_real_distribution<double> ux(-0.06, 0.06);
    std::uniform_real_distribution<double> uy(-0.045, 0.045);
    std::uniform_real_distribution<double> depth(0.0001, 0.006);
    int cases = 0;
    int identical = 0;
    long steps = 0;
    int vertexEnds = 0;
    for (const OwnedFrame &f : frames) {
        HeightField hf(kBox);
        ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
        for (int i = 0; i < 2000; ++i) {
            // WHEN the proxy slides from a random triangle towards a HIP under the surface
            // (possibly beyond the border)
            const double sx = std::clamp(ux(rng), -0.0499, 0.0499);
            const double sy = std::clamp(uy(rng), -0.036, 0.036);
            const TriangleId start = hf.triangleAt(sx, sy);
            const double hx = ux(rng);
            const double hy = uy(rng);
            const double ground = hf.contains(hx, hy) ? hf.heightAt(hx, hy) : 0.0;
            const glm::dvec3 hip(hx, hy, ground - depth(rng));
            const ProxySolution fast = solveProxy(hf, start, hip);
            const ProxySolution plain = plainDescent(hf, start, hip);
            // THEN both stop at the same point (up to rounding), after the same triangles
            const double dFast = glm::length(fast.point - hip);
            const double dPlain = glm::length(plain.point - hip);
            EXPECT_NEAR(dFast, dPlain, 1e-9 * hf.spacing()) << "case " << i;
            EXPECT_LT(glm::length(fast.point - plain.point), 1e-6 * hf.spacing()) << "case " << i;
            EXPECT_EQ(fast.steps, plain.steps) << "case " << i;
            EXPECT_EQ(fast.constraints, plain.constraints) << "case " << i;
            // AND the proxy is on the surface
            EXPECT_NEAR(fast.point.z, hf.heightAt(fast.point.x, fast.point.y), 1e-9 * hf.spacing());
            ++cases;
            identical += fast.triangle == plain.triangle ? 1 : 0;
            steps += plain.steps;
            vertexEnds += plain.constraints == 3 ? 1 : 0;
        }
    }
    EXPECT_EQ(cases, 6000);
    // AND the cases are not trivial: the proxy crossed triangles and also stopped at vertices
    EXPECT_GT(steps, 5L * cases) << steps;
    EXPECT_GT(vertexEnds, 100) << vertexEnds;
    // Ties between triangles sharing the closest point may be broken either way; rarely.
    EXPECT_GT(identical, cases * 99 / 100);
}

} // namespace
} // namespace depthtouch::haptics
