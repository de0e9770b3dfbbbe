/// \file
/// \brief Metric depth → nearness: mappings, robust planes, invalid samples, depth scale.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "depthtouch/depth/conversion.h"

using namespace depthtouch;
using namespace depthtouch::depth;

TEST(DepthMappingTest, inverseZRoundTripsAndHitsThePlanes)
{
    // GIVEN planes at 0.5 m and 4 m
    const DepthRange range{0.5, 4.0};
    for (const DepthMapping m : {DepthMapping::InverseZ, DepthMapping::Linear}) {
        // THEN the planes map to v_max and 0, and every depth in between round-trips
        EXPECT_DOUBLE_EQ(metresToNearness(0.5, range, m, 255.0), 255.0);
        EXPECT_NEAR(metresToNearness(4.0, range, m, 255.0), 0.0, 1e-12);
        for (double z = 0.5; z <= 4.0; z += 0.05) {
            const double v = metresToNearness(z, range, m, 65535.0);
            EXPECT_NEAR(nearnessToMetres(v, range, m, 65535.0), z, 1e-9)
                << mappingName(m) << " z=" << z;
        }
    }
}

TEST(DepthMappingTest, nearerIsBrighterAndOutsideIsClamped)
{
    const DepthRange range{0.8, 3.0};
    for (const DepthMapping m : {DepthMapping::InverseZ, DepthMapping::Linear}) {
        double previous = 256.0;
        for (double z = 0.8; z <= 3.0; z += 0.01) {
            const double v = metresToNearness(z, range, m, 255.0);
            EXPECT_LT(v, previous) << "farther must be darker at z=" << z;
            previous = v;
        }
        EXPECT_DOUBLE_EQ(metresToNearness(0.1, range, m, 255.0), 255.0);
        EXPECT_DOUBLE_EQ(metresToNearness(10.0, range, m, 255.0), 0.0);
    }
}

TEST(DepthMappingTest, inverseZGivesHalfScaleAtTheHarmonicMean)
{
    // 1/Z halfway between 1/near and 1/far: Z = 2·near·far/(near + far) = 0.8 m for 0.5 and 2 m.
    EXPECT_NEAR(metresToNearness(0.8, DepthRange{0.5, 2.0}, DepthMapping::InverseZ, 255.0), 127.5,
                1e-9);
    // The linear mapping puts the arithmetic mean there instead.
    EXPECT_NEAR(metresToNearness(1.25, DepthRange{0.5, 2.0}, DepthMapping::Linear, 255.0), 127.5,
                1e-9);
}

TEST(DepthMappingTest, parsesNamesAndRefusesOthers)
{
    EXPECT_EQ(parseMapping("inverse_z").value(), DepthMapping::InverseZ);
    EXPECT_EQ(parseMapping("linear").value(), DepthMapping::Linear);
    EXPECT_EQ(parseMapping(mappingName(DepthMapping::Linear)).value(), DepthMapping::Linear);
    const auto bad = parseMapping("log");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().code, Errc::InvalidArgument);
}

TEST(MetricToNearnessTest, flagsZeroAndSaturationAsInvalidAndNeverMapsThem)
{
    // GIVEN a frame in mm with a 0 and a 65535 sample
    Plane<std::uint16_t> raw(4, 1);
    raw.samples = {1000, 0, 2000, 65535};
    ConvertOptions o;
    o.range = DepthRange{1.0, 2.0};
    // WHEN converted
    const auto f = metricToNearness(raw, o);
    ASSERT_TRUE(f);
    // THEN the two invalid samples are flagged and counted, the valid ones sit on the planes
    EXPECT_EQ(f->invalidCount, 2u);
    EXPECT_EQ(f->valid.samples, (std::vector<std::uint8_t>{1, 0, 1, 0}));
    EXPECT_FLOAT_EQ(f->nearness.samples[0], 255.0f);
    EXPECT_FLOAT_EQ(f->nearness.samples[2], 0.0f);
}

TEST(MetricToNearnessTest, depthScaleReadsTumUnits)
{
    // GIVEN TUM depth: metres = value / 5000; 5000 → 1 m, 10000 → 2 m
    Plane<std::uint16_t> raw(2, 1);
    raw.samples = {5000, 10000};
    ConvertOptions o;
    o.raw.metresPerUnit = 1.0 / 5000.0;
    o.mapping = DepthMapping::Linear;
    o.range = DepthRange{1.0, 3.0};
    const auto f = metricToNearness(raw, o);
    ASSERT_TRUE(f);
    EXPECT_NEAR(f->nearness.samples[0], 255.0, 1e-4);
    EXPECT_NEAR(f->nearness.samples[1], 127.5, 1e-4);
}

TEST(MetricToNearnessTest, estimatesPlanesFromTheValidDataIgnoringOutliers)
{
    // GIVEN 1000 valid samples 1000..1999 mm, 5 far outliers and many invalid samples
    Plane<std::uint16_t> raw(1100, 1, 0);
    for (int i = 0; i < 1000; ++i)
        raw.samples[static_cast<std::size_t>(i)] = static_cast<std::uint16_t>(1000 + i);
    for (int i = 0; i < 5; ++i)
        raw.samples[static_cast<std::size_t>(1000 + i)] = 30000;
    raw.samples[1099] = 65535;
    // WHEN the planes are estimated at the 1 % and 99 % quantiles
    const auto r = robustRange(raw, RawDepthFormat{});
    ASSERT_TRUE(r);
    // THEN they bracket the bulk and ignore invalid samples and the outliers
    EXPECT_NEAR(r->nearM, 1.010, 0.002);
    EXPECT_NEAR(r->farM, 1.995, 0.006);
}

TEST(MetricToNearnessTest, refusesBadInput)
{
    ConvertOptions o;
    EXPECT_EQ(metricToNearness(Plane<std::uint16_t>{}, o).error().code, Errc::InvalidArgument);
    // No valid sample to estimate the planes from.
    EXPECT_EQ(metricToNearness(Plane<std::uint16_t>(3, 3, 0), o).error().code,
              Errc::InvalidArgument);
    o.range = DepthRange{2.0, 1.0};
    EXPECT_EQ(metricToNearness(Plane<std::uint16_t>(3, 3, 1000), o).error().code,
              Errc::InvalidArgument);
}

TEST(MetricToNearnessTest, eightBitNearnessPassesThroughAndQuantizeRoundTrips)
{
    Plane<std::uint8_t> n8(3, 1);
    n8.samples = {0, 128, 255};
    const NearnessFrame f = nearnessFrom8Bit(n8);
    EXPECT_EQ(f.invalidCount, 0u);
    const Plane<std::uint16_t> q = quantize(f.nearness, 255.0);
    EXPECT_EQ(q.samples, (std::vector<std::uint16_t>{0, 128, 255}));
    Plane<float> over(2, 1);
    over.samples = {-3.0f, 300.4f};
    EXPECT_EQ(quantize(over, 255.0).samples, (std::vector<std::uint16_t>{0, 255}));
}

namespace {

/// docs/architecture.md "Metric depth input": v = v_max·(1/Z − 1/far)/(1/near − 1/far).
double inverseZLevel(double z, double nearM, double farM, double vmax)
{
    return vmax * (1.0 / z - 1.0 / farM) / (1.0 / nearM - 1.0 / farM);
}

} // namespace

TEST(MetricToLevels8Test, convertsWithTheGivenPlanesAndKeepsTheFirstFramesForTheNext)
{
    // GIVEN a flat 4×3 frame at 1 m (mm units) and planes at 0.5 m and 4 m
    std::optional<DepthRange> range = DepthRange{0.5, 4.0};
    // WHEN it becomes 8-bit levels of the same size
    auto levels = metricToLevels8(Plane<std::uint16_t>(4, 3, 1000), range, 4, 3);
    ASSERT_TRUE(levels);
    // THEN every level is 1 m through those planes, not through the frame's own (flat) range,
    // and the planes are left as given
    const auto atOneMetre =
        static_cast<std::uint16_t>(std::lround(inverseZLevel(1.0, 0.5, 4.0, 255.0)));
    EXPECT_EQ(levels->samples, std::vector<std::uint16_t>(12, atOneMetre));
    ASSERT_TRUE(range.has_value());
    EXPECT_EQ(range->nearM, 0.5);
    EXPECT_EQ(range->farM, 4.0);

    // GIVEN no planes and a first frame half at 1 m, half at 2 m
    range.reset();
    Plane<std::uint16_t> first(4, 2, 1000);
    for (int x = 0; x < 4; ++x)
        first.samples[static_cast<std::size_t>(4 + x)] = 2000;
    ASSERT_TRUE(metricToLevels8(first, range, 4, 2));
    // THEN its robust range (the 1 % and 99 % depths) is returned: 1 m and 2 m
    ASSERT_TRUE(range.has_value());
    EXPECT_DOUBLE_EQ(range->nearM, 1.0);
    EXPECT_DOUBLE_EQ(range->farM, 2.0);
    // WHEN the next frame, flat at 1.5 m, is converted with them
    levels = metricToLevels8(Plane<std::uint16_t>(4, 2, 1500), range, 4, 2);
    ASSERT_TRUE(levels);
    // THEN its levels are 1.5 m between 1 m and 2 m (85), the planes unchanged
    const auto between =
        static_cast<std::uint16_t>(std::lround(inverseZLevel(1.5, 1.0, 2.0, 255.0)));
    EXPECT_EQ(levels->samples, std::vector<std::uint16_t>(8, between));
    EXPECT_DOUBLE_EQ(range->nearM, 1.0);
    EXPECT_DOUBLE_EQ(range->farM, 2.0);
}

namespace {

/// An active-stereo frame (W×H mm): a floor ramp from 800 mm (bottom row) to 3000 mm (top row), 8 %
/// holes, and 2.5 % isolated far speckles, one pixel each with no speckle beside it, spread evenly
/// in disparity from 1.9 to 0.32 px (10..60 m at f·b = 19136 px·mm, a RealSense D4xx at 640×480),
/// as IR-stereo mismatches read.
struct StereoFrame {
    Plane<std::uint16_t> raw;
    std::vector<std::uint16_t> valid; ///< The valid samples, sorted.
    long long speckles = 0;
    std::uint16_t farthestSpeckle = 0;
};

StereoFrame stereoFrameWithFarSpeckles()
{
    constexpr int kW = 200;
    constexpr int kH = 150;
    StereoFrame f;
    f.raw = Plane<std::uint16_t>(kW, kH, 0);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            std::uint16_t v = static_cast<std::uint16_t>(800 + (2200 * (kH - 1 - y)) / (kH - 1));
            if ((x * 7 + y * 13) % 40 == 0) { // neighbours differ by 6, 7, 13 or 20 (mod 40)
                const double d = 0.32 + 1.58 * static_cast<double>(f.speckles % 97) / 96.0;
                v = static_cast<std::uint16_t>(std::lround(19136.0 / d));
                ++f.speckles;
                f.farthestSpeckle = std::max(f.farthestSpeckle, v);
            } else if ((x * 3 + y * 5) % 12 == 0) {
                v = 0;
            }
            f.raw.at(x, y) = v;
        }
    for (const std::uint16_t v : f.raw.samples)
        if (v != 0)
            f.valid.push_back(v);
    std::sort(f.valid.begin(), f.valid.end());
    return f;
}

} // namespace

TEST(MetricToNearnessTest, robustRangeLeavesOutTheSparseFarSpecklesOfAStereoSensor)
{
    // GIVEN a stereo frame whose 2.5 % far speckles put its 99 % quantile at 10..60 m
    const StereoFrame f = stereoFrameWithFarSpeckles();
    const auto n = f.valid.size();
    const double q99 =
        f.valid[static_cast<std::size_t>(std::lround(0.99 * static_cast<double>(n - 1)))];
    ASSERT_GT(q99, 10000.0) << "the speckles must reach into the 99 % quantile";
    // WHEN the planes are estimated
    const auto r = robustRange(f.raw, RawDepthFormat{});
    ASSERT_TRUE(r);
    // THEN near is the 1 % quantile of the valid samples and far is the planted scene's farthest
    // depth, 3 m, not the speckles' 10..60 m
    const double q01 =
        f.valid[static_cast<std::size_t>(std::lround(0.01 * static_cast<double>(n - 1)))];
    EXPECT_NEAR(r->nearM, q01 / 1000.0, 1e-9);
    EXPECT_NEAR(r->farM, 3.000, 1e-9);
}

TEST(MetricToNearnessTest, estimateRangeSaysWhatTheFarTailWas)
{
    const StereoFrame f = stereoFrameWithFarSpeckles();
    const auto e = estimateRange(f.raw, RawDepthFormat{});
    ASSERT_TRUE(e);
    // THEN the tail left out is exactly the speckles, and the median is the ramp's
    EXPECT_TRUE(e->tailCut);
    EXPECT_NEAR(e->beyondFraction,
                static_cast<double>(f.speckles) / static_cast<double>(f.valid.size()), 1e-12);
    EXPECT_NEAR(e->maxM, f.farthestSpeckle / 1000.0, 1e-9);
    EXPECT_GT(e->quantileFarM, 10.0);
    EXPECT_NEAR(e->medianM, f.valid[(f.valid.size() - 1) / 2 + ((f.valid.size() - 1) % 2)] / 1000.0,
                1e-3);
}

TEST(MetricToNearnessTest, aDenseFarBackgroundStaysInTheRange)
{
    // GIVEN 90 % of the samples on a ramp 1..2 m and 10 % on a wall at 20 m (a real background)
    Plane<std::uint16_t> raw(1000, 1, 0);
    for (int i = 0; i < 900; ++i)
        raw.samples[static_cast<std::size_t>(i)] =
            static_cast<std::uint16_t>(1000 + (1000 * i) / 899);
    for (int i = 900; i < 1000; ++i)
        raw.samples[static_cast<std::size_t>(i)] = 20000;
    // WHEN the planes are estimated
    const auto e = estimateRange(raw, RawDepthFormat{});
    ASSERT_TRUE(e);
    // THEN the wall is kept: the far plane is at it, nothing is left out
    EXPECT_FALSE(e->tailCut);
    EXPECT_NEAR(e->range.farM, 20.0, 1e-9);
    EXPECT_EQ(e->beyondFraction, 0.0);
}
