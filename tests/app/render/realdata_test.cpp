/// \file
/// \brief The renderer on real RGB-D frames (7-Scenes redkitchen at 720×486): the adaptive mesh's
/// error bound and coverage, the mono view against the colour frame, and a side-by-side snapshot.
/// Skips without the shared data (fails instead when DT_REQUIRE_SHARED_DATA=1).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "app/render/egl_test_context.h"
#include "depthtouch/render/render_bench.h"
#include "depthtouch/render/render_target.h"
#include "depthtouch/render/renderer.h"
#include "support/shared_data.h"

using namespace depthtouch;
using namespace depthtouch::render;
namespace fs = std::filesystem;

namespace {

std::string kitchenDir()
{
    return depthtouch::testing::sharedDataPath("rgbd-7scenes-redkitchen");
}

} // namespace

TEST(RenderRealDataTest, adaptiveMeshMeetsTheErrorGoalWithFewTrianglesAndNoCracks)
{
    DT_NEED_SHARED_DATA("rgbd-7scenes-redkitchen/frame-000000.depth.png");
    const std::string dir = kitchenDir();
    auto frames = bench::loadKitchenFrames(dir, 6, 720, 486);
    ASSERT_TRUE(frames) << frames.error().what;
    ASSERT_EQ(frames->size(), 6u);
    for (const auto &f : *frames) {
        scene::DepthFrameView v;
        v.data = f.nearness.data();
        v.width = f.width;
        v.height = f.height;
        v.strideBytes = static_cast<std::size_t>(f.width);
        // GIVEN the default adaptive mesh (tile 8, mean criterion, 1.2 levels per tile, cap 16)
        MeshOptions o;
        AdaptiveMesh mesh;
        ASSERT_TRUE(mesh.build(v, o));
        const MeshError e = measureMeshError(v, mesh.indices());
        // THEN the mean error meets the ≤ 0.5-level goal, no sample falls through, the largest
        // error stays near the tolerance, and far fewer triangles than the full mesh are drawn
        EXPECT_EQ(e.uncovered, 0u);
        EXPECT_LE(e.mean, 0.5);
        EXPECT_LE(e.max, 2.0 * o.maxErrorCap);
        EXPECT_LT(mesh.stats().triangles, 2u * 719u * 485u / 8u);
    }
}

TEST(RenderRealDataTest, writesASideBySideSnapshot)
{
    DT_NEED_SHARED_DATA("rgbd-7scenes-redkitchen/frame-000000.depth.png");
    const std::string dir = kitchenDir();
    DT_REQUIRE_GLES_CONTEXT(ctx);
    auto frames = bench::loadKitchenFrames(dir, 1, 720, 486);
    ASSERT_TRUE(frames);
    const std::string out = ::testing::TempDir() + "/dt_render_kitchen_sbs.png";
    const MeshOptions o;
    ASSERT_TRUE(bench::writeSideBySideSnapshot(*frames, 0, o, 1440, 486, out));
    EXPECT_GT(fs::file_size(out), 100000u) << "a real scene compresses far less than a blank frame";
}

// docs/playing.md "Picture": the mono view of a real frame at the colour frame's size is that frame
// pixel for pixel where there is depth (the kitchen's holes are filled): its luma, computed here
// from the rendered R'G'B' with BT.601's weights, against the frame's own Y' in full range.
TEST(RenderRealDataTest, theMonoViewIsTheColorFrame)
{
    DT_NEED_SHARED_DATA("rgbd-7scenes-redkitchen/frame-000000.depth.png");
    DT_REQUIRE_GLES_CONTEXT(ctx);
    auto frames = bench::loadKitchenFrames(kitchenDir(), 1, 320, 240);
    ASSERT_TRUE(frames) << frames.error().what;
    bench::RgbdFrame &f = frames->front();
    RendererOptions o;
    o.mode = StereoMode::Mono;
    auto r = StereoRenderer::create(o);
    ASSERT_TRUE(r) << r.error().what;
    scene::DepthFrameView d;
    d.data = f.nearness.data();
    d.width = f.width;
    d.height = f.height;
    d.strideBytes = static_cast<std::size_t>(f.width);
    hal::ImageView c;
    c.width = f.colorWidth;
    c.height = f.colorHeight;
    c.format = hal::PixelFormat::Yuv420p;
    c.planes[0] = {f.y.data(), f.colorWidth};
    c.planes[1] = {f.u.data(), (f.colorWidth + 1) / 2};
    c.planes[2] = {f.v.data(), (f.colorWidth + 1) / 2};
    ASSERT_TRUE((*r)->setDepth(d));
    ASSERT_TRUE((*r)->setColor(c, ColorSpec{YuvMatrix::Bt601, false}));
    auto t = RenderTarget::create(f.colorWidth, f.colorHeight);
    ASSERT_TRUE(t);
    ASSERT_TRUE((*r)->render(*t));
    std::vector<std::uint8_t> rgb;
    ASSERT_TRUE(t->readRgb(rgb));
    // Over the picture the depth covers: the mesh spans the samples' centres, so a colour frame
    // finer than the depth (640×480 over 320×240) has a ring of half a sample outside it.
    const auto inside = [](int i, int color, int depth) {
        const double at = (i + 0.5) / color;
        return at >= 0.5 / depth && at <= (depth - 0.5) / depth;
    };
    double se = 0.0;
    std::size_t n = 0;
    for (int y = 0; y < f.colorHeight; ++y)
        for (int x = 0; x < f.colorWidth; ++x) {
            if (!inside(x, f.colorWidth, f.width) || !inside(y, f.colorHeight, f.height))
                continue;
            ++n;
            const std::size_t i = static_cast<std::size_t>(y * f.colorWidth + x);
            const double got = 0.299 * rgb[3 * i] + 0.587 * rgb[3 * i + 1] + 0.114 * rgb[3 * i + 2];
            const double want = std::clamp(255.0 / 219.0 * (f.y[i] - 16.0), 0.0, 255.0);
            se += (got - want) * (got - want);
        }
    ASSERT_GT(n, static_cast<std::size_t>(f.colorWidth * f.colorHeight) * 9 / 10);
    const double mse = se / static_cast<double>(n);
    const double psnr = 10.0 * std::log10(255.0 * 255.0 / std::max(mse, 1e-9));
    EXPECT_GE(psnr, 35.0) << "mse " << mse;
    std::printf("mono view against the colour frame: PSNR %.1f dB (%dx%d)\n", psnr, f.colorWidth,
                f.colorHeight);
}
