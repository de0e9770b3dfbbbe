/// \file
/// \brief The renderer on real RGB-D frames (7-Scenes redkitchen at 720×486): the adaptive mesh's
/// error bound and coverage, and a side-by-side snapshot. Skips without the shared data (fails
/// instead when DT_REQUIRE_SHARED_DATA=1).

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

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
