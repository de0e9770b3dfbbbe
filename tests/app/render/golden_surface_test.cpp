/// \file
/// \brief Golden tests of the drawn surface on a real GLES 3 context (EGL surfaceless, llvmpipe):
/// every covered pixel lies on the haptic height field (the surface seen is the surface touched),
/// and the adaptive mesh is crack-free within its measured error. Skips without the platform.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <thread>
#include <vector>

#include <glm/vec4.hpp>
#include <GLES3/gl3.h>

#include "app/render/egl_test_context.h"
#include "app/render/golden_fixture.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/media/image_io.h"
#include "depthtouch/render/render_target.h"
#include "depthtouch/render/renderer.h"
#include "depthtouch/render/snapshot.h"

using namespace depthtouch;
using namespace depthtouch::render;
using namespace depthtouch::render::golden; // the fixture, its picture helpers and test frames

namespace {

/// Renders the surface's scene-box position into a float target and checks every covered pixel lies
/// on the haptic height field; \return the number of covered pixels and the largest |z − h| (m).
struct Agreement {
    int covered = 0;
    int total = 0;
    double maxDz = 0.0;
    double maxGridDx = 0.0;
};

/// |z − plane(x, y)| for the haptic triangles within 1 % of a sample spacing of (x, y) (planes
/// extended that far), smallest: the rasteriser snaps vertices to a fraction of a pixel, so a pixel
/// centre near an edge may be interpolated on a neighbouring triangle's plane just past its edge.
double distanceToSurface(const haptics::HeightField &hf, double x, double y, double z)
{
    const double u = hf.xToColumn(x);
    const double v = hf.yToRow(y);
    constexpr double kSlack = 0.01;
    double best = 1e9;
    for (int r = static_cast<int>(std::floor(v)) - 1; r <= static_cast<int>(std::floor(v)) + 1; ++r)
        for (int c = static_cast<int>(std::floor(u)) - 1; c <= static_cast<int>(std::floor(u)) + 1;
             ++c) {
            if (c < 0 || r < 0 || c + 1 >= hf.columns() || r + 1 >= hf.rows())
                continue;
            const double fu = u - c;
            const double fv = v - r;
            for (int upper = 0; upper < 2; ++upper) {
                // barycentric coordinates in the cell (docs/architecture.md §3 diagonal)
                const double b0 = upper == 0 ? 1.0 - fu : 1.0 - fv;
                const double b1 = upper == 0 ? fu - fv : fu;
                const double b2 = upper == 0 ? fv : fv - fu;
                if (b0 < -kSlack || b1 < -kSlack || b2 < -kSlack)
                    continue;
                glm::dvec3 p[3];
                haptics::triangleVertices(hf, haptics::TriangleId{c, r, upper}, p);
                best = std::min(best, std::fabs(z - (b0 * p[0].z + b1 * p[1].z + b2 * p[2].z)));
            }
        }
    return best;
}

Agreement agreement(StereoRenderer &renderer, const haptics::HeightField &hf, const EyeView &eye,
                    int w, int h, bool gridAligned)
{
    Agreement a;
    auto t = RenderTarget::create(w, h, TargetFormat::Rgba32F);
    EXPECT_TRUE(t) << "float render targets need EXT_color_buffer_float";
    if (!t)
        return a;
    t->bind();
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    EXPECT_TRUE(renderer.drawSurface(eye, SurfaceOutput::Position));
    std::vector<float> px;
    EXPECT_TRUE(t->readRgbaFloat(px));
    for (int y = eye.viewport.y; y < eye.viewport.y + eye.viewport.height; ++y)
        for (int x = eye.viewport.x; x < eye.viewport.x + eye.viewport.width; ++x) {
            const std::size_t i =
                (static_cast<std::size_t>(h - 1 - y) * static_cast<std::size_t>(w) +
                 static_cast<std::size_t>(x)) *
                4;
            ++a.total;
            if (px[i + 3] < 0.5f)
                continue;
            const double sx = static_cast<double>(px[i]);
            const double sy = static_cast<double>(px[i + 1]);
            const double sz = static_cast<double>(px[i + 2]);
            ++a.covered;
            const double best = distanceToSurface(hf, sx, sy, sz);
            a.maxDz = std::max(a.maxDz, best);
            if (gridAligned) {
                // pixel (x, image row h−1−y) sits on sample column x, row h−1−y
                a.maxGridDx = std::max(a.maxGridDx, std::fabs(sx - hf.columnToX(x)));
                a.maxGridDx = std::max(a.maxGridDx, std::fabs(sy - hf.rowToY(h - 1 - y)));
            }
        }
    return a;
}

} // namespace

TEST_F(RenderGoldenTest, drawnSurfaceIsTheTouchedHeightField)
{
    // GIVEN a bumpy 8-bit and a 16-bit depth frame, full-resolution mesh
    const Depth8 d8(97, 65, bumpy);
    const Depth16 d16(97, 65,
                      [](int c, int r) { return bumpy(c, r) * 257 + (c * 31 + r * 17) % 200; });
    for (const scene::DepthFrameView view : {d8.view(), d16.view()}) {
        ASSERT_TRUE(renderer_->setDepth(view));
        haptics::HeightField hf(renderer_->options().box);
        ASSERT_TRUE(hf.setFrames(view, nullptr));
        const double level = renderer_->mapping().levelMetres() *
                             (view.format == scene::SampleFormat::Gray8 ? 1.0 : 257.0);
        // WHEN its scene-box position is read back from straight above (one pixel per sample)
        const Agreement top = agreement(
            *renderer_, hf,
            topView(97, 65, renderer_->mapping().width(), renderer_->mapping().height(), 0.04), 97,
            65, true);
        // THEN every pixel is covered, sits on its sample, and lies on the haptic surface
        EXPECT_EQ(top.covered, 97 * 65);
        EXPECT_LT(top.maxGridDx, 0.02 * hf.spacing());
        EXPECT_LT(top.maxDz, 0.01 * level) << "haptic and graphic surfaces differ";
        // AND through the left eye's shift-sensor view (between the samples too)
        const auto eyes = eyesFor(StereoMode::SideBySide, 400, 150);
        const Agreement persp = agreement(*renderer_, hf, eyes[0], 400, 150, false);
        EXPECT_GT(persp.covered, persp.total / 2);
        EXPECT_LT(persp.maxDz, 0.02 * level) << "haptic and graphic surfaces differ";
    }
}

TEST_F(RenderGoldenTest, adaptiveMeshIsCrackFreeAndWithinItsMeasuredError)
{
    // GIVEN a bumpy frame and an adaptive mesh mixing steps
    const Depth8 d(161, 113, [](int c, int r) { return c < 80 ? 100 + c / 8 : bumpy(c, r); });
    MeshOptions mesh{MeshMode::Adaptive, 16, 1, 2.0, 16};
    setMode(StereoMode::Mono, 1.04, mesh);
    ASSERT_TRUE(renderer_->setDepth(d.view()));
    const MeshStats &st = renderer_->mesh().stats();
    ASSERT_GT(st.tilesAtStep[4] + st.tilesAtStep[3], 0);
    ASSERT_GT(st.tilesAtStep[0] + st.tilesAtStep[1], 0);
    const MeshError cpu = measureMeshError(d.view(), renderer_->mesh().indices());
    haptics::HeightField hf(renderer_->options().box);
    ASSERT_TRUE(hf.setFrames(d.view(), nullptr));
    // WHEN read back from straight above
    const Agreement top = agreement(
        *renderer_, hf,
        topView(161, 113, renderer_->mapping().width(), renderer_->mapping().height(), 0.04), 161,
        113, true);
    // THEN no background shows through (every pixel covered) and the height error is the CPU's
    EXPECT_EQ(top.covered, 161 * 113);
    EXPECT_LE(top.maxDz, (cpu.max + 0.01) * renderer_->mapping().levelMetres());
    EXPECT_GT(top.maxDz, 0.0);
}
