/// \file
/// \brief Golden-image tests of the stereo renderer on a real GLES 3 context (EGL surfaceless,
/// llvmpipe): known depth + colour → expected pixels with a tolerance, the parallax sign, each
/// output layout, Y'CbCr accuracy, the CPU and shader colour paths, the colour filter, frames
/// prepared ahead, stage times and refused input. The drawn surface against the touched one:
/// golden_surface_test.cpp; avatar, OSD and snapshots: golden_overlay_test.cpp (fixture and
/// helpers: golden_fixture.h). Skips when EGL has no surfaceless platform.

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

TEST_F(RenderGoldenTest, flatPlaneWithSolidColorFillsTheBoxRegion)
{
    // GIVEN a flat depth frame at mid nearness and a solid red colour frame (BT.601 limited)
    ASSERT_NO_FATAL_FAILURE(
        showFlatPlane(64, 43, {81, 90, 240}, 1.3, ColorSpec{YuvMatrix::Bt601, false}));
    // WHEN drawn mono into 160×120
    const Picture p = draw(160, 120);
    // THEN the box's projected rectangle is red and the rest is the black background
    const auto eyes = eyesFor(StereoMode::Mono, 160, 120);
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
    // GIVEN a far plane with a raised square in its middle (nearness 255 = nearest) with a red mark
    // on it (its edges are not the measure: the mesh's steep sides between the far plane and the
    // square stretch the colour across the depth edge, DIBR's rubber sheet)
    const auto inSquare = [](int c, int r) { return c >= 24 && c <= 40 && r >= 16 && r <= 32; };
    const auto inMark = [](int c, int r) { return c >= 30 && c <= 34 && r >= 22 && r <= 26; };
    const Depth8 d(64, 48, [&](int c, int r) { return inSquare(c, r) ? 255 : 0; });
    Yuv420 col(64, 48, [&](int c, int r) {
        return inMark(c, r)     ? std::array<int, 3>{81, 90, 240}
               : inSquare(c, r) ? std::array<int, 3>{235, 128, 128}
                                : std::array<int, 3>{40, 128, 128};
    });
    setMode(StereoMode::SideBySide);
    ASSERT_TRUE(renderer_->setDepth(d.view()));
    ASSERT_TRUE(renderer_->setColor(col.view(), ColorSpec{}));
    // WHEN drawn side-by-side
    const Picture p = draw(320, 120);
    const auto red = [](Rgb c) { return c.r > 200 && c.g < 60 && c.b < 60; };
    const Blob left = findBlob(p, 0, 160, 0, 120, red);
    const Blob right = findBlob(p, 160, 320, 0, 120, red);
    ASSERT_GT(left.count, 20);
    ASSERT_GT(right.count, 20);
    // THEN the near mark's left-eye image is right of its right-eye image (crossed parallax), by
    // the disparity the eye cameras predict
    const auto eyes = eyesFor(StereoMode::SideBySide, 320, 120);
    const glm::dvec3 centre = renderer_->mapping().point(32, 24, 255);
    const double predicted =
        project(eyes[0], 120, centre).x - (project(eyes[1], 120, centre).x - 160);
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

// The picture is the source's (docs/playing.md "Picture"): with the default margin the mono view of
// a W×H frame drawn into W×H pixels is the colour frame pixel for pixel, a near disc in front of a
// far wall included (a camera that scales points by their distance draws the disc bigger relative
// to the wall and leaves a border: 20 dB here). The reference is the BT.601 limited-range formula
// computed here from the luma (grey chroma, so no chroma filter enters).
TEST_F(RenderGoldenTest, theMonoViewIsTheSourcePicturePixelForPixel)
{
    // GIVEN a far wall and a near disc at the left edge, each with a texture of its own
    constexpr int kW = 96;
    constexpr int kH = 72;
    const auto inDisc = [](int c, int r) {
        return (c - 14) * (c - 14) + (r - 36) * (r - 36) < 196;
    };
    const Depth8 d(kW, kH, [&](int c, int r) { return inDisc(c, r) ? 250 : 10 + r / 8; });
    const auto luma = [&](int c, int r) {
        return inDisc(c, r) ? 235 - ((c / 3 + r / 3) % 2) * 55 : 40 + (c * 5 + r * 3) % 100;
    };
    Yuv420 col(kW, kH, [&](int c, int r) { return std::array<int, 3>{luma(c, r), 128, 128}; });
    RendererOptions o = renderer_->options();
    o.mode = StereoMode::Mono;
    o.stereo = StereoParams{}; // the product's defaults: margin 1
    ASSERT_TRUE(renderer_->setOptions(o));
    ASSERT_TRUE(renderer_->setDepth(d.view()));
    ASSERT_TRUE(renderer_->setColor(col.view(), ColorSpec{YuvMatrix::Bt601, false}));
    // WHEN drawn mono at the source size
    const Picture p = draw(kW, kH);
    // THEN every pixel is the colour frame's: PSNR ≥ 35 dB (8-bit peak), and the disc's first
    // and last bright columns on its middle row are the source's
    double se = 0.0;
    for (int r = 0; r < kH; ++r)
        for (int c = 0; c < kW; ++c) {
            const double want = std::clamp(255.0 / 219.0 * (luma(c, r) - 16), 0.0, 255.0);
            const Rgb got = p.at(c, r);
            for (const int v : {got.r, got.g, got.b})
                se += (v - want) * (v - want);
        }
    const double mse = se / (3.0 * kW * kH);
    const double psnr = 10.0 * std::log10(255.0 * 255.0 / std::max(mse, 1e-9));
    EXPECT_GE(psnr, 35.0) << "mse " << mse;
    const Blob disc = findBlob(p, 0, kW, 36, 37, [](Rgb c) { return c.r > 170; });
    EXPECT_EQ(disc.x0, 1); // columns 1..27 of the source are in the disc on row 36
    EXPECT_EQ(disc.x1, 27);
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
    const Blob redOnly =
        findBlob(p, 0, 160, 0, 120, [](Rgb c) { return c.r > 200 && c.g < 30 && c.b < 30; });
    const Blob cyanOnly =
        findBlob(p, 0, 160, 0, 120, [](Rgb c) { return c.r < 30 && c.g > 200 && c.b > 200; });
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
    Yuv420 col(64, 48, [&](int c, int r) {
        return patches[static_cast<std::size_t>((r / 24) * 4 + c / 16)];
    });
    ASSERT_TRUE(renderer_->setDepth(d.view()));
    ASSERT_TRUE(renderer_->setColor(col.view(), ColorSpec{YuvMatrix::Bt601, false}));
    // WHEN drawn from straight above, one pixel per sample
    auto t = RenderTarget::create(64, 48);
    ASSERT_TRUE(t);
    t->bind();
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    ASSERT_TRUE(renderer_->drawSurface(
        topView(64, 48, renderer_->mapping().width(), renderer_->mapping().height(), 0.04),
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

TEST_F(RenderGoldenTest, cpuAndShaderColorConversionAgree)
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
    EXPECT_GT(std::count_if(pictures[1].rgb.begin(), pictures[1].rgb.end(),
                            [](std::uint8_t v) { return v > 100; }),
              1000)
        << "the surface was drawn";
}

TEST_F(RenderGoldenTest, colorFilterIsHonoured)
{
    // GIVEN a flat surface coloured by a 2×2 frame of black and white columns, stretched over the
    // whole eye, on the CPU path
    const Depth8 d(32, 32, [](int, int) { return 128; });
    Yuv420 col(2, 2, [](int c, int) { return std::array<int, 3>{c == 0 ? 16 : 235, 128, 128}; });
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
        const hal::ImageView color = col.view();
        ASSERT_TRUE(prep.build(d.view(), &color, ColorSpec{YuvMatrix::Bt601, false},
                               renderer_->options().mesh));
    });
    worker.join();
    ASSERT_TRUE(prep.built());
    ASSERT_TRUE(renderer_->setDepth(d.view(), prep));
    ASSERT_TRUE(renderer_->setColor(prep));
    const Picture prepared = draw(300, 120);
    // THEN the pictures and meshes are identical
    EXPECT_EQ(renderer_->mesh().indices().size() / 3, triangles);
    EXPECT_EQ(prepared.rgb, direct.rgb);
    EXPECT_GT(
        std::count_if(direct.rgb.begin(), direct.rgb.end(), [](std::uint8_t v) { return v > 60; }),
        1000)
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
    scene::DepthFrameView bad;
    EXPECT_EQ(renderer_->setDepth(bad).error().code, Errc::InvalidArgument);
    Yuv420 col(8, 8, [](int, int) { return std::array<int, 3>{0, 0, 0}; });
    hal::ImageView v = col.view();
    v.format = hal::PixelFormat::Nv12;
    EXPECT_EQ(renderer_->setColor(v, ColorSpec{}).error().code, Errc::NotSupported);
    EXPECT_FALSE(RenderTarget::create(0, 10));
}
