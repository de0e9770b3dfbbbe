/// \file
/// \brief AdaptiveMesh: level choice, the haptic triangulation at step 1, error bound and
/// watertightness (CPU only).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <set>
#include <utility>
#include <vector>
#include <tuple>

#include "app/render/render_test_support.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/render/adaptive_mesh.h"

using namespace depthtouch;
using namespace depthtouch::render;
using test::Depth8;

namespace {

/// A smooth terrain with a few sharp bumps: flat regions, gentle slopes and steep detail.
int terrain(int c, int r)
{
    double v = 100.0 + 0.2 * c;
    const double dx = c - 70.0;
    const double dy = r - 40.0;
    v += 120.0 * std::exp(-(dx * dx + dy * dy) / 60.0);
    if (c > 20 && c < 30 && r > 50 && r < 60)
        v += 40.0;
    return static_cast<int>(std::lround(v));
}

MeshOptions adaptive(double tolerance)
{
    MeshOptions o;
    o.mode = MeshMode::Adaptive;
    o.tolerance = tolerance;
    o.criterion = ErrorCriterion::Max;
    o.tileSize = 16;
    o.maxStep = 16;
    return o;
}

} // namespace

TEST(AdaptiveMeshTest, fullResolutionIsTheHapticTriangulation)
{
    // GIVEN a 9×7 frame and a fixed step-1 mesh
    const Depth8 d(9, 7, [](int c, int r) { return 10 * c + r; });
    MeshOptions o;
    o.mode = MeshMode::Fixed;
    o.fixedStep = 1;
    AdaptiveMesh mesh;
    ASSERT_TRUE(mesh.build(d.view(), o));
    // THEN its triangles are exactly the haptic TriangleIds of every cell (same diagonal)
    std::set<std::set<std::uint32_t>> drawn;
    const auto &idx = mesh.indices();
    for (std::size_t i = 0; i < idx.size(); i += 3)
        drawn.insert({idx[i], idx[i + 1], idx[i + 2]});
    std::set<std::set<std::uint32_t>> haptic;
    for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 8; ++c)
            for (int upper = 0; upper < 2; ++upper) {
                std::set<std::uint32_t> tri;
                for (int k = 0; k < 3; ++k) {
                    int vc = 0;
                    int vr = 0;
                    haptics::triangleVertex(haptics::TriangleId{c, r, upper}, k, vc, vr);
                    tri.insert(static_cast<std::uint32_t>(vr * 9 + vc));
                }
                haptic.insert(tri);
            }
    EXPECT_EQ(drawn, haptic);
    EXPECT_EQ(mesh.stats().triangles, 2u * 8u * 6u);
}

TEST(AdaptiveMeshTest, planeUsesTheCoarsestStepWithNoError)
{
    // GIVEN an exactly planar frame (any linear interpolation reproduces it)
    const Depth8 d(100, 70, [](int c, int r) { return c + r; });
    AdaptiveMesh mesh;
    ASSERT_TRUE(mesh.build(d.view(), adaptive(0.0)));
    // THEN every tile is at step 16 and the surface has no error at all
    EXPECT_EQ(mesh.stats().tilesAtStep[4], mesh.stats().tiles);
    const MeshError e = measureMeshError(d.view(), mesh.indices());
    EXPECT_EQ(e.uncovered, 0u);
    EXPECT_NEAR(e.max, 0.0, 1e-9);
    EXPECT_LT(mesh.stats().triangles, 100u);
}

TEST(AdaptiveMeshTest, terrainMixesLevelsStaysWatertightAndNearTheTolerance)
{
    const Depth8 d(130, 90, terrain);
    for (const double tol : {0.5, 1.0, 2.0, 4.0}) {
        AdaptiveMesh mesh;
        ASSERT_TRUE(mesh.build(d.view(), adaptive(tol)));
        int levelsUsed = 0;
        for (int k : mesh.stats().tilesAtStep)
            levelsUsed += k > 0 ? 1 : 0;
        EXPECT_GE(levelsUsed, 2) << "tolerance " << tol;
        // THEN no sample falls through a crack, and the error stays near the tolerance (the
        // stitching strips interpolate between a coarse border and a finer inner row)
        const MeshError e = measureMeshError(d.view(), mesh.indices());
        EXPECT_EQ(e.uncovered, 0u) << "tolerance " << tol;
        EXPECT_LE(e.max, 2.0 * tol + 1.0) << "tolerance " << tol;
        EXPECT_LE(e.mean, tol) << "tolerance " << tol;
        // AND a larger tolerance never needs more triangles than the full mesh
        EXPECT_LT(mesh.stats().triangles, 2u * 129u * 89u);
    }
}

TEST(AdaptiveMeshTest, fixedDecimationCoversOddSizes)
{
    // GIVEN sizes that are not multiples of the tile or the step
    const Depth8 d(37, 23, terrain);
    for (const int step : {1, 2, 4, 8}) {
        MeshOptions o;
        o.mode = MeshMode::Fixed;
        o.fixedStep = step;
        o.tileSize = 8;
        AdaptiveMesh mesh;
        ASSERT_TRUE(mesh.build(d.view(), o));
        const MeshError e = measureMeshError(d.view(), mesh.indices());
        EXPECT_EQ(e.uncovered, 0u) << "step " << step;
        if (step == 1) {
            EXPECT_NEAR(e.max, 0.0, 1e-9);
        }
    }
}

TEST(AdaptiveMeshTest, errorGrowsWithTheToleranceAndTrianglesShrink)
{
    const Depth8 d(130, 90, terrain);
    std::size_t lastTriangles = SIZE_MAX;
    for (const double tol : {0.0, 1.0, 3.0, 10.0}) {
        AdaptiveMesh mesh;
        ASSERT_TRUE(mesh.build(d.view(), adaptive(tol)));
        EXPECT_LE(mesh.stats().triangles, lastTriangles) << "tolerance " << tol;
        lastTriangles = mesh.stats().triangles;
        if (tol == 0.0) {
            const MeshError e = measureMeshError(d.view(), mesh.indices());
            EXPECT_NEAR(e.max, 0.0, 1e-9) << "zero tolerance must reproduce every sample";
        }
    }
}

TEST(AdaptiveMeshTest, rejectsBadOptionsAndKeepsThePreviousMesh)
{
    const Depth8 d(20, 20, terrain);
    AdaptiveMesh mesh;
    ASSERT_TRUE(mesh.build(d.view(), adaptive(1.0)));
    const auto before = mesh.indices();
    MeshOptions bad = adaptive(1.0);
    bad.tileSize = 12;
    EXPECT_EQ(mesh.build(d.view(), bad).error().code, Errc::InvalidArgument);
    bad = adaptive(-1.0);
    EXPECT_EQ(mesh.build(d.view(), bad).error().code, Errc::InvalidArgument);
    bad = adaptive(1.0);
    bad.maxStep = 32;
    EXPECT_EQ(mesh.build(d.view(), bad).error().code, Errc::InvalidArgument);
    scene::DepthFrameView empty;
    EXPECT_EQ(mesh.build(empty, adaptive(1.0)).error().code, Errc::InvalidArgument);
    EXPECT_EQ(mesh.indices(), before);
}

TEST(AdaptiveMeshTest, meanCriterionIgnoresNoiseButKeepsEdges)
{
    // GIVEN a plane with ±1-level noise and a 40-level step edge
    const Depth8 d(129, 65,
                   [](int c, int r) { return 100 + (c * 7 + r * 3) % 3 - 1 + (c >= 64 ? 40 : 0); });
    MeshOptions mean = adaptive(0.8);
    mean.criterion = ErrorCriterion::Mean;
    mean.maxErrorCap = 4.0;
    AdaptiveMesh meshMean;
    ASSERT_TRUE(meshMean.build(d.view(), mean));
    AdaptiveMesh meshMax;
    ASSERT_TRUE(meshMax.build(d.view(), adaptive(0.8)));
    // THEN the mean criterion decimates the noisy plane far more than the max criterion
    EXPECT_LT(meshMean.stats().triangles * 4, meshMax.stats().triangles);
    const MeshError e = measureMeshError(d.view(), meshMean.indices());
    EXPECT_EQ(e.uncovered, 0u);
    EXPECT_LE(e.mean, 0.8);
    // AND the step edge stays within the cap (its tiles are not smeared over 16 samples)
    EXPECT_LE(e.max, 2.0 * 4.0 + 1.0);
}

namespace {

/// Checks that \a idx (triangles over a W×H grid) tiles the grid exactly and conformingly: every
/// triangle has the winding of the two-triangle split (positive area in image coordinates), the
/// areas add up to the grid's, and every edge inside the grid is shared by exactly two triangles
/// in opposite directions (no T-junction, hence no crack once the vertices are lifted).
void expectConformingTiling(const std::vector<std::uint32_t> &idx, int w, int h)
{
    long long area2 = 0;
    int flipped = 0;
    std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
        long long x[3];
        long long y[3];
        for (std::size_t k = 0; k < 3; ++k) {
            x[k] = idx[t + k] % static_cast<std::uint32_t>(w);
            y[k] = idx[t + k] / static_cast<std::uint32_t>(w);
            edges.insert({idx[t + k], idx[t + (k + 1) % 3]});
        }
        const long long a = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
        flipped += a <= 0 ? 1 : 0;
        area2 += a;
    }
    EXPECT_EQ(flipped, 0);
    EXPECT_EQ(area2, 2LL * (w - 1) * (h - 1));
    int open = 0;
    for (const auto &[i, j] : edges) {
        if (edges.count({j, i}) != 0)
            continue;
        const auto xi = static_cast<int>(i % static_cast<std::uint32_t>(w));
        const auto yi = static_cast<int>(i / static_cast<std::uint32_t>(w));
        const auto xj = static_cast<int>(j % static_cast<std::uint32_t>(w));
        const auto yj = static_cast<int>(j / static_cast<std::uint32_t>(w));
        const bool border =
            (xi == xj && (xi == 0 || xi == w - 1)) || (yi == yj && (yi == 0 || yi == h - 1));
        open += border ? 0 : 1;
    }
    EXPECT_EQ(open, 0) << "edges inside the grid without a twin (T-junctions)";
}

MeshOptions quadtree(double tolerance, ErrorCriterion criterion)
{
    MeshOptions o;
    o.mode = MeshMode::Quadtree;
    o.tileSize = 32;
    o.maxStep = 32;
    o.tolerance = tolerance;
    o.criterion = criterion;
    o.maxErrorCap = 16.0;
    return o;
}

} // namespace

TEST(QuadtreeMeshTest, planeIsOneBlockPerTile)
{
    // GIVEN an exactly planar frame
    const Depth8 d(100, 70, [](int c, int r) { return c + r; });
    for (const ErrorCriterion crit : {ErrorCriterion::Max, ErrorCriterion::Mean}) {
        AdaptiveMesh mesh;
        ASSERT_TRUE(mesh.build(d.view(), quadtree(0.0, crit)));
        // THEN every tile is one leaf block of two triangles and the surface is exact
        EXPECT_EQ(mesh.stats().blocks, mesh.stats().tiles);
        EXPECT_EQ(mesh.stats().triangles, 2u * static_cast<std::size_t>(mesh.stats().tiles));
        const MeshError e = measureMeshError(d.view(), mesh.indices());
        EXPECT_EQ(e.uncovered, 0u);
        EXPECT_NEAR(e.max, 0.0, 1e-9);
    }
}

TEST(QuadtreeMeshTest, mixedLevelsTileTheGridWithoutTJunctions)
{
    // GIVEN a terrain with a step edge and odd sizes (clipped tiles), both criteria, several
    // tolerances, and sizes whose last block row/column is one cell thin
    const Depth8 terrainFrame(130, 90, terrain);
    const Depth8 edge(97, 66, [](int c, int r) {
        return (c - 40) * (c - 40) + (r - 30) * (r - 30) < 300 ? 200 : 40 + c / 9;
    });
    for (const Depth8 *d : {&terrainFrame, &edge})
        for (const ErrorCriterion crit : {ErrorCriterion::Max, ErrorCriterion::Mean})
            for (const double tol : {0.3, 1.0, 4.0}) {
                AdaptiveMesh mesh;
                ASSERT_TRUE(mesh.build(d->view(), quadtree(tol, crit)));
                int sizesUsed = 0;
                for (const int n : mesh.stats().blocksAtSize)
                    sizesUsed += n > 0 ? 1 : 0;
                EXPECT_GE(sizesUsed, 3) << "tolerance " << tol;
                // THEN the triangles tile the grid conformingly, and no sample falls through
                expectConformingTiling(mesh.indices(), d->width, d->height);
                EXPECT_EQ(measureMeshError(d->view(), mesh.indices()).uncovered, 0u);
            }
}

TEST(QuadtreeMeshTest, maxCriterionBoundsEveryBlockAndFullResolutionAtZero)
{
    const Depth8 d(130, 90, terrain);
    AdaptiveMesh exact;
    ASSERT_TRUE(exact.build(d.view(), quadtree(0.0, ErrorCriterion::Max)));
    EXPECT_NEAR(measureMeshError(d.view(), exact.indices()).max, 0.0, 1e-9);
    AdaptiveMesh coarse;
    ASSERT_TRUE(coarse.build(d.view(), quadtree(2.0, ErrorCriterion::Max)));
    // Transition blocks are fanned around their middle sample: within the bound, not only the
    // two-triangle surface that was checked.
    EXPECT_LE(measureMeshError(d.view(), coarse.indices()).max, 2.0 + 1e-6);
    EXPECT_LT(coarse.stats().triangles, exact.stats().triangles / 2);
}

TEST(QuadtreeMeshTest, meanBudgetSpendsTrianglesWhereTheErrorIs)
{
    // GIVEN a noisy plane (±1 level) with a raised disc: noise no split can remove, and an edge
    const Depth8 d(161, 129, [](int c, int r) {
        const int noise = (c * 7 + r * 13) % 3 - 1;
        return 90 + c / 4 + noise + ((c - 100) * (c - 100) + (r - 60) * (r - 60) < 600 ? 60 : 0);
    });
    std::size_t lastTriangles = SIZE_MAX;
    for (const double budget : {0.5, 0.8, 1.2}) {
        AdaptiveMesh mesh;
        ASSERT_TRUE(mesh.build(d.view(), quadtree(budget, ErrorCriterion::Mean)));
        const MeshError e = measureMeshError(d.view(), mesh.indices());
        // THEN the frame's mean error meets the budget (with the fans' small change), the disc's
        // edge stays within the cap, and a larger budget needs fewer triangles
        EXPECT_EQ(e.uncovered, 0u);
        EXPECT_LE(e.mean, budget * 1.1) << "budget " << budget;
        EXPECT_LE(e.max, 2.0 * 16.0) << "budget " << budget;
        EXPECT_LT(mesh.stats().triangles, lastTriangles) << "budget " << budget;
        lastTriangles = mesh.stats().triangles;
    }
}

TEST(QuadtreeMeshTest, blockBudgetBoundsTheLeavesAndRefinesEdgesBreadthFirst)
{
    // GIVEN a noisy slope with a raised disc (its edge is over the cap at every coarse size)
    const Depth8 d(161, 129, [](int c, int r) {
        const int noise = (c * 7 + r * 13) % 3 - 1;
        return 90 + c / 4 + noise + ((c - 100) * (c - 100) + (r - 60) * (r - 60) < 600 ? 60 : 0);
    });
    AdaptiveMesh unlimited;
    ASSERT_TRUE(unlimited.build(d.view(), quadtree(0.5, ErrorCriterion::Mean)));
    EXPECT_FALSE(unlimited.stats().budgetLimited);
    const auto leaves = static_cast<std::size_t>(unlimited.stats().blocks);

    // A budget above what the tolerance needs changes nothing.
    MeshOptions o = quadtree(0.5, ErrorCriterion::Mean);
    o.maxBlocks = leaves + 10;
    AdaptiveMesh loose;
    ASSERT_TRUE(loose.build(d.view(), o));
    EXPECT_FALSE(loose.stats().budgetLimited);
    EXPECT_EQ(loose.indices(), unlimited.indices());

    double lastMean = 0.0;
    std::size_t lastBlocks = SIZE_MAX;
    for (const std::size_t budget : {leaves / 2, leaves / 4, leaves / 8, std::size_t{240},
                                     std::size_t{120}, std::size_t{60}, std::size_t{30}}) {
        o.maxBlocks = budget;
        AdaptiveMesh mesh;
        ASSERT_TRUE(mesh.build(d.view(), o));
        const MeshError e = measureMeshError(d.view(), mesh.indices());
        // THEN the leaves stay within the budget, the mesh stays watertight and conforming, and a
        // smaller budget costs accuracy
        EXPECT_TRUE(mesh.stats().budgetLimited) << budget;
        EXPECT_LE(static_cast<std::size_t>(mesh.stats().blocks), budget);
        EXPECT_LT(static_cast<std::size_t>(mesh.stats().blocks), lastBlocks);
        EXPECT_EQ(e.uncovered, 0u);
        expectConformingTiling(mesh.indices(), d.width, d.height);
        EXPECT_GE(e.mean, lastMean) << budget;
        lastMean = e.mean;
        lastBlocks = static_cast<std::size_t>(mesh.stats().blocks);
        // While the budget is too small for the disc's edge to come within the cap, the edge is
        // refined evenly, the largest blocks over the cap first: no leaf is a single cell yet.
        if (budget <= 240) {
            EXPECT_EQ(mesh.stats().blocksAtSize[0], 0) << "budget " << budget;
        }
    }
}

namespace {

/// Blocks options with 16-sample tiles from step 16 and a tolerance of 100 levels (no refinement
/// for the mean error budget): only the probes and the pass over neighbouring samples refine.
MeshOptions blocksFromStep16()
{
    MeshOptions o;
    o.mode = MeshMode::Blocks;
    o.tileSize = 16;
    o.maxStep = 16;
    o.tolerance = 100.0;
    return o;
}

/// Builds a mesh with \a o from the 65×49-sample frame filled by \a f, in 8- and 16-bit depth with
/// holes below the code \a holeBelow, and checks that it has 4×3 tiles, tile (1, 1) drawn at step 1
/// and the other eleven at step 16.
void expectOnlyTileOneOneAtStepOne(const std::function<int(int, int)> &f, const MeshOptions &o,
                                   std::uint32_t holeBelow)
{
    const test::Depth8 d8(65, 49, f);
    const test::Depth16 d16(65, 49, f);
    for (scene::DepthFrameView v : {d8.view(), d16.view()}) {
        v.holeBelow = holeBelow;
        AdaptiveMesh mesh;
        ASSERT_TRUE(mesh.build(v, o));
        ASSERT_EQ(mesh.tilesX(), 4);
        ASSERT_EQ(mesh.tilesY(), 3);
        for (int t = 0; t < 12; ++t)
            EXPECT_EQ(mesh.tileSteps()[static_cast<std::size_t>(t)], t == 5 ? 1 : 16)
                << "tile " << t << (v.format == scene::SampleFormat::Gray8 ? " 8-bit" : " 16-bit");
    }
}

} // namespace

/// Blocks: a depth edge that no probe sees still sends its tile to full resolution (the pass over
/// neighbouring samples), in 8- and 16-bit depth; the flat tiles stay at the coarsest step.
TEST(BlockStepsTest, anEdgeBetweenTheProbesSendsItsTileToStepOne)
{
    // GIVEN a flat 64×48-cell frame with a ridge 40 samples high on rows 24-25 of tile (1, 1)
    // (probe rows 21 and 29: at step 16, where the choice starts, no probe sees it, so the probes
    // alone leave the tile at step 16)
    const auto ridge = [](int c, int r) {
        return (r == 24 || r == 25) && c >= 18 && c <= 28 ? 140 : 100;
    };
    // THEN that tile is drawn at step 1 and the other eleven at step 16
    expectOnlyTileOneOneAtStepOne(ridge, blocksFromStep16(), 0);
}

/// Blocks: a hole's border is over any cap (adaptive_mesh.h, "Holes"), also at a hole threshold of
/// 1 (only the code 0 is a hole) and with a cap above every jump the samples can make, in 8- and
/// 16-bit depth: the tile with a hole that no probe sees is drawn at step 1.
TEST(BlockStepsTest, aHoleBetweenTheProbesSendsItsTileToStepOneAtAHoleThresholdOfOne)
{
    // GIVEN a flat 64×48-cell frame at level 100 with a hole (code 0) on rows 24-25 of tile (1, 1),
    // where no probe row (21, 29) is, holes below 1, and a cap of 100 000 levels (over 65 535)
    const auto holed = [](int c, int r) {
        return (r == 24 || r == 25) && c >= 18 && c <= 28 ? 0 : 100;
    };
    MeshOptions o = blocksFromStep16();
    o.maxErrorCap = 100000.0;
    // THEN that tile is drawn at step 1 and the other eleven at step 16
    expectOnlyTileOneOneAtStepOne(holed, o, 1);
}
