#pragma once
/// \file
/// \brief The golden-image tests' fixture (a GLES 3 context on the EGL surfaceless platform,
/// skipped without one, and a renderer drawing the full-resolution grid) and their picture helpers:
/// pixels, blobs of pixels, the projection of a scene point. Shared by golden_test.cpp (pictures,
/// layouts, colour), golden_surface_test.cpp (the drawn surface against the touched one) and
/// golden_overlay_test.cpp (avatar, OSD, snapshots).
/// The owned test frames (render_test_support.h) are named here too, so that the tests using this
/// namespace see them. Thread-safety: test code, one thread.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "app/render/gles_fixture.h"
#include "app/render/render_test_support.h"
#include "depthtouch/render/render_target.h"
#include "depthtouch/render/renderer.h"

namespace depthtouch::render::golden {

using test::Depth16;
using test::Depth8;
using test::Yuv420;

struct Rgb {
    int r, g, b;
};

struct Picture {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb;
    [[nodiscard]] Rgb at(int x, int y) const
    {
        const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                               static_cast<std::size_t>(x)) *
                              3;
        return {rgb[i], rgb[i + 1], rgb[i + 2]};
    }
};

/// Bounding box and centroid of pixels passing a predicate.
struct Blob {
    int x0 = 1 << 30, x1 = -1, y0 = 1 << 30, y1 = -1;
    double cx = 0.0;
    int count = 0;
};

template <class Pred> Blob findBlob(const Picture &p, int xa, int xb, int ya, int yb, Pred pred)
{
    Blob b;
    double sum = 0.0;
    for (int y = ya; y < yb; ++y)
        for (int x = xa; x < xb; ++x)
            if (pred(p.at(x, y))) {
                b.x0 = std::min(b.x0, x - xa);
                b.x1 = std::max(b.x1, x - xa);
                b.y0 = std::min(b.y0, y - ya);
                b.y1 = std::max(b.y1, y - ya);
                sum += x - xa;
                ++b.count;
            }
    b.cx = b.count > 0 ? sum / b.count : 0.0;
    return b;
}

/// A bumpy depth pattern (nearness 8-bit levels) with a fine ripple: a surface with detail.
inline int bumpy(int c, int r)
{
    const double v =
        128.0 + 90.0 * std::sin(c * 0.31) * std::cos(r * 0.23) + ((c * 7 + r * 13) % 11) * 3.0;
    return static_cast<int>(std::lround(v));
}

inline bool bright(Rgb c)
{
    return c.r > 200 && c.g > 200 && c.b > 200;
}

/// Pixel position (window coordinates, top-left origin) of scene point \a p seen by \a e.
inline glm::dvec2 project(const EyeView &e, int targetHeight, glm::dvec3 p)
{
    const glm::vec4 clip = e.projection * e.view * glm::vec4(glm::vec3(p), 1.0f);
    const double nx = static_cast<double>(clip.x / clip.w);
    const double ny = static_cast<double>(clip.y / clip.w);
    const double wx = e.viewport.x + (nx + 1.0) * 0.5 * e.viewport.width;
    const double wy = e.viewport.y + (ny + 1.0) * 0.5 * e.viewport.height;
    return {wx, targetHeight - wy};
}

class RenderGoldenTest : public depthtouch::test::GlesRendererTest {
protected:
    void SetUp() override
    {
        RendererOptions o;
        o.mesh.mode = MeshMode::Fixed;
        o.mesh.fixedStep = 1;
        o.stereo.eyeSeparation = 0.03; // parallax of a few pixels in these small frames
        setUpRenderer(o);
    }

    void setMode(StereoMode mode, double margin = 1.04,
                 MeshOptions mesh = {MeshMode::Fixed, 16, 1, 0.0, 16})
    {
        RendererOptions o = renderer_->options();
        o.mode = mode;
        o.stereo.margin = margin;
        o.mesh = mesh;
        ASSERT_TRUE(renderer_->setOptions(o));
    }

    /// Shows a flat plane at mid nearness (8-bit level 128) of \a w × \a h samples in the solid
    /// colour \a yuv (8-bit Y', Cb, Cr, read as \a spec says), drawn mono with box margin
    /// \a margin. A refused option or frame fails the test fatally: call it inside
    /// ASSERT_NO_FATAL_FAILURE.
    void showFlatPlane(int w, int h, std::array<int, 3> yuv, double margin,
                       const ColorSpec &spec = {})
    {
        const Depth8 d(w, h, [](int, int) { return 128; });
        Yuv420 col(w, h, [yuv](int, int) { return yuv; });
        setMode(StereoMode::Mono, margin);
        ASSERT_TRUE(renderer_->setDepth(d.view()));
        ASSERT_TRUE(renderer_->setColor(col.view(), spec));
    }

    /// The eyes the renderer draws for \a mode in a \a w × \a h target (pixels) with its current
    /// cameras and picture size and a box depth of 0.04 m, left eye first (one for Mono).
    [[nodiscard]] std::array<EyeView, 2> eyesFor(StereoMode mode, int w, int h) const
    {
        int n = 0;
        return eyeViews(mode, renderer_->options().stereo, w, h,
                        renderer_->mapping().pictureWidth(), renderer_->mapping().pictureHeight(),
                        0.04, n);
    }

    Picture draw(int w, int h)
    {
        Picture p;
        p.width = w;
        p.height = h;
        p.rgb = depthtouch::test::drawRgb(*renderer_, w, h);
        return p;
    }
};

} // namespace depthtouch::render::golden
