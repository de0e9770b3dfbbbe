/// \file
/// \brief Golden-image tests of the stereo renderer on a real GLES 3 context (EGL surfaceless,
/// llvmpipe): known depth + colour → expected pixels with a tolerance, the parallax sign, each output
/// layout, Y'CbCr accuracy, agreement with the haptic height field, adaptive-mesh coverage, avatar,
/// OSD and snapshots. Skips when EGL has no surfaceless platform.

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
#include "app/render/render_test_support.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/media/image_io.h"
#include "depthtouch/render/render_target.h"
#include "depthtouch/render/renderer.h"
#include "depthtouch/render/snapshot.h"

using namespace depthtouch;
using namespace depthtouch::render;
using test::Depth16;
using test::Depth8;
using test::Yuv420;

namespace {

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
                               static_cast<std::size_t>(x)) * 3;
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

bool bright(Rgb c)
{
    return c.r > 200 && c.g > 200 && c.b > 200;
}

/// Pixel position (window coordinates, top-left origin) of scene point \a p seen by \a e.
glm::dvec2 project(const EyeView &e, int targetHeight, glm::dvec3 p)
{
    const glm::vec4 clip = e.projection * e.view * glm::vec4(glm::vec3(p), 1.0f);
    const double nx = static_cast<double>(clip.x / clip.w);
    const double ny = static_cast<double>(clip.y / clip.w);
    const double wx = e.viewport.x + (nx + 1.0) * 0.5 * e.viewport.width;
    const double wy = e.viewport.y + (ny + 1.0) * 0.5 * e.viewport.height;
    return {wx, targetHeight - wy};
}

class RenderGoldenTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        std::string why;
        ctx_ = test::EglTestContext::create(why);
        if (!ctx_)
            GTEST_SKIP() << "No GLES 3 context on the EGL surfaceless platform: " << why;
        RendererOptions o;
        o.mesh.mode = MeshMode::Fixed;
        o.mesh.fixedStep = 1;
        o.stereo.eyeSeparation = 0.03; // parallax of a few pixels in these small frames
        auto r = StereoRenderer::create(o);
        ASSERT_TRUE(r) << r.error().what;
        renderer_ = std::move(*r);
    }

    void setMode(StereoMode mode, double margin = 1.04, MeshOptions mesh = {MeshMode::Fixed, 16, 1, 0.0, 16})
    {
        RendererOptions o = renderer_->options();
        o.mode = mode;
        o.stereo.margin = margin;
        o.mesh = mesh;
        ASSERT_TRUE(renderer_->setOptions(o));
    }

    Picture draw(int w, int h)
    {
        auto t = RenderTarget::create(w, h);
        EXPECT_TRUE(t);
        EXPECT_TRUE(renderer_->render(*t));
        Picture p;
        p.width = w;
        p.height = h;
        EXPECT_TRUE(t->readRgb(p.rgb));
        return p;
    }

    std::unique_ptr<test::EglTestContext> ctx_;
    std::unique_ptr<StereoRenderer> renderer_;
};

} // namespace

TEST_F(RenderGoldenTest, flatPlaneWithSolidColourFillsTheBoxRegion)
{
    // GIVEN a flat depth frame at mid nearness and a solid red colour frame (BT.601 limited)
    const Depth8 d(64, 43, [](int, int) { return 128; });
    Yuv420 c(64, 43, [](int, int) { return std::array<int, 3>{81, 90, 240}; });
    setMode(StereoMode::Mono, 1.3);
    ASSERT_TRUE(renderer_->setDepth(d.view()));
    ASSERT_TRUE(renderer_->setColor(c.view(), ColorSpec{YuvMatrix::Bt601, false}));
    // WHEN drawn mono into 160×120
    const Picture p = draw(160, 120);
    // THEN the box's projected rectangle is red and the rest is the black background
    int n = 0;
    const auto eyes = eyeViews(StereoMode::Mono, renderer_->options().stereo, 160, 120, renderer_->mapping().width(),
                               renderer_->mapping().height(), 0.04, n);
    const double z = renderer_->mapping().point(0, 0, 128).z;
    const glm::dvec2 tl = project(eyes[0], 120, {-0.05, renderer_->mapping().height() / 2, z});
    const glm::dvec2 br = project(eyes[0], 120, {0.05, -renderer_->mapping().height() / 2, z});
    ASSERT_GT(br.x - tl.x, 60.0);
    int inside = 0;
    int outside = 0;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x) {
            const double px = x + 0.5;
            const double py = y + 0.5;
            const Rgb v = p.at(x, y);
            if (px > tl.x + 2 && px < br.x - 2 && py > tl.y + 2 && py < br.y - 2) {
                ++inside;
                EXPECT_GE(v.r, 250) << x << "," << y;
                EXPECT_LE(v.g, 4) << x << "," << y;
                EXPECT_LE(v.b, 4) << x << "," << y;
            } else if (px < tl.x - 2 || px > br.x + 2 || py < tl.y - 2 || py > br.y + 2) {
                ++outside;
                EXPECT_LE(v.r + v.g + v.b, 0) << x << "," << y;
            }
        }
    EXPECT_GT(inside, 5000);
    EXPECT_GT(outside, 1000);
}

TEST_F(RenderGoldenTest, raisedSquareHasCrossedParallaxAndFarMarkUncrossed)
{
    // GIVEN a far plane with a raised white square in its middle (nearness 255 = nearest)
    const auto inSquare = [](int c, int r) { return c >= 24 && c <= 40 && r >= 16 && r <= 32; };
    const Depth8 d(64, 48, [&](int c, int r) { return inSquare(c, r) ? 255 : 0; });
    Yuv420 col(64, 48, [&](int c, int r) {
        return inSquare(c, r) ? std::array<int, 3>{235, 128, 128} : std::array<int, 3>{40, 128, 128};
    });
    setMode(StereoMode::SideBySide);
    ASSERT_TRUE(renderer_->setDepth(d.view()));
    ASSERT_TRUE(renderer_->setColor(col.view(), ColorSpec{}));
    // WHEN drawn side-by-side
    const Picture p = draw(320, 120);
    const Blob left = findBlob(p, 0, 160, 0, 120, bright);
    const Blob right = findBlob(p, 160, 320, 0, 120, bright);
    ASSERT_GT(left.count, 50);
    ASSERT_GT(right.count, 50);
    // THEN the near square's left-eye image is right of its right-eye image (crossed parallax), by
    // the disparity the eye cameras predict
    int n = 0;
    const auto eyes = eyeViews(StereoMode::SideBySide, renderer_->options().stereo, 320, 120,
                               renderer_->mapping().width(), renderer_->mapping().height(), 0.04, n);
    const glm::dvec3 centre = renderer_->mapping().point(32, 24, 255);
    const double predicted = project(eyes[0], 120, centre).x - (project(eyes[1], 120, centre).x - 160);
    ASSERT_GT(predicted, 1.0);
    EXPECT_GT(left.cx - right.cx, 1.0);
    EXPECT_NEAR(left.cx - right.cx, predicted, 1.0);

    // GIVEN instead a mark painted on the far plane (nearness 0 everywhere)
    const Depth8 flatFar(64, 48, [](int, int) { return 0; });
    ASSERT_TRUE(renderer_->setDepth(flatFar.view()));
    const Picture q = draw(320, 120);
    const Blob l2 = findBlob(q, 0, 160, 0, 120, bright);
    const Blob r2 = findBlob(q, 160, 320, 0, 120, bright);
    ASSERT_GT(l2.count, 20);
    // THEN it lies behind the screen: uncrossed (left-eye image left of the right-eye image)
    EXPECT_LT(l2.cx - r2.cx, -1.0);
}

TEST_F(RenderGoldenTest, eachOutputModeHasItsLayout)
{
    // GIVEN a white plane in front of the screen (crossed parallax) in a black frame
    const Depth8 d(64, 48, [](int, int) { return 220; });
    Yuv420 col(64, 48, [](int, int) { return std::array<int, 3>{235, 128, 128}; });
    ASSERT_TRUE(renderer_->setDepth(d.view()));
    ASSERT_TRUE(renderer_->setColor(col.view(), ColorSpec{}));

    // sbs: one image per half, the left eye's shifted right
    setMode(StereoMode::SideBySide, 1.6);
    Picture p = draw(320, 120);
    Blob l = findBlob(p, 0, 160, 0, 120, bright);
    Blob r = findBlob(p, 160, 320, 0, 120, bright);
    ASSERT_GT(l.count, 100);
    EXPECT_NEAR(l.count, r.count, 0.1 * l.count);
    EXPECT_GT(l.x0, r.x0);
    EXPECT_GT(l.x1, r.x1);
    EXPECT_GT(l.x0, 0); // inside its half, with a border
    EXPECT_LT(r.x1, 159);

    // tab: left eye in the top half, right eye in the bottom half
    setMode(StereoMode::TopAndBottom, 1.6);
    p = draw(160, 240);
    l = findBlob(p, 0, 160, 0, 120, bright);
    r = findBlob(p, 0, 160, 120, 240, bright);
    ASSERT_GT(l.count, 100);
    EXPECT_NEAR(l.count, r.count, 0.1 * l.count);
    EXPECT_GT(l.x0, r.x0);
    EXPECT_NEAR(l.y0, r.y0, 1);
    EXPECT_GT(l.y0, 0);
    EXPECT_LT(r.y1, 119);

    // anaglyph: where only the left eye sees the plane the pixel is red, where only the right eye
    // does it is cyan; the left-only strip is right of the right-only strip (crossed)
    setMode(StereoMode::Anaglyph, 1.6);
    p = draw(160, 120);
    const Blob redOnly = findBlob(p, 0, 160, 0, 120, [](Rgb c) { return c.r > 200 && c.g < 30 && c.b < 30; });
    const Blob cyanOnly = findBlob(p, 0, 160, 0, 120, [](Rgb c) { return c.r < 30 && c.g > 200 && c.b > 200; });
    const Blob both = findBlob(p, 0, 160, 0, 120, bright);
    ASSERT_GT(redOnly.count, 10);
    ASSERT_GT(cyanOnly.count, 10);
    EXPECT_GT(both.count, 1000);
    EXPECT_GT(redOnly.cx, cyanOnly.cx);

    // interleaved: rows counted from the top alternate left eye (even) and right eye (odd)
    setMode(StereoMode::RowInterleaved, 1.6);
    p = draw(160, 120);
    int checked = 0;
    for (int y = 40; y < 80; y += 2) {
        const Blob even = findBlob(p, 0, 160, y, y + 1, bright);
        const Blob odd = findBlob(p, 0, 160, y + 1, y + 2, bright);
        const Blob evenMono = findBlob(p, 0, 160, 40, 41, bright);
        ASSERT_GT(even.count, 50) << y;
        ASSERT_GT(odd.count, 50) << y;
        EXPECT_GT(even.x0, odd.x0) << y;
        EXPECT_EQ(even.x0, evenMono.x0) << y; // every left-eye row is the same plane
        ++checked;
    }
    EXPECT_EQ(checked, 20);
}

TEST_F(RenderGoldenTest, yuvConversionMatchesBt601LimitedOnScreen)
{
    // GIVEN a colour frame of 8 patches of known Y'CbCr (16×24 pixels each) on a flat surface
    const std::array<std::array<int, 3>, 8> patches = {{{16, 128, 128},
                                                        {235, 128, 128},
                                                        {81, 90, 240},
                                                        {145, 54, 34},
                                                        {41, 240, 110},
                                                        {170, 166, 16},
                                                        {106, 202, 222},
                                                        {126, 128, 128}}};
    const Depth8 d(64, 48, [](int, int) { return 128; });
    Yuv420 col(64, 48, [&](int c, int r) { return patches[static_cast<std::size_t>((r / 24) * 4 + c / 16)]; });
    ASSERT_TRUE(renderer_->setDepth(d.view()));
    ASSERT_TRUE(renderer_->setColor(col.view(), ColorSpec{YuvMatrix::Bt601, false}));
    // WHEN drawn from straight above, one pixel per sample
    auto t = RenderTarget::create(64, 48);
    ASSERT_TRUE(t);
    t->bind();
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    ASSERT_TRUE(renderer_->drawSurface(topView(64, 48, renderer_->mapping().width(), renderer_->mapping().height(), 0.04),
                                       SurfaceOutput::Color));
    Picture p;
    p.width = 64;
    p.height = 48;
    ASSERT_TRUE(t->readRgb(p.rgb));
    // THEN each patch's centre has the textbook BT.601 limited-range RGB (within 2 codes)
    for (std::size_t i = 0; i < patches.size(); ++i) {
        const auto [y, u, v] = patches[i];
        const auto clamp = [](double x) { return std::clamp(x, 0.0, 255.0); };
        const double er = clamp(1.164 * (y - 16) + 1.596 * (v - 128));
        const double eg = clamp(1.164 * (y - 16) - 0.392 * (u - 128) - 0.813 * (v - 128));
        const double eb = clamp(1.164 * (y - 16) + 2.017 * (u - 128));
        const int px = static_cast<int>(i % 4) * 16 + 8;
        const int py = static_cast<int>(i / 4) * 24 + 12;
        const Rgb got = p.at(px, py);
        EXPECT_NEAR(got.r, er, 2.0) << "patch " << i;
        EXPECT_NEAR(got.g, eg, 2.0) << "patch " << i;
        EXPECT_NEAR(got.b, eb, 2.0) << "patch " << i;
    }
}

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
        for (int c = static_cast<int>(std::floor(u)) - 1; c <= static_cast<int>(std::floor(u)) + 1; ++c) {
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

Agreement agreement(StereoRenderer &renderer, const haptics::HeightField &hf, const EyeView &eye, int w, int h,
                    bool gridAligned)
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
            const std::size_t i = (static_cast<std::size_t>(h - 1 - y) * static_cast<std::size_t>(w) +
                                   static_cast<std::size_t>(x)) * 4;
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

int bumpy(int c, int r)
{
    const double v = 128.0 + 90.0 * std::sin(c * 0.31) * std::cos(r * 0.23) + ((c * 7 + r * 13) % 11) * 3.0;
    return static_cast<int>(std::lround(v));
}

} // namespace

TEST_F(RenderGoldenTest, drawnSurfaceIsTheTouchedHeightField)
{
    // GIVEN a bumpy 8-bit and a 16-bit depth frame, full-resolution mesh
    const Depth8 d8(97, 65, bumpy);
    const Depth16 d16(97, 65, [](int c, int r) { return bumpy(c, r) * 257 + (c * 31 + r * 17) % 200; });
    for (const haptics::DepthFrameView view : {d8.view(), d16.view()}) {
        ASSERT_TRUE(renderer_->setDepth(view));
        haptics::HeightField hf(renderer_->options().box);
        ASSERT_TRUE(hf.setFrames(view, nullptr));
        const double level = renderer_->mapping().levelMetres() * (view.format == haptics::SampleFormat::Gray8 ? 1.0 : 257.0);
        // WHEN its scene-box position is read back from straight above (one pixel per sample)
        const Agreement top = agreement(*renderer_, hf,
                                        topView(97, 65, renderer_->mapping().width(), renderer_->mapping().height(), 0.04),
                                        97, 65, true);
        // THEN every pixel is covered, sits on its sample, and lies on the haptic surface
        EXPECT_EQ(top.covered, 97 * 65);
        EXPECT_LT(top.maxGridDx, 0.02 * hf.spacing());
        EXPECT_LT(top.maxDz, 0.01 * level) << "haptic and graphic surfaces differ";
        // AND through the left eye's off-axis perspective (between the samples too)
        int n = 0;
        const auto eyes = eyeViews(StereoMode::SideBySide, renderer_->options().stereo, 400, 150,
                                   renderer_->mapping().width(), renderer_->mapping().height(), 0.04, n);
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
    const Agreement top = agreement(*renderer_, hf,
                                    topView(161, 113, renderer_->mapping().width(), renderer_->mapping().height(), 0.04),
                                    161, 113, true);
    // THEN no background shows through (every pixel covered) and the height error is the CPU's
    EXPECT_EQ(top.covered, 161 * 113);
    EXPECT_LE(top.maxDz, (cpu.max + 0.01) * renderer_->mapping().levelMetres());
    EXPECT_GT(top.maxDz, 0.0);
}

TEST_F(RenderGoldenTest, avatarOsdAndSnapshot)
{
    const Depth8 d(64, 48, [](int, int) { return 128; });
    Yuv420 col(64, 48, [](int, int) { return std::array<int, 3>{126, 128, 128}; });
    setMode(StereoMode::Mono, 1.2);
    ASSERT_TRUE(renderer_->setDepth(d.view()));
    ASSERT_TRUE(renderer_->setColor(col.view(), ColorSpec{}));
    const Picture plain = draw(200, 150);
    // GIVEN the proxy resting on the surface near the box centre and the OSD on
    AvatarState av;
    av.visible = true;
    av.proxy = {0.01, -0.005, renderer_->mapping().point(0, 0, 128).z + av.radius};
    av.hip = av.proxy - glm::dvec3(0.0, 0.0, 0.004);
    renderer_->setAvatar(av);
    OsdState osd;
    osd.visible = true;
    osd.status = "PLAYING";
    osd.hapticsOn = true;
    osd.force = 4.0;
    renderer_->setOsd(osd);
    const Picture withAvatar = draw(200, 150);
    // THEN the pixel at the proxy is the sphere's warm colour instead of the grey surface
    int n = 0;
    const auto eyes = eyeViews(StereoMode::Mono, renderer_->options().stereo, 200, 150, renderer_->mapping().width(),
                               renderer_->mapping().height(), 0.04, n);
    const glm::dvec2 at = project(eyes[0], 150, av.proxy + glm::dvec3(0, 0, av.radius));
    const Rgb before = plain.at(static_cast<int>(at.x), static_cast<int>(at.y));
    const Rgb sphere = withAvatar.at(static_cast<int>(at.x), static_cast<int>(at.y));
    EXPECT_NEAR(before.r, before.b, 3);
    EXPECT_GT(sphere.r, sphere.b + 60);
    // AND the OSD changed the top-left corner but not the bottom-right one
    int changedTopLeft = 0;
    int changedBottomRight = 0;
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 60; ++x) {
            changedTopLeft += plain.at(x, y).g != withAvatar.at(x, y).g ? 1 : 0;
            changedBottomRight += plain.at(199 - x, 149 - y).g != withAvatar.at(199 - x, 149 - y).g ? 1 : 0;
        }
    EXPECT_GT(changedTopLeft, 200);
    EXPECT_EQ(changedBottomRight, 0);

    // WHEN snapshotted to PNG THEN reading the file back gives the same pixels
    auto t = RenderTarget::create(200, 150);
    ASSERT_TRUE(t);
    ASSERT_TRUE(renderer_->render(*t));
    const std::string dir = ::testing::TempDir() + "/dt_render_snapshots";
    std::filesystem::remove_all(dir);
    Snapshotter snap(dir, 2);
    auto first = snap.onFrame(*t);
    ASSERT_TRUE(first);
    ASSERT_TRUE(first->has_value());
    auto second = snap.onFrame(*t);
    ASSERT_TRUE(second);
    EXPECT_FALSE(second->has_value());
    snap.request();
    auto third = snap.onFrame(*t);
    ASSERT_TRUE(third);
    ASSERT_TRUE(third->has_value());
    ASSERT_TRUE(snap.flush());
    EXPECT_EQ(snap.written(), 2u);
    auto img = media::readImage(**first, media::PixelFormat::Rgb24);
    ASSERT_TRUE(img);
    ASSERT_EQ(img->width, 200);
    ASSERT_EQ(img->height, 150);
    for (int y = 0; y < 150; ++y)
        ASSERT_EQ(0, std::memcmp(img->row(y), withAvatar.rgb.data() + static_cast<std::size_t>(y) * 600, 600)) << y;
}

TEST_F(RenderGoldenTest, snapshotsQueuedFasterThanWrittenAreAllWrittenAndErrorsReported)
{
    const Depth8 d(64, 48, bumpy);
    ASSERT_TRUE(renderer_->setDepth(d.view()));
    auto t = RenderTarget::create(320, 240);
    ASSERT_TRUE(t);
    ASSERT_TRUE(renderer_->render(*t));
    const std::string dir = ::testing::TempDir() + "/dt_render_snapshot_burst";
    std::filesystem::remove_all(dir);
    {
        // WHEN every one of 12 frames is snapshotted (more than the writer queue holds)
        Snapshotter snap(dir, 1, "burst");
        for (int i = 0; i < 12; ++i) {
            auto r = snap.onFrame(*t);
            ASSERT_TRUE(r);
            ASSERT_TRUE(r->has_value());
        }
    } // the destructor waits for the writer
    // THEN every file is there and complete
    for (int i = 0; i < 12; ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "/burst-%06d.png", i);
        auto img = media::readImage(dir + name, media::PixelFormat::Rgb24);
        ASSERT_TRUE(img) << name;
        EXPECT_EQ(img->width, 320);
    }
    // WHEN a snapshot's file cannot be written (a directory stands in its way)
    std::filesystem::remove(dir + "/burst-000000.png");
    std::filesystem::create_directories(dir + "/burst-000000.png");
    std::filesystem::remove(dir + "/burst-000001.png");
    Snapshotter again(dir, 1, "burst");
    auto r0 = again.onFrame(*t);
    ASSERT_TRUE(r0);
    auto r1 = again.onFrame(*t);
    // THEN the error comes back once (from flush() or the next frame), and the next file is written
    const auto flushed = again.flush();
    EXPECT_TRUE(!r1 || !flushed) << "the failed write was not reported";
    if (!flushed) {
        EXPECT_EQ(flushed.error().code, Errc::Io);
    }
    EXPECT_TRUE(again.flush()) << "an error is reported once";
    EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/burst-000001.png"));
}

TEST_F(RenderGoldenTest, cpuAndShaderColourConversionAgree)
{
    // GIVEN a bumpy surface with a colour frame of steep gradients that stay in gamut (odd size)
    const Depth8 d(97, 65, bumpy);
    Yuv420 col(97, 65, [](int c, int r) {
        return std::array<int, 3>{50 + c + r, 60 + 3 * c / 2, 170 - r};
    });
    ASSERT_TRUE(renderer_->setDepth(d.view()));
    setMode(StereoMode::SideBySide, 1.04, {MeshMode::Fixed, 16, 1, 0.0, 16});
    std::vector<Picture> pictures;
    for (const ColorConversion where : {ColorConversion::Shader, ColorConversion::Cpu}) {
        RendererOptions o = renderer_->options();
        o.colorConversion = where;
        o.colorFilter = ColorFilter::Linear; // the CPU path interpolates chroma as GL_LINEAR does
        ASSERT_TRUE(renderer_->setOptions(o));
        ASSERT_TRUE(renderer_->setColor(col.view(), ColorSpec{YuvMatrix::Bt709, false}));
        EXPECT_EQ(renderer_->colorConvertedOnCpu(), where == ColorConversion::Cpu);
        // WHEN the same frame is drawn with the conversion in the fragment shader and on the CPU
        pictures.push_back(draw(300, 120));
    }
    // THEN the pictures agree within rounding (the CPU path rounds to 8 bits before filtering; in
    // gamut, filtering R'G'B' or Y'CbCr is the same linear map)
    int worst = 0;
    long long sum = 0;
    for (std::size_t i = 0; i < pictures[0].rgb.size(); ++i) {
        const int diff = std::abs(pictures[0].rgb[i] - pictures[1].rgb[i]);
        worst = std::max(worst, diff);
        sum += diff;
    }
    EXPECT_LE(worst, 3);
    EXPECT_LT(static_cast<double>(sum) / static_cast<double>(pictures[0].rgb.size()), 0.5);
    EXPECT_GT(std::count_if(pictures[1].rgb.begin(), pictures[1].rgb.end(), [](std::uint8_t v) { return v > 100; }),
              1000) << "the surface was drawn";
}

TEST_F(RenderGoldenTest, colourFilterIsHonoured)
{
    // GIVEN a flat surface coloured by a 2×2 frame of black and white columns, stretched over the
    // whole eye, on the CPU path
    const Depth8 d(32, 32, [](int, int) { return 128; });
    Yuv420 col(2, 2, [](int c, int) {
        return std::array<int, 3>{c == 0 ? 16 : 235, 128, 128};
    });
    ASSERT_TRUE(renderer_->setDepth(d.view()));
    setMode(StereoMode::Mono);
    std::array<std::size_t, 2> mids{};
    for (const ColorFilter f : {ColorFilter::Nearest, ColorFilter::Linear}) {
        RendererOptions o = renderer_->options();
        o.colorConversion = ColorConversion::Cpu;
        o.colorFilter = f;
        ASSERT_TRUE(renderer_->setOptions(o));
        ASSERT_TRUE(renderer_->setColor(col.view(), ColorSpec{YuvMatrix::Bt709, false}));
        // WHEN drawn with nearest and with bilinear sampling
        const Picture p = draw(160, 120);
        std::size_t mid = 0;
        for (std::size_t i = 0; i < p.rgb.size(); ++i)
            mid += p.rgb[i] > 40 && p.rgb[i] < 215 ? 1u : 0u;
        mids[f == ColorFilter::Nearest ? 0 : 1] = mid;
    }
    // THEN nearest shows only the two colours (and the black background) while bilinear blends
    // them into a ramp across the middle
    EXPECT_EQ(mids[0], 0u);
    EXPECT_GT(mids[1], 1000u);
}

TEST_F(RenderGoldenTest, framePreparedAheadDrawsTheSamePicture)
{
    // GIVEN a bumpy depth frame and a colour frame, on the CPU colour path with the default mesh
    const Depth8 d(97, 65, bumpy);
    Yuv420 col(97, 65, [](int c, int r) {
        return std::array<int, 3>{40 + c + r, 90 + c / 2, 160 - r};
    });
    setMode(StereoMode::SideBySide, 1.04, MeshOptions{});
    RendererOptions o = renderer_->options();
    o.colorConversion = ColorConversion::Cpu;
    ASSERT_TRUE(renderer_->setOptions(o));
    ASSERT_TRUE(renderer_->convertsColorOnCpu());
    // WHEN drawn directly
    ASSERT_TRUE(renderer_->setDepth(d.view()));
    ASSERT_TRUE(renderer_->setColor(col.view(), ColorSpec{YuvMatrix::Bt601, false}));
    const Picture direct = draw(300, 120);
    const std::size_t triangles = renderer_->mesh().indices().size() / 3;
    // AND from a FramePrep built on another thread
    FramePrep prep;
    std::thread worker([&] {
        const hal::ImageView colour = col.view();
        ASSERT_TRUE(prep.build(d.view(), &colour, ColorSpec{YuvMatrix::Bt601, false}, renderer_->options().mesh));
    });
    worker.join();
    ASSERT_TRUE(prep.built());
    ASSERT_TRUE(renderer_->setDepth(d.view(), prep));
    ASSERT_TRUE(renderer_->setColor(prep));
    const Picture prepared = draw(300, 120);
    // THEN the pictures and meshes are identical
    EXPECT_EQ(renderer_->mesh().indices().size() / 3, triangles);
    EXPECT_EQ(prepared.rgb, direct.rgb);
    EXPECT_GT(std::count_if(direct.rgb.begin(), direct.rgb.end(), [](std::uint8_t v) { return v > 60; }), 1000)
        << "the surface was drawn";
    // AND a prep of another frame, or built with other mesh options, is not used for this one
    const Depth8 other(97, 65, [](int, int) { return 10; });
    ASSERT_TRUE(prep.build(other.view(), nullptr, ColorSpec{}, renderer_->options().mesh));
    ASSERT_TRUE(renderer_->setDepth(d.view(), prep));
    EXPECT_EQ(renderer_->mesh().indices().size() / 3, triangles);
    EXPECT_FALSE(renderer_->setColor(prep)) << "no colour was converted";
    // AND bad colour is refused by the prep
    const hal::ImageView bad{};
    EXPECT_FALSE(prep.build(d.view(), &bad, ColorSpec{}, renderer_->options().mesh));
    EXPECT_FALSE(prep.built());
}

TEST_F(RenderGoldenTest, stageTimesAreRecordedPerEye)
{
    const Depth8 d(64, 48, bumpy);
    ASSERT_TRUE(renderer_->setDepth(d.view()));
    renderer_->setStageTiming(StageTiming::Finished);
    // WHEN a mono frame follows a side-by-side one
    setMode(StereoMode::SideBySide);
    (void)draw(200, 100);
    const StageTimes sbs = renderer_->stageTimes();
    setMode(StereoMode::Mono);
    (void)draw(200, 100);
    const StageTimes mono = renderer_->stageTimes();
    // THEN both eyes have a time in stereo, the second none in mono
    EXPECT_GT(sbs.eye[0], 0.0);
    EXPECT_GT(sbs.eye[1], 0.0);
    EXPECT_GT(mono.eye[0], 0.0);
    EXPECT_EQ(mono.eye[1], 0.0);
    EXPECT_GE(mono.clear, 0.0);
    EXPECT_GE(mono.overlay, 0.0);
}

TEST_F(RenderGoldenTest, badInputIsRefused)
{
    auto t = RenderTarget::create(32, 32);
    ASSERT_TRUE(t);
    EXPECT_EQ(renderer_->render(*t).error().code, Errc::InvalidState);
    haptics::DepthFrameView bad;
    EXPECT_EQ(renderer_->setDepth(bad).error().code, Errc::InvalidArgument);
    Yuv420 col(8, 8, [](int, int) { return std::array<int, 3>{0, 0, 0}; });
    hal::ImageView v = col.view();
    v.format = hal::PixelFormat::Nv12;
    EXPECT_EQ(renderer_->setColor(v, ColorSpec{}).error().code, Errc::NotSupported);
    EXPECT_FALSE(RenderTarget::create(0, 10));
}
