/// \file
/// \brief Depth enhancement (paper §V.B): adaptive sampling, Delaunay, smoothing, re-render,
/// measures.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdint>
#include <random>

#include "depthtouch/depth/enhance.h"
#include "depthtouch/depth/filters.h"

using namespace depthtouch;
using namespace depthtouch::depth;

namespace {

/// A Gaussian bump of \a amplitude levels over a 40-level floor, centred, width 12 px.
Plane<float> bump(int w, int h, float amplitude)
{
    Plane<float> p(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double dx = x - w / 2.0;
            const double dy = y - h / 2.0;
            p.at(x, y) =
                static_cast<float>(40.0 + static_cast<double>(amplitude) *
                                              std::exp(-(dx * dx + dy * dy) / (2.0 * 144.0)));
        }
    return p;
}

Plane<float> plane(int w, int h, double a, double b, double c)
{
    Plane<float> p(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            p.at(x, y) = static_cast<float>(a + b * x + c * y);
    return p;
}

/// Uniform noise in [−amp, amp] from mt19937 (whose output sequence the standard fixes).
void addNoise(Plane<float> &p, float amp, std::uint32_t seed)
{
    std::mt19937 rng(seed);
    for (float &v : p.samples)
        v += amp * (2.0f * static_cast<float>(rng()) / 4294967295.0f - 1.0f);
}

std::size_t countIn(const std::vector<PixelPoint> &pts, int x0, int y0, int x1, int y1)
{
    std::size_t n = 0;
    for (const auto &p : pts)
        n += (p.x >= x0 && p.x < x1 && p.y >= y0 && p.y < y1) ? 1u : 0u;
    return n;
}

} // namespace

TEST(SamplePointsTest, flatAndPlanarSurfacesKeepOnlyTheCoarseGrid)
{
    // GIVEN a 65×49 flat map and a steep plane, blocks of 16
    SamplingOptions o;
    o.maxBlock = 16;
    const auto flat = samplePoints(Plane<float>(65, 49, 100.0f), o);
    const auto tilted = samplePoints(plane(65, 49, 10.0, 2.0, -1.5), o);
    // THEN only the corners of the 4×3 block grid remain: 5 × 4 points
    EXPECT_EQ(flat.size(), 20u);
    EXPECT_EQ(tilted.size(), 20u);
    // and the image corners are always included
    EXPECT_EQ(flat.front(), (PixelPoint{0, 0}));
    EXPECT_EQ(flat.back(), (PixelPoint{64, 48}));
}

TEST(SamplePointsTest, densityGrowsWithTheGradientAndATighterTolerance)
{
    SamplingOptions o;
    // WHEN the same bump is made steeper
    const std::size_t gentle = samplePoints(bump(128, 128, 10.0f), o).size();
    const std::size_t steep = samplePoints(bump(128, 128, 80.0f), o).size();
    // THEN more points are kept
    EXPECT_GT(steep, gentle + gentle / 2);
    // WHEN the tolerance tightens
    o.tolerance = 0.25f;
    const std::size_t tight = samplePoints(bump(128, 128, 10.0f), o).size();
    EXPECT_GT(tight, gentle + gentle / 2);
    // The paper-literal gradient criterion also grows with the slope, even on planes.
    SamplingOptions g;
    g.criterion = SamplingCriterion::Gradient;
    EXPECT_GT(samplePoints(plane(128, 128, 0.0, 0.5, 0.0), g).size(),
              2 * samplePoints(plane(128, 128, 0.0, 0.05, 0.0), g).size());
}

TEST(SamplePointsTest, pointsConcentrateWhereDepthChanges)
{
    // GIVEN a step edge at x = 64 (40 | 120 levels)
    Plane<float> p(128, 128);
    for (int y = 0; y < 128; ++y)
        for (int x = 0; x < 128; ++x)
            p.at(x, y) = x < 64 ? 40.0f : 120.0f;
    const auto pts = samplePoints(p, SamplingOptions{});
    // THEN a 16-px band around the edge holds far more points than an equal band far from it
    const std::size_t nearEdge = countIn(pts, 56, 0, 72, 128);
    const std::size_t farAway = countIn(pts, 0, 0, 16, 128);
    EXPECT_GT(nearEdge, 5 * farAway);
}

TEST(SamplePointsTest, theGradientCriterionFollowsTheEdgeNotItsTranspose)
{
    // GIVEN a step edge at x = 40 (40 | 120 levels), away from the image's diagonal
    Plane<float> p(128, 128);
    for (int y = 0; y < 128; ++y)
        for (int x = 0; x < 128; ++x)
            p.at(x, y) = x < 40 ? 40.0f : 120.0f;
    SamplingOptions g;
    g.criterion = SamplingCriterion::Gradient; // the paper's criterion: side x mean gradient
    const auto pts = samplePoints(p, g);
    // THEN a 16-px column band around the edge holds far more points than the row band at y = 40
    // outside it (the edge's transpose) and than a column band far from it
    const std::size_t nearEdge = countIn(pts, 32, 0, 48, 128);
    const std::size_t transposed = countIn(pts, 64, 32, 128, 48);
    const std::size_t farAway = countIn(pts, 96, 0, 112, 128);
    EXPECT_GT(nearEdge, 5 * transposed);
    EXPECT_GT(nearEdge, 5 * farAway);
}

TEST(TriangulateTest, rendersAPlaneExactlyAndCoversTheImage)
{
    // GIVEN a tilted plane and adaptively sampled points of a bumpy map (irregular triangles)
    const Plane<float> surface = plane(97, 61, 20.0, 0.7, -0.3);
    const auto pts = samplePoints(bump(97, 61, 60.0f), SamplingOptions{});
    auto mesh = triangulate(pts, surface);
    if (!mesh && mesh.error().code == Errc::NotSupported)
        GTEST_SKIP() << "built without CGAL";
    ASSERT_TRUE(mesh);
    EXPECT_EQ(mesh->vertices.size(), pts.size());
    // Euler: a triangulation of n points with h on the hull has 2n − 2 − h triangles.
    EXPECT_GT(mesh->triangles.size(), pts.size());
    // WHEN rendered
    std::size_t uncovered = 1;
    const Plane<float> r = renderMesh(*mesh, 97, 61, &uncovered);
    // THEN every pixel is covered and equals the plane
    EXPECT_EQ(uncovered, 0u);
    for (std::size_t i = 0; i < r.size(); ++i)
        ASSERT_NEAR(r.samples[i], surface.samples[i], 1e-3) << "pixel " << i;
    // AND Gaussian smoothing (a weighted plane fit) leaves a plane unchanged
    smoothHeights(*mesh, surface, SmoothOptions{});
    const Plane<float> s = renderMesh(*mesh, 97, 61);
    for (std::size_t i = 0; i < s.size(); ++i)
        ASSERT_NEAR(s.samples[i], surface.samples[i], 1e-3) << "pixel " << i;
}

TEST(TriangulateTest, refusesDegenerateInput)
{
    const Plane<float> h(10, 10, 1.0f);
    auto two = triangulate({{0, 0}, {1, 1}}, h);
    ASSERT_FALSE(two);
    if (two.error().code == Errc::NotSupported)
        GTEST_SKIP() << "built without CGAL";
    EXPECT_EQ(two.error().code, Errc::InvalidArgument);
    EXPECT_EQ(triangulate({{0, 0}, {1, 1}, {2, 2}}, h).error().code, Errc::InvalidArgument);
    EXPECT_EQ(triangulate({{0, 0}, {1, 0}, {0, 1}, {1, 0}}, h).error().code, Errc::InvalidArgument);
    EXPECT_EQ(triangulate({{0, 0}, {10, 0}, {0, 1}}, h).error().code, Errc::InvalidArgument);
}

TEST(EnhanceTest, removesNoiseOnFlatRegionsAndKeepsAStepEdge)
{
    // GIVEN a 160×120 map: a 45-level plane tilted on the left, a flat 120-level plateau on the
    // right (a 75-level step at x = 80), plus uniform noise of ±3 levels
    Plane<float> truth(160, 120);
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x)
            truth.at(x, y) = x < 80 ? static_cast<float>(45.0 + 0.1 * y) : 120.0f;
    Plane<float> noisy = truth;
    addNoise(noisy, 3.0f, 42);

    // WHEN enhanced with the defaults
    const auto r = enhance(noisy, EnhanceOptions{});
    if (!r && r.error().code == Errc::NotSupported)
        GTEST_SKIP() << "built without CGAL";
    ASSERT_TRUE(r);
    const EnhanceReport &rep = r->report;

    // THEN flat-region roughness drops to under a fifth of the input's and under half the median's
    ASSERT_GT(rep.flatPixels, 10000u);
    EXPECT_LT(rep.enhanced.roughness, 0.2 * rep.input.roughness);
    EXPECT_LT(rep.enhanced.roughness, 0.5 * rep.median.roughness);
    // AND the step keeps at least 90 % of its true contrast (63..75 levels along the edge),
    // measured on the same edge pixels
    ASSERT_GT(rep.edgePixels, 100u);
    const SurfaceMeasures ideal = measureSurface(medianFilter(noisy, EnhanceOptions{}.medianRadius),
                                                 truth, EnhanceOptions{}.measure);
    EXPECT_GT(ideal.edgeContrast, 60.0);
    EXPECT_GT(rep.enhanced.edgeContrast, 0.9 * ideal.edgeContrast);
    std::printf("points %zu of %zu, error mean %.3f max %.2f, roughness %.3f -> %.3f -> %.3f, "
                "edge contrast %.2f -> %.2f (ideal %.2f)\n",
                rep.points, rep.pixels, rep.meanAbsError, rep.maxAbsError, rep.input.roughness,
                rep.median.roughness, rep.enhanced.roughness, rep.input.edgeContrast,
                rep.enhanced.edgeContrast, ideal.edgeContrast);
    // AND few points model the scene
    EXPECT_LT(rep.pointsFraction(), 0.10);
    // AND away from the step the result is closer to the truth than the noise was (mean |noise|
    // = 1.5)
    double sumErr = 0.0;
    std::size_t n = 0;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x)
            if (std::abs(x - 80) > 4) {
                sumErr += std::fabs(static_cast<double>(r->depth.at(x, y) - truth.at(x, y)));
                ++n;
            }
    EXPECT_LT(sumErr / static_cast<double>(n), 0.5);
    EXPECT_GT(rep.maxAbsError, rep.meanAbsError);
}

TEST(EnhanceTest, refusesBadOptionsAndTinyMaps)
{
    EnhanceOptions o;
    o.sampling.tolerance = 0.0f;
    EXPECT_EQ(enhance(Plane<float>(8, 8, 1.0f), o).error().code, Errc::InvalidArgument);
    EXPECT_EQ(enhance(Plane<float>(1, 8, 1.0f), EnhanceOptions{}).error().code,
              Errc::InvalidArgument);
    const EnhanceOptions sixteen = EnhanceOptions::forScale(65535.0);
    EXPECT_FLOAT_EQ(sixteen.sampling.tolerance, 257.0f);
}
