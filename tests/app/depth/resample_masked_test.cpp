/// \file
/// \brief resampleMasked (measured depth resampled with its holes kept, docs/architecture.md §3
/// "Holes") against values worked out here: the bilinear value of a ramp at each output sample's
/// source position, hole values that never leak, a step kept sharp, the mask resampled nearest.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "depthtouch/depth/resample.h"

using namespace depthtouch;
using namespace depthtouch::depth;

namespace {

constexpr int kWs = 8, kHs = 6, kW = 12, kH = 9;

double ramp(double x, double y)
{
    return 10.0 + 2.0 * x + 3.0 * y;
}

/// The source position of output sample (x, y) (resample.h: centres aligned).
double sourceX(int x)
{
    return (x + 0.5) * kWs / kW - 0.5;
}
double sourceY(int y)
{
    return (y + 0.5) * kHs / kH - 0.5;
}

Plane<float> rampPlane()
{
    Plane<float> p(kWs, kHs);
    for (int y = 0; y < kHs; ++y)
        for (int x = 0; x < kWs; ++x)
            p.at(x, y) = static_cast<float>(ramp(x, y));
    return p;
}

} // namespace

TEST(ResampleMaskedTest, aMeasuredRampIsInterpolatedExactly)
{
    // GIVEN a measured ramp of 10 + 2x + 3y levels on 8×6 samples
    const Plane<float> src = rampPlane();
    const Plane<std::uint8_t> valid(kWs, kHs, 1);
    Plane<std::uint8_t> validOut;
    // WHEN resampled to 12×9 with a threshold above the ramp's 2×2 range (5 levels)
    auto out = resampleMasked(src, valid, kW, kH, 6.0f, validOut);
    ASSERT_TRUE(out) << out.error().what;
    ASSERT_EQ(out->width, kW);
    ASSERT_EQ(out->height, kH);
    // THEN inside the source grid each sample is the ramp at its source position (bilinear is
    // exact on a plane), and every sample is measured
    int inside = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            EXPECT_EQ(validOut.at(x, y), 1);
            const double sx = sourceX(x), sy = sourceY(y);
            if (sx < 0.0 || sy < 0.0 || sx > kWs - 1 || sy > kHs - 1)
                continue;
            EXPECT_NEAR(out->at(x, y), ramp(sx, sy), 1e-4) << x << "," << y;
            ++inside;
        }
    EXPECT_GT(inside, 60);
}

TEST(ResampleMaskedTest, holesKeepTheirPlaceAndNeverBlendIntoMeasuredDepth)
{
    // GIVEN the ramp with a 2×2 hole whose samples hold 1000 (a value no measured sample has)
    Plane<float> src = rampPlane();
    Plane<std::uint8_t> valid(kWs, kHs, 1);
    for (int y = 2; y < 4; ++y)
        for (int x = 3; x < 5; ++x) {
            src.at(x, y) = 1000.0f;
            valid.at(x, y) = 0;
        }
    Plane<std::uint8_t> validOut;
    auto out = resampleMasked(src, valid, kW, kH, 6.0f, validOut);
    ASSERT_TRUE(out) << out.error().what;
    // THEN the mask is the nearest source flag, holes read 0, and a measured sample lies within
    // the measured ramp's values around it (renormalised over the measured neighbours only)
    const Plane<std::uint8_t> nearest = resampleNearest(valid, kW, kH);
    int holes = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            ASSERT_EQ(validOut.at(x, y), nearest.at(x, y)) << x << "," << y;
            if (validOut.at(x, y) == 0) {
                EXPECT_EQ(out->at(x, y), 0.0f);
                ++holes;
                continue;
            }
            const double sx = std::clamp(sourceX(x), 0.0, kWs - 1.0);
            const double sy = std::clamp(sourceY(y), 0.0, kHs - 1.0);
            EXPECT_GE(out->at(x, y), ramp(std::floor(sx), std::floor(sy)) - 1e-4) << x << "," << y;
            EXPECT_LE(out->at(x, y), ramp(std::ceil(sx), std::ceil(sy)) + 1e-4) << x << "," << y;
        }
    EXPECT_GT(holes, 0);
}

TEST(ResampleMaskedTest, aStepAboveTheThresholdStaysSharp)
{
    // GIVEN a measured step from 20 to 200 levels between columns 3 and 4
    Plane<float> src(kWs, kHs, 20.0f);
    for (int y = 0; y < kHs; ++y)
        for (int x = 4; x < kWs; ++x)
            src.at(x, y) = 200.0f;
    const Plane<std::uint8_t> valid(kWs, kHs, 1);
    Plane<std::uint8_t> validOut;
    auto out = resampleMasked(src, valid, kW, kH, 4.0f, validOut);
    ASSERT_TRUE(out) << out.error().what;
    // THEN every sample is one side's value (the neighbour of largest weight), none between
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const float v = out->at(x, y);
            EXPECT_TRUE(v == 20.0f || v == 200.0f) << x << "," << y << ": " << v;
            EXPECT_EQ(v, sourceX(x) < 3.5 ? 20.0f : 200.0f) << x << "," << y;
        }
}

TEST(ResampleMaskedTest, badSizesAreRefused)
{
    Plane<std::uint8_t> validOut;
    const Plane<float> src = rampPlane();
    EXPECT_FALSE(resampleMasked(src, Plane<std::uint8_t>(kWs, kHs - 1, 1), kW, kH, 4.0f, validOut));
    EXPECT_FALSE(resampleMasked(src, Plane<std::uint8_t>(kWs, kHs, 1), 0, kH, 4.0f, validOut));
    EXPECT_FALSE(resampleMasked(Plane<float>(), Plane<std::uint8_t>(), kW, kH, 4.0f, validOut));
}
