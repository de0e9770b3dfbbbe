/// \file
/// \brief Eye cameras (parallax sign, zero-parallax plane, layouts), the depth-frame mapping shared
/// with the haptic renderer, and the Y'CbCr matrices against the standards' published coefficients.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec4.hpp>

#include "app/render/render_test_support.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/render/color.h"
#include "depthtouch/render/stereo.h"
#include "depthtouch/render/surface_mapping.h"

using namespace depthtouch;
using namespace depthtouch::render;

namespace {

/// Window x (pixels, within the eye's viewport) of scene point \a p.
double windowX(const EyeView &e, glm::vec3 p)
{
    const glm::vec4 clip = e.projection * e.view * glm::vec4(p, 1.0f);
    const double ndc = static_cast<double>(clip.x / clip.w);
    return (ndc + 1.0) * 0.5 * e.viewport.width;
}

} // namespace

TEST(StereoCameraTest, nearPointsHaveCrossedParallaxFarPointsUncrossed)
{
    StereoParams p;
    int n = 0;
    const auto eyes = eyeViews(StereoMode::SideBySide, p, 1440, 486, 0.10, 0.067, 0.04, n);
    ASSERT_EQ(n, 2);
    // GIVEN a point in front of the zero-parallax plane (z = 0 with the default convergence)
    const glm::vec3 nearP(0.01f, 0.0f, 0.02f);
    const glm::vec3 farP(0.01f, 0.0f, -0.02f);
    const glm::vec3 screenP(0.01f, 0.0f, 0.0f);
    // THEN its left-eye image is right of its right-eye image (crossed), a far point the reverse,
    // and a point on the screen plane has none
    EXPECT_GT(windowX(eyes[0], nearP) - windowX(eyes[1], nearP), 1.0);
    EXPECT_LT(windowX(eyes[0], farP) - windowX(eyes[1], farP), -1.0);
    EXPECT_NEAR(windowX(eyes[0], screenP), windowX(eyes[1], screenP), 1e-3);
}

TEST(StereoCameraTest, convergenceMovesTheZeroParallaxPlane)
{
    StereoParams p;
    p.convergence = p.viewDistance - 0.02; // the screen plane at z = +0.02
    int n = 0;
    const auto eyes = eyeViews(StereoMode::SideBySide, p, 1440, 486, 0.10, 0.067, 0.04, n);
    const glm::vec3 onScreen(-0.02f, 0.01f, 0.02f);
    EXPECT_NEAR(windowX(eyes[0], onScreen), windowX(eyes[1], onScreen), 1e-3);
    // z = 0 is now behind the screen: uncrossed
    const glm::vec3 mid(-0.02f, 0.01f, 0.0f);
    EXPECT_LT(windowX(eyes[0], mid), windowX(eyes[1], mid));
}

TEST(StereoCameraTest, layoutsSplitTheFrame)
{
    StereoParams p;
    int n = 0;
    auto e = eyeViews(StereoMode::SideBySide, p, 101, 50, 0.1, 0.05, 0.04, n);
    EXPECT_EQ(e[0].viewport.x, 0);
    EXPECT_EQ(e[0].viewport.width + e[1].viewport.width, 101);
    EXPECT_EQ(e[1].viewport.x, e[0].viewport.width);
    e = eyeViews(StereoMode::TopAndBottom, p, 100, 51, 0.1, 0.05, 0.04, n);
    EXPECT_EQ(e[1].viewport.y, 0);
    EXPECT_EQ(e[0].viewport.y, e[1].viewport.height); // left eye on top
    EXPECT_EQ(e[0].viewport.height + e[1].viewport.height, 51);
    e = eyeViews(StereoMode::Anaglyph, p, 100, 50, 0.1, 0.05, 0.04, n);
    EXPECT_EQ(e[0].colorMask, 0x1);
    EXPECT_EQ(e[1].colorMask, 0x6);
    e = eyeViews(StereoMode::RowInterleaved, p, 100, 50, 0.1, 0.05, 0.04, n);
    EXPECT_EQ(e[0].rowParity, 1); // top row is window row 49
    EXPECT_EQ(e[1].rowParity, 0);
    e = eyeViews(StereoMode::Mono, p, 100, 50, 0.1, 0.05, 0.04, n);
    EXPECT_EQ(n, 1);
    EXPECT_EQ(e[0].eyeOffset, 0.0);
    for (const char *name : {"mono", "sbs", "tab", "anaglyph", "interleaved"})
        EXPECT_STREQ(stereoModeName(*parseStereoMode(name)), name);
    EXPECT_FALSE(parseStereoMode("3d"));
    // full-aspect halves: each sbs eye projects like a mono view of its own W/2×H size
    p.frameCompatible = false;
    p.eyeSeparation = 0.0;
    e = eyeViews(StereoMode::SideBySide, p, 200, 50, 0.1, 0.05, 0.04, n);
    const auto mono = eyeViews(StereoMode::Mono, p, 100, 50, 0.1, 0.05, 0.04, n);
    EXPECT_FLOAT_EQ(e[0].projection[0][0], mono[0].projection[0][0]);
    EXPECT_FLOAT_EQ(e[0].projection[1][1], mono[0].projection[1][1]);
}

TEST(SurfaceMappingTest, isTheHapticHeightFieldMapping)
{
    const test::Depth8 d(11, 7, [](int c, int r) { return 20 * c + r; });
    scene::SceneBox box{0.12, 0.05};
    haptics::HeightField hf(box);
    ASSERT_TRUE(hf.setFrames(d.view(), nullptr));
    const auto mapping = SurfaceMapping::of(box, d.view());
    ASSERT_TRUE(mapping);
    const SurfaceMapping m = *mapping;
    EXPECT_EQ(m.columns, 11);
    EXPECT_EQ(m.rows, 7);
    for (int r = 0; r < 7; ++r)
        for (int c = 0; c < 11; ++c) {
            const glm::dvec3 want = hf.vertex(c, r);
            const glm::dvec3 got = m.point(c, r, d.view().sample(c, r));
            EXPECT_NEAR(got.x, want.x, 1e-12);
            EXPECT_NEAR(got.y, want.y, 1e-12);
            EXPECT_NEAR(got.z, want.z, 1e-12);
        }
    EXPECT_NEAR(m.width(), 0.12, 1e-12);
    EXPECT_NEAR(m.levelMetres(), 0.05 / 255.0, 1e-15);
}

TEST(YuvToRgbTest, bt601LimitedMatchesThePublishedCoefficients)
{
    // R = 1.164(Y−16) + 1.596(V−128); G = 1.164(Y−16) − 0.392(U−128) − 0.813(V−128);
    // B = 1.164(Y−16) + 2.017(U−128)  (ITU-R BT.601, 8-bit limited range, rounded coefficients)
    const YuvToRgb m = yuvToRgb(ColorSpec{YuvMatrix::Bt601, false});
    for (const auto &yuv :
         {glm::ivec3(16, 128, 128), glm::ivec3(235, 128, 128), glm::ivec3(81, 90, 240),
          glm::ivec3(145, 54, 34), glm::ivec3(41, 240, 110)}) {
        const glm::vec3 in = glm::vec3(yuv) / 255.0f;
        const glm::vec3 rgb = m.matrix * (in - m.offset) * 255.0f;
        const double y = yuv.x - 16.0;
        const double u = yuv.y - 128.0;
        const double v = yuv.z - 128.0;
        EXPECT_NEAR(rgb.r, 1.164 * y + 1.596 * v, 0.6);
        EXPECT_NEAR(rgb.g, 1.164 * y - 0.392 * u - 0.813 * v, 0.6);
        EXPECT_NEAR(rgb.b, 1.164 * y + 2.017 * u, 0.6);
    }
}

TEST(YuvToRgbTest, bt709FullRangeMatchesThePublishedCoefficients)
{
    // BT.709 full range: R = Y + 1.5748 V; G = Y − 0.1873 U − 0.4681 V; B = Y + 1.8556 U
    const YuvToRgb m = yuvToRgb(ColorSpec{YuvMatrix::Bt709, true});
    const glm::vec3 in = glm::vec3(120.0f, 60.0f, 200.0f) / 255.0f;
    const glm::vec3 rgb = m.matrix * (in - m.offset) * 255.0f;
    EXPECT_NEAR(rgb.r, 120.0 + 1.5748 * 72.0, 0.1);
    EXPECT_NEAR(rgb.g, 120.0 - 0.1873 * -68.0 - 0.4681 * 72.0, 0.1);
    EXPECT_NEAR(rgb.b, 120.0 + 1.8556 * -68.0, 0.1);
}

TEST(YuvConverterTest, cpuConversionIsTheMatrixWithBilinearChroma)
{
    // GIVEN a 6×4 yuv420p frame whose chroma differs per 2×2 block, both matrices and ranges
    std::vector<std::uint8_t> y(24), u(6), v(6);
    for (std::size_t i = 0; i < y.size(); ++i)
        y[i] = static_cast<std::uint8_t>(20 + 9 * i);
    for (std::size_t i = 0; i < u.size(); ++i) {
        u[i] = static_cast<std::uint8_t>(60 + 25 * i);
        v[i] = static_cast<std::uint8_t>(200 - 21 * i);
    }
    hal::ImageView img;
    img.width = 6;
    img.height = 4;
    img.format = hal::PixelFormat::Yuv420p;
    img.planes[0] = {y.data(), 6};
    img.planes[1] = {u.data(), 3};
    img.planes[2] = {v.data(), 3};
    YuvConverter conv;
    for (const ColorSpec spec :
         {ColorSpec{YuvMatrix::Bt601, false}, ColorSpec{YuvMatrix::Bt709, true}}) {
        const std::vector<std::uint32_t> &px = conv.convert(img, spec);
        ASSERT_EQ(px.size(), 24u);
        const YuvToRgb m = yuvToRgb(spec);
        // A GL_LINEAR, clamp-to-edge lookup at the luma sample's centre, in chroma texels.
        const auto tap = [](int i, int luma, int chroma, int &i0, int &i1, double &w) {
            const double t = (i + 0.5) / luma * chroma - 0.5;
            const double f = std::floor(t);
            w = t - f;
            i0 = std::clamp(static_cast<int>(f), 0, chroma - 1);
            i1 = std::clamp(static_cast<int>(f) + 1, 0, chroma - 1);
        };
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 6; ++c) {
                int c0, c1, r0, r1;
                double wc, wr;
                tap(c, 6, 3, c0, c1, wc);
                tap(r, 4, 2, r0, r1, wr);
                const auto bil = [&](const std::vector<std::uint8_t> &p) {
                    const auto at = [&](int cc, int rr) {
                        return static_cast<double>(p[static_cast<std::size_t>(rr * 3 + cc)]);
                    };
                    return (1 - wr) * ((1 - wc) * at(c0, r0) + wc * at(c1, r0)) +
                           wr * ((1 - wc) * at(c0, r1) + wc * at(c1, r1));
                };
                const glm::dvec3 yuv(y[static_cast<std::size_t>(r * 6 + c)] / 255.0, bil(u) / 255.0,
                                     bil(v) / 255.0);
                const glm::dvec3 rgb = glm::dmat3(m.matrix) * (yuv - glm::dvec3(m.offset));
                const std::uint32_t p = px[static_cast<std::size_t>(r * 6 + c)];
                // THEN each pixel is the matrix applied to the bilinear chroma, within one code
                for (int k = 0; k < 3; ++k) {
                    const double want = std::clamp(rgb[k] * 255.0, 0.0, 255.0);
                    EXPECT_NEAR(static_cast<double>((p >> (8 * k)) & 0xff), want, 1.0)
                        << "pixel " << c << "," << r << " channel " << k;
                }
                EXPECT_EQ(p >> 24, 255u);
            }
    }
}
