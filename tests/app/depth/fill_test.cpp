/// \file
/// \brief Hole filling (push-pull), filters and resampling.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "depthtouch/depth/conversion.h"
#include "depthtouch/depth/fill.h"
#include "depthtouch/depth/filters.h"
#include "depthtouch/depth/resample.h"

using namespace depthtouch;
using namespace depthtouch::depth;

TEST(FillInvalidTest, fillsAHoleInAConstantRegionWithThatDepth)
{
    // GIVEN a constant 90-level surface with a 10×10 hole (invalid samples read as 0 = far plane)
    Plane<float> d(40, 30, 90.0f);
    Plane<std::uint8_t> valid(40, 30, 1);
    for (int y = 10; y < 20; ++y)
        for (int x = 15; x < 25; ++x) {
            d.at(x, y) = 0.0f;
            valid.at(x, y) = 0;
        }
    // WHEN filled
    const auto n = fillInvalid(d, valid);
    ASSERT_TRUE(n);
    // THEN exactly the hole was filled, with the surrounding depth
    EXPECT_EQ(*n, 100u);
    for (const float v : d.samples)
        EXPECT_FLOAT_EQ(v, 90.0f);
}

TEST(FillInvalidTest, fillsFromTheNeighboursAndNeverWithTheFarPlane)
{
    // GIVEN left half at 50 levels, right half at 150, an 8×8 hole inside the left half, and a hole
    // spanning the boundary, all holes carrying 0 (the far plane)
    Plane<float> d(64, 64);
    Plane<std::uint8_t> valid(64, 64, 1);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            d.at(x, y) = x < 32 ? 50.0f : 150.0f;
    const Plane<float> before = d;
    const auto punch = [&](int x0, int y0, int w, int h) {
        for (int y = y0; y < y0 + h; ++y)
            for (int x = x0; x < x0 + w; ++x) {
                d.at(x, y) = 0.0f;
                valid.at(x, y) = 0;
            }
    };
    punch(12, 20, 8, 8);
    punch(28, 44, 8, 8);
    ASSERT_TRUE(fillInvalid(d, valid));
    // THEN the hole inside the left half takes the left depth, the boundary hole stays within the
    // neighbours' range, and valid samples are untouched
    for (int y = 20; y < 28; ++y)
        for (int x = 12; x < 20; ++x)
            EXPECT_NEAR(d.at(x, y), 50.0f, 0.5f);
    for (int y = 44; y < 52; ++y)
        for (int x = 28; x < 36; ++x) {
            EXPECT_GE(d.at(x, y), 50.0f);
            EXPECT_LE(d.at(x, y), 150.0f);
        }
    for (std::size_t i = 0; i < d.size(); ++i) {
        if (valid.samples[i] != 0) {
            EXPECT_EQ(d.samples[i], before.samples[i]);
        }
    }
}

TEST(FillInvalidTest, fillsBorderHolesAndRefusesAFrameWithoutData)
{
    // GIVEN a ramp whose first 10 columns are invalid
    Plane<float> d(50, 20);
    Plane<std::uint8_t> valid(50, 20, 1);
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 50; ++x) {
            d.at(x, y) = x < 10 ? 0.0f : static_cast<float>(100 + x);
            valid.at(x, y) = x < 10 ? 0 : 1;
        }
    ASSERT_TRUE(fillInvalid(d, valid));
    // THEN the border is filled with values of the valid data's range (not 0)
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 10; ++x) {
            EXPECT_GE(d.at(x, y), 110.0f);
            EXPECT_LE(d.at(x, y), 149.0f);
        }
    Plane<float> none(4, 4, 0.0f);
    EXPECT_EQ(fillInvalid(none, Plane<std::uint8_t>(4, 4, 0)).error().code, Errc::InvalidArgument);
    EXPECT_EQ(fillInvalid(none, Plane<std::uint8_t>(3, 4, 1)).error().code, Errc::InvalidArgument);
    EXPECT_EQ(fillInvalid(none, Plane<std::uint8_t>(4, 4, 1)).value(), 0u);
}

TEST(FillInvalidTest, convertedMetricFrameHasNoFarPlaneHoles)
{
    // GIVEN raw mm depth 1000..1300 with invalid 0 and 65535 samples scattered
    Plane<std::uint16_t> raw(32, 32);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x)
            raw.at(x, y) = static_cast<std::uint16_t>(1000 + 10 * x);
    for (int i = 0; i < 32; i += 3) {
        raw.at(i, (i * 7) % 32) = 0;
        raw.at((i * 5) % 32, i) = 65535;
    }
    ConvertOptions o;
    o.range = DepthRange{0.5, 4.0};
    auto f = metricToNearness(raw, o);
    ASSERT_TRUE(f);
    ASSERT_GT(f->invalidCount, 0u);
    ASSERT_TRUE(fillInvalid(f->nearness, f->valid));
    const float farthestValid = static_cast<float>(
        metresToNearness(1.311, DepthRange{0.5, 4.0}, DepthMapping::InverseZ, 255.0));
    for (const float v : f->nearness.samples)
        EXPECT_GE(v, farthestValid);
}

TEST(MedianFilterTest, takesTheMiddleValueOfKnownWindows)
{
    // GIVEN 1..9 in a 3×3 image
    Plane<float> p(3, 3);
    for (int i = 0; i < 9; ++i)
        p.samples[static_cast<std::size_t>(i)] = static_cast<float>(9 - i);
    // THEN the 3×3 median of the centre is 5; the top-left corner sees (replicated border)
    // 9 9 8 / 9 9 8 / 6 6 5 → median 8
    const Plane<float> m = medianFilter(p, 1);
    EXPECT_FLOAT_EQ(m.at(1, 1), 5.0f);
    EXPECT_FLOAT_EQ(m.at(0, 0), 8.0f);
}

TEST(MedianFilterTest, removesImpulsesAndKeepsAStepEdge)
{
    // GIVEN a vertical step 40 | 200 with salt-and-pepper impulses away from each other
    Plane<float> p(30, 30);
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 30; ++x)
            p.at(x, y) = x < 15 ? 40.0f : 200.0f;
    Plane<float> clean = p;
    for (int k = 0; k < 30; k += 4) {
        p.at((k * 7) % 30, k) = 255.0f;
        p.at((k * 11 + 3) % 30, (k + 2) % 30) = 0.0f;
    }
    // WHEN 5×5 median filtered
    const Plane<float> m = medianFilter(p, 2);
    // THEN the clean step comes back exactly
    EXPECT_EQ(m.samples, clean.samples);
}

TEST(GradientTest, measuresSlopeInLevelsPerPixel)
{
    Plane<float> ramp(20, 10);
    for (int y = 0; y < 10; ++y)
        for (int x = 0; x < 20; ++x)
            ramp.at(x, y) = 0.5f * static_cast<float>(x) + 0.25f * static_cast<float>(y);
    const Plane<float> g = gradientMagnitude(ramp);
    EXPECT_NEAR(g.at(10, 5), std::sqrt(0.25 + 0.0625), 1e-5);
    EXPECT_NEAR(laplacian(ramp).at(10, 5), 0.0f, 1e-4);
}

TEST(ResampleTest, nearestAndEdgeAwareKeepStepsSharpAndRampsSmooth)
{
    // GIVEN 8×4 with a ramp on the left and a step at the right
    Plane<float> src(8, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x)
            src.at(x, y) = x < 4 ? static_cast<float>(10 * x) : 200.0f;
    // WHEN doubled with the edge-aware method (threshold 15 levels)
    const auto up = resample(src, 16, 8, ResampleMethod::EdgeAware, 15.0f);
    ASSERT_TRUE(up);
    // THEN the ramp is interpolated (between 0 and 30, strictly increasing inside) ...
    for (int x = 1; x < 7; ++x)
        EXPECT_LT(up->at(x - 1, 3), up->at(x, 3));
    // ... and across the step no value falls between the sides (30 | 200)
    for (int x = 6; x < 10; ++x) {
        const float v = up->at(x, 3);
        EXPECT_TRUE(v <= 30.0f || v == 200.0f) << "x=" << x << " v=" << v;
    }
    // Nearest halves by picking source samples.
    const auto down = resample(src, 4, 2, ResampleMethod::Nearest);
    ASSERT_TRUE(down);
    EXPECT_EQ(down->samples, (std::vector<float>{10, 30, 200, 200, 10, 30, 200, 200}));
    EXPECT_FALSE(resample(src, 0, 2));
}
