/// \file
/// \brief The renderer's per-frame geometry on a real GLES 3 context (EGL surfaceless, llvmpipe;
/// skips without one): the static grid of a fixed step is made once per frame size and draws what
/// a fresh renderer draws (the golden pictures do not change), the quadtree's per-frame lists of
/// changing length stay watertight and draw no stale triangles from the reused index buffers, and
/// the per-frame path (the mesh made ahead, depth, colour, overlays, both eyes) allocates nothing
/// once warm (a counting operator new: support/allocation_counter.h). Per-tile steps from
/// precomputed ranges (MeshMode::Blocks): their stitched triangles tile the grid, at step 1 they
/// draw the full-resolution picture, and they keep to the cell budget. Holes (samples below
/// DepthFrameView::holeBelow) are not drawn in any mesh mode.

#include <gtest/gtest.h>

#include <GLES3/gl3.h>

#include <cmath>
#include <functional>
#include <set>
#include <utility>
#include <vector>

#include "app/render/gles_fixture.h"
#include "app/render/render_test_support.h"
#include "depthtouch/render/render_target.h"
#include "depthtouch/render/renderer.h"
#include "depthtouch/render/stereo.h"
#include "support/allocation_counter.h"

using namespace depthtouch;
using namespace depthtouch::render;
using test::Depth8;
using test::Yuv420;

namespace {

int bumpy(int c, int r)
{
    const double dx = c - 40.0;
    const double dy = r - 30.0;
    return static_cast<int>(std::lround(60.0 + 0.5 * c +
                                        150.0 * std::exp(-(dx * dx + dy * dy) / 80.0) +
                                        ((c / 7 + r / 5) % 3 == 0 ? 30.0 : 0.0)));
}

int gentle(int c, int r)
{
    return 100 + c / 6 + r / 9;
}

MeshOptions fixedStep(int step)
{
    MeshOptions m;
    m.mode = MeshMode::Fixed;
    m.fixedStep = step;
    return m;
}

/// Edges inside the grid without a twin (T-junctions or holes) and the triangles' doubled area,
/// which is 2·(W−1)·(H−1) when they tile the grid.
std::pair<int, long long> openEdgesAndArea(const std::vector<std::uint32_t> &idx, int w, int h)
{
    std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
    long long area2 = 0;
    const auto uw = static_cast<std::uint32_t>(w);
    for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
        long long x[3];
        long long y[3];
        for (std::size_t k = 0; k < 3; ++k) {
            x[k] = idx[t + k] % uw;
            y[k] = idx[t + k] / uw;
            edges.insert({idx[t + k], idx[t + (k + 1) % 3]});
        }
        area2 += (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
    }
    int open = 0;
    for (const auto &[i, j] : edges) {
        if (edges.count({j, i}) != 0)
            continue;
        const auto xi = static_cast<int>(i % uw);
        const auto yi = static_cast<int>(i / uw);
        const auto xj = static_cast<int>(j % uw);
        const auto yj = static_cast<int>(j / uw);
        const bool border =
            (xi == xj && (xi == 0 || xi == w - 1)) || (yi == yj && (yi == 0 || yi == h - 1));
        open += border ? 0 : 1;
    }
    return {open, area2};
}

class RenderGeometryTest : public test::GlesTest {
protected:
    static std::unique_ptr<StereoRenderer> make(const MeshOptions &mesh)
    {
        RendererOptions o;
        o.mode = StereoMode::SideBySide;
        o.mesh = mesh;
        auto r = StereoRenderer::create(o);
        EXPECT_TRUE(r);
        return r ? std::move(*r) : nullptr;
    }

    /// Draws the current frame of \a r into a 240×90 side-by-side target; \return its pixels.
    static std::vector<std::uint8_t> picture(StereoRenderer &r)
    {
        return test::drawRgb(r, 240, 90);
    }

    /// The picture a renderer made for this frame alone draws of \a d with \a mesh.
    static std::vector<std::uint8_t> freshPicture(const Depth8 &d, Yuv420 &col,
                                                  const MeshOptions &mesh)
    {
        auto r = make(mesh);
        EXPECT_TRUE(r->setDepth(d.view()));
        EXPECT_TRUE(r->setColor(col.view(), ColorSpec{}));
        return picture(*r);
    }

    /// A detailed frame (a long triangle list, tiles at several steps), a gentle one (a short
    /// list) and a colour frame of their size, 130×90.
    const Depth8 detailed{130, 90, bumpy};
    const Depth8 plain{130, 90, gentle};
    Yuv420 col{130, 90, [](int c, int r) {
                   return std::array<int, 3>{60 + c, 100 + r / 2, 150 - c / 3};
               }};
};

} // namespace

TEST_F(RenderGeometryTest, staticGridIsMadeOncePerSizeAndDrawsWhatAFreshRendererDraws)
{
    // GIVEN two frames of one size and one of another, and a renderer at full resolution
    const Depth8 a(97, 65, bumpy);
    const Depth8 b(97, 65, gentle);
    const Depth8 small(64, 48, bumpy);
    Yuv420 col97(97, 65, [](int c, int r) {
        return std::array<int, 3>{40 + c + r, 90 + c / 2, 160 - r};
    });
    auto r = make(fixedStep(1));
    ASSERT_TRUE(r);
    ASSERT_TRUE(r->setColor(col97.view(), ColorSpec{}));
    ASSERT_TRUE(r->setDepth(a.view()));
    const AdaptiveMesh *grid = &r->mesh();
    const std::uint32_t *first = grid->indices().data();
    // WHEN the next frame of that size comes
    ASSERT_TRUE(r->setDepth(b.view()));
    // THEN the same grid is drawn, not made again: every cell's two triangles (the haptic ones)
    EXPECT_EQ(&r->mesh(), grid);
    EXPECT_EQ(r->mesh().indices().data(), first);
    EXPECT_EQ(r->mesh().stats().triangles, 2u * 96u * 64u);
    const auto [open, area2] = openEdgesAndArea(r->mesh().indices(), 97, 65);
    EXPECT_EQ(open, 0);
    EXPECT_EQ(area2, 2LL * 96 * 64);
    // AND its picture is the picture of a renderer made for that frame alone, bit for bit
    EXPECT_EQ(picture(*r), freshPicture(b, col97, fixedStep(1)));
    // AND after five other steps and another size (more than the grids kept), each still draws
    // its own grid and the full mesh's picture is unchanged
    for (const int step : {2, 4, 8, 16, 32}) {
        RendererOptions o = r->options();
        o.mesh = fixedStep(step);
        ASSERT_TRUE(r->setOptions(o));
        ASSERT_TRUE(r->setDepth(b.view()));
        const int cells = ((96 + step - 1) / step) * ((64 + step - 1) / step);
        EXPECT_EQ(r->mesh().stats().triangles, 2u * static_cast<std::size_t>(cells))
            << "step " << step;
        EXPECT_EQ(picture(*r), freshPicture(b, col97, fixedStep(step))) << "step " << step;
    }
    RendererOptions o = r->options();
    o.mesh = fixedStep(1);
    ASSERT_TRUE(r->setOptions(o));
    ASSERT_TRUE(r->setDepth(small.view()));
    EXPECT_EQ(r->mesh().stats().triangles, 2u * 63u * 47u);
    ASSERT_TRUE(r->setDepth(b.view()));
    EXPECT_EQ(r->mesh().stats().triangles, 2u * 96u * 64u);
    EXPECT_EQ(picture(*r), freshPicture(b, col97, fixedStep(1)));
}

TEST_F(RenderGeometryTest, quadtreeListsOfChangingLengthStayWatertightAndDrawNoStaleTriangles)
{
    // GIVEN a detailed frame (a long triangle list) and a gentle one (a short list), the quadtree
    const MeshOptions mesh{};
    auto r = make(mesh);
    ASSERT_TRUE(r);
    ASSERT_TRUE(r->setColor(col.view(), ColorSpec{}));
    const std::vector<std::uint8_t> plainAlone = freshPicture(plain, col, mesh);
    FramePrep prep;
    for (int round = 0; round < 3; ++round) {
        // WHEN they alternate, directly and with the mesh made ahead (the reused buffers then hold
        // a longer list's tail)
        ASSERT_TRUE(r->setDepth(detailed.view()));
        const std::size_t longList = r->mesh().indices().size();
        auto [open, area2] = openEdgesAndArea(r->mesh().indices(), 130, 90);
        EXPECT_EQ(open, 0) << "T-junctions at block borders";
        EXPECT_EQ(area2, 2LL * 129 * 89);
        ASSERT_TRUE(prep.build(plain.view(), nullptr, ColorSpec{}, r->options().mesh));
        ASSERT_TRUE(r->setDepth(plain.view(), prep));
        // THEN each list tiles the grid with no T-junction, and the short one draws exactly the
        // picture of a renderer that never held the long one
        EXPECT_LT(r->mesh().indices().size(), longList);
        std::tie(open, area2) = openEdgesAndArea(r->mesh().indices(), 130, 90);
        EXPECT_EQ(open, 0) << "T-junctions at block borders";
        EXPECT_EQ(area2, 2LL * 129 * 89);
        EXPECT_EQ(picture(*r), plainAlone) << "round " << round;
    }
}

MeshOptions blocks(int tile, double tolerance)
{
    MeshOptions m;
    m.mode = MeshMode::Blocks;
    m.tileSize = tile;
    m.maxStep = tile;
    m.tolerance = tolerance;
    return m;
}

TEST_F(RenderGeometryTest, blockStepsAreWatertightAndAtStepOneDrawTheFullResolutionPicture)
{
    // GIVEN a detailed frame and a gentle one, and per-tile steps from precomputed ranges
    std::vector<std::uint32_t> drawn;
    for (const int tile : {8, 16, 32}) {
        auto r = make(blocks(tile, 0.5));
        ASSERT_TRUE(r);
        for (const Depth8 *d : {&detailed, &plain, &detailed}) {
            // WHEN the steps are chosen (the mesh made ahead)
            FramePrep prep;
            ASSERT_TRUE(prep.build(d->view(), nullptr, ColorSpec{}, r->options().mesh));
            ASSERT_TRUE(r->setDepth(d->view(), prep));
            // THEN the tiles are at several steps, no triangle list was made, and the stitched
            // triangles (what the vertex shader draws) tile the grid with no T-junction
            const AdaptiveMesh &m = r->mesh();
            EXPECT_TRUE(m.indices().empty());
            std::set<std::uint16_t> steps(m.tileSteps().begin(), m.tileSteps().end());
            EXPECT_GE(steps.size(), d == &plain ? 1u : 2u) << "tile " << tile;
            m.drawnIndices(drawn);
            const auto [open, area2] = openEdgesAndArea(drawn, 130, 90);
            EXPECT_EQ(open, 0) << "T-junctions at tile borders, tile " << tile;
            EXPECT_EQ(area2, 2LL * 129 * 89) << "tile " << tile;
            EXPECT_EQ(measureMeshError(d->view(), drawn).uncovered, 0u);
        }
    }
    // AND with every tile at step 1 (a largest step of 1), the picture of the full-resolution grid
    MeshOptions fine = blocks(16, 0.5);
    fine.maxStep = 1;
    auto r = make(fine);
    ASSERT_TRUE(r);
    ASSERT_TRUE(r->setColor(col.view(), ColorSpec{}));
    ASSERT_TRUE(r->setDepth(detailed.view()));
    EXPECT_EQ(r->mesh().stats().tilesAtStep[0], r->mesh().stats().tiles);
    EXPECT_EQ(picture(*r), freshPicture(detailed, col, fixedStep(1)));
}

TEST_F(RenderGeometryTest, blockStepsDrawStepOneFromTheFullResolutionGridAsFromTheirOwnBuffer)
{
    // GIVEN a detailed frame drawn first at full resolution in tiles of 16 (a GPU's start: the
    // step-1 grid is then held), and a renderer that never drew it
    MeshOptions full = fixedStep(1);
    full.tileSize = 16;
    auto r = make(full);
    ASSERT_TRUE(r);
    ASSERT_TRUE(r->setColor(col.view(), ColorSpec{}));
    ASSERT_TRUE(r->setDepth(detailed.view()));
    const std::vector<std::uint8_t> fullPicture = picture(*r);
    // WHEN the level of detail takes over (tiles of 16, some at step 1, the others coarser)
    RendererOptions o = r->options();
    o.mesh = blocks(16, 0.5);
    ASSERT_TRUE(r->setOptions(o));
    for (const Depth8 *d : {&detailed, &plain, &detailed}) {
        ASSERT_TRUE(r->setDepth(d->view()));
        const MeshStats &st = r->mesh().stats();
        if (d == &detailed) {
            ASSERT_GT(st.tilesAtStep[0], 0);
            ASSERT_LT(st.tilesAtStep[0], st.tiles);
        }
        // THEN it draws what a renderer with the steps in its own buffer draws, to the pixel
        EXPECT_EQ(picture(*r), freshPicture(*d, col, blocks(16, 0.5)))
            << (d == &detailed ? "detailed" : "plain");
    }
    // AND back at full resolution the grid is unchanged
    o.mesh = full;
    ASSERT_TRUE(r->setOptions(o));
    ASSERT_TRUE(r->setDepth(detailed.view()));
    EXPECT_EQ(picture(*r), fullPicture);
    // AND once four other grids have taken every slot (that grid dropped), the level of detail
    // makes step 1 its own again and still draws the same picture
    for (const int step : {1, 2, 4, 8}) {
        o.mesh = fixedStep(step); // tiles of 32
        ASSERT_TRUE(r->setOptions(o));
        ASSERT_TRUE(r->setDepth(plain.view()));
    }
    o.mesh = blocks(16, 0.5);
    ASSERT_TRUE(r->setOptions(o));
    ASSERT_TRUE(r->setDepth(detailed.view()));
    EXPECT_EQ(picture(*r), freshPicture(detailed, col, blocks(16, 0.5))) << "after the grids";
}

TEST_F(RenderGeometryTest, blockStepsFollowTheCellBudget)
{
    // GIVEN a detailed frame
    auto r = make(blocks(8, 0.0));
    ASSERT_TRUE(r);
    ASSERT_TRUE(r->setDepth(detailed.view()));
    const std::size_t unlimited = static_cast<std::size_t>(r->mesh().stats().blocks);
    // WHEN the cells are capped at half of what the tolerance asks
    RendererOptions o = r->options();
    o.mesh.maxBlocks = unlimited / 2;
    ASSERT_TRUE(r->setOptions(o));
    ASSERT_TRUE(r->setDepth(detailed.view()));
    // THEN the steps stay within the budget, and the refinement says it was limited
    EXPECT_LE(static_cast<std::size_t>(r->mesh().stats().blocks), unlimited / 2);
    EXPECT_GT(static_cast<std::size_t>(r->mesh().stats().blocks), unlimited / 4);
    EXPECT_TRUE(r->mesh().stats().budgetLimited);
    EXPECT_EQ(r->mesh().stats().triangles, 2u * static_cast<std::size_t>(r->mesh().stats().blocks));
}

TEST_F(RenderGeometryTest, perFramePathAllocatesNothingOnceWarm)
{
    // GIVEN two frames that alternate, for the full-resolution grid and the quadtree (its mesh
    // made ahead, as the player does), with the avatar and the on-screen display
    const Depth8 a(130, 90, bumpy);
    const Depth8 b(130, 90, gentle);
    for (const MeshOptions &mesh : {fixedStep(1), MeshOptions{}, blocks(8, 0.5)}) {
        auto r = make(mesh);
        ASSERT_TRUE(r);
        auto target = RenderTarget::create(240, 90);
        ASSERT_TRUE(target);
        AvatarState avatar;
        avatar.visible = true;
        avatar.hip = glm::dvec3(0.0, 0.0, -0.002);
        OsdState osd;
        osd.visible = true;
        osd.status = "PLAYING";
        osd.hapticsOn = true;
        FramePrep prep;
        const auto frame = [&](const Depth8 &d) {
            ASSERT_TRUE(prep.build(d.view(), nullptr, ColorSpec{}, r->options().mesh));
            ASSERT_TRUE(r->setDepth(d.view(), prep));
            ASSERT_TRUE(r->setColor(col.view(), ColorSpec{}));
            r->setAvatar(avatar);
            r->setOsd(osd);
            ASSERT_TRUE(r->render(*target));
        };
        for (int warm = 0; warm < 3; ++warm) {
            frame(a);
            frame(b);
        }
        r->finish();
        // WHEN four more frames are made and drawn
        std::size_t allocations = 0;
        {
            const depthtouch::testing::AllocationCounter counter;
            frame(a);
            frame(b);
            frame(a);
            frame(b);
            allocations = counter.count();
        }
        r->finish();
        // THEN nothing was allocated with operator new on the way
        EXPECT_EQ(allocations, 0u) << (mesh.mode == MeshMode::Fixed    ? "full resolution"
                                       : mesh.mode == MeshMode::Blocks ? "blocks"
                                                                       : "quadtree");
    }
}

namespace {

/// Chebyshev distance from sample (c, r) to the nearest sample for which \a inSet is true (the
/// frame's size when none is).
int distanceTo(int c, int r, int w, int h, const std::function<bool(int, int)> &inSet)
{
    for (int d = 0; d < std::max(w, h); ++d)
        for (int y = std::max(0, r - d); y <= std::min(h - 1, r + d); ++y)
            for (int x = std::max(0, c - d); x <= std::min(w - 1, c + d); ++x)
                if (inSet(x, y))
                    return d;
    return std::max(w, h);
}

} // namespace

TEST_F(RenderGeometryTest, holesShowTheClearColorInEveryMeshMode)
{
    // GIVEN a bumpy frame with a 30x25 hole coded 0 under a threshold of 24 (docs/architecture.md
    // §3 "Holes"), every other sample measured at 60 or more
    constexpr int kW = 97;
    constexpr int kH = 65;
    const auto isHole = [](int c, int r) { return c >= 30 && c < 60 && r >= 20 && r < 45; };
    const Depth8 holed(kW, kH, [&](int c, int r) { return isHole(c, r) ? 0 : bumpy(c, r); });
    Yuv420 col97(kW, kH, [](int c, int r) {
        return std::array<int, 3>{120 + c / 2, 100 + r / 2, 150 - c / 3};
    });
    MeshOptions quadtree;
    MeshOptions adaptive{MeshMode::Adaptive, 16, 1, 2.0, 16};
    MeshOptions blocks;
    blocks.mode = MeshMode::Blocks;
    blocks.tileSize = blockTileFor(kW, kH);
    blocks.maxStep = blocks.tileSize;
    // (mesh, margin: how far from the hole's border the picture must be exact, samples)
    const std::pair<MeshOptions, int> meshes[] = {
        {fixedStep(1), 1}, {fixedStep(4), 4}, {quadtree, 1}, {adaptive, 1}, {blocks, 1}};
    for (const auto &[mesh, margin] : meshes) {
        for (const std::uint32_t holeBelow : {24u, 0u}) {
            auto r = make(mesh);
            ASSERT_TRUE(r);
            ASSERT_TRUE(r->setColor(col97.view(), ColorSpec{}));
            scene::DepthFrameView v = holed.view();
            v.holeBelow = holeBelow;
            ASSERT_TRUE(r->setDepth(v));
            // WHEN drawn from straight above, one pixel a sample, over a black clear colour
            auto t = RenderTarget::create(kW, kH);
            ASSERT_TRUE(t);
            t->bind();
            glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
            glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
            ASSERT_TRUE(r->drawSurface(topView(kW, kH, r->mapping().width(), r->mapping().height(),
                                               r->options().box.depth),
                                       SurfaceOutput::Color));
            std::vector<std::uint8_t> rgb;
            ASSERT_TRUE(t->readRgb(rgb));
            // THEN with the threshold, the hole shows the clear colour and the surface is drawn
            // elsewhere; without it (an old file) the hole's samples are a surface like any other
            int clearInHole = 0;
            int holeSamples = 0;
            int wrong = 0;
            for (int y = 0; y < kH; ++y)
                for (int x = 0; x < kW; ++x) {
                    const std::uint8_t *p = &rgb[3 * static_cast<std::size_t>(y * kW + x)];
                    const bool clear = p[0] < 8 && p[1] < 8 && p[2] < 8;
                    const bool hole = isHole(x, y);
                    const int border =
                        hole ? distanceTo(x, y, kW, kH,
                                          [&](int c, int rr) { return !isHole(c, rr); })
                             : distanceTo(x, y, kW, kH, isHole);
                    holeSamples += hole ? 1 : 0;
                    clearInHole += hole && clear ? 1 : 0;
                    if (border > margin && clear != (hole && holeBelow > 0))
                        ++wrong;
                }
            EXPECT_EQ(wrong, 0) << "mesh mode " << static_cast<int>(mesh.mode) << " step "
                                << mesh.fixedStep << ", holeBelow " << holeBelow;
            if (holeBelow > 0)
                EXPECT_EQ(clearInHole, holeSamples) << "mesh mode " << static_cast<int>(mesh.mode);
            else
                EXPECT_EQ(clearInHole, 0);
        }
    }
}
