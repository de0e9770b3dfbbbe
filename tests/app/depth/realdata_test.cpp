/// \file
/// \brief Depth conversion, hole filling and enhancement on real RGB-D frames (Microsoft 7-Scenes
/// "redkitchen", TUM). Skipped when ../shared/data is absent (set DT_SHARED_DATA); failed instead
/// when DT_REQUIRE_SHARED_DATA=1.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "depthtouch/depth/conversion.h"
#include "depthtouch/depth/enhance.h"
#include "depthtouch/depth/fill.h"
#include "depthtouch/depth/resample.h"
#include "depthtouch/media/image_io.h"
#include "support/shared_data.h"

using namespace depthtouch;
using namespace depthtouch::depth;

namespace {

std::string kitchenFrame(int n, const char *kind)
{
    char name[64];
    std::snprintf(name, sizeof name, "rgbd-7scenes-redkitchen/frame-%06d.%s", n, kind);
    return depthtouch::testing::sharedDataPath(name);
}

#define DT_REQUIRE_KITCHEN() DT_NEED_SHARED_DATA("rgbd-7scenes-redkitchen/frame-000000.depth.png")

Plane<std::uint16_t> readDepth(const std::string &path)
{
    auto img = media::readImage(path, media::PixelFormat::Gray16);
    EXPECT_TRUE(img) << path;
    return img ? media::toPlane16(*img) : Plane<std::uint16_t>{};
}

} // namespace

TEST(DepthRealDataTest, conversionAndFillLeaveNoInvalidSample)
{
    DT_REQUIRE_KITCHEN();
    for (const int n : {0, 30, 59}) {
        const Plane<std::uint16_t> raw = readDepth(kitchenFrame(n, "depth.png"));
        ASSERT_EQ(raw.width, 640);
        // GIVEN planes wider than the Kinect's range, so every valid sample maps above 0
        ConvertOptions o;
        o.range = DepthRange{0.3, 12.0};
        auto f = metricToNearness(raw, o);
        ASSERT_TRUE(f);
        EXPECT_GT(f->invalidCount, 1000u) << "real Kinect frames have holes";
        float minValid = 1e9f;
        for (std::size_t i = 0; i < f->nearness.size(); ++i)
            if (f->valid.samples[i] != 0)
                minValid = std::min(minValid, f->nearness.samples[i]);
        ASSERT_GT(minValid, 0.0f);
        // WHEN filled
        const auto filled = fillInvalid(f->nearness, f->valid);
        ASSERT_TRUE(filled);
        // THEN every hole was filled with a depth of the valid data's range, never the far plane
        EXPECT_EQ(*filled, f->invalidCount);
        for (std::size_t i = 0; i < f->nearness.size(); ++i)
            ASSERT_GE(f->nearness.samples[i], minValid) << "frame " << n << " sample " << i;

        // AND with planes from the data (1 %/99 % quantiles) the holes are filled as well
        auto robust = metricToNearness(raw, ConvertOptions{});
        ASSERT_TRUE(robust);
        EXPECT_GT(robust->range.nearM, 0.3);
        EXPECT_LT(robust->range.farM, 8.0);
        EXPECT_EQ(fillInvalid(robust->nearness, robust->valid).value(), robust->invalidCount);
    }
}

TEST(DepthRealDataTest, depthResamplesToAnotherGrid)
{
    DT_REQUIRE_KITCHEN();
    const auto color = media::readImage(kitchenFrame(0, "color.jpg"), media::PixelFormat::Rgb24);
    ASSERT_TRUE(color);
    auto f = metricToNearness(readDepth(kitchenFrame(0, "depth.png")), ConvertOptions{});
    ASSERT_TRUE(f);
    ASSERT_TRUE(fillInvalid(f->nearness, f->valid));
    // Same grid as the colour here; `--size 320x240` halves it.
    EXPECT_EQ(f->nearness.width, color->width);
    const auto half = resample(f->nearness, 320, 240);
    ASSERT_TRUE(half);
    const auto [lo, hi] =
        std::minmax_element(f->nearness.samples.begin(), f->nearness.samples.end());
    for (const float v : half->samples) {
        ASSERT_GE(v, *lo);
        ASSERT_LE(v, *hi);
    }
}

TEST(DepthRealDataTest, enhancementRemovesSensorNoiseAndKeepsEdges)
{
    DT_REQUIRE_KITCHEN();
    for (const int n : {0, 45}) {
        auto f = metricToNearness(readDepth(kitchenFrame(n, "depth.png")), ConvertOptions{});
        ASSERT_TRUE(f);
        ASSERT_TRUE(fillInvalid(f->nearness, f->valid));
        // WHEN enhanced with the defaults (8-bit nearness, tolerance 1 level)
        const auto r = enhance(f->nearness, EnhanceOptions{});
        if (!r && r.error().code == Errc::NotSupported)
            GTEST_SKIP() << "built without CGAL";
        ASSERT_TRUE(r);
        const EnhanceReport &rep = r->report;
        std::printf(
            "frame %d: points %zu of %zu (%.2f %%), |error| mean %.3f p99 %.2f max %.2f levels, "
            "flat roughness %.3f -> %.3f (median %.3f) on %zu px, edge contrast %.2f -> %.2f on "
            "%zu px\n",
            n, rep.points, rep.pixels, 100.0 * rep.pointsFraction(), rep.meanAbsError,
            rep.p99AbsError, rep.maxAbsError, rep.input.roughness, rep.enhanced.roughness,
            rep.median.roughness, rep.flatPixels, rep.input.edgeContrast, rep.enhanced.edgeContrast,
            rep.edgePixels);
        RecordProperty("points_frame_" + std::to_string(n), static_cast<int>(rep.points));
        // THEN flat-region roughness falls below a third of the input's, ...
        ASSERT_GT(rep.flatPixels, 50000u);
        EXPECT_LT(rep.enhanced.roughness, rep.input.roughness / 3.0);
        EXPECT_LT(rep.enhanced.roughness, rep.median.roughness / 3.0);
        // ... edges keep at least 85 % of their contrast, ...
        ASSERT_GT(rep.edgePixels, 1000u);
        EXPECT_GT(rep.enhanced.edgeContrast, 0.85 * rep.input.edgeContrast);
        // ... with a small fraction of the pixels as points and a bounded error.
        EXPECT_LT(rep.pointsFraction(), 0.15);
        EXPECT_LT(rep.meanAbsError, 1.5);
        EXPECT_LT(rep.p99AbsError, 8.0);
    }
}

TEST(DepthRealDataTest, tumDepthScaleGivesPlausibleMetres)
{
    DT_NEED_SHARED_DATA("rgbd-open3d/other_formats/TUM_depth.png");
    const std::string tum =
        depthtouch::testing::sharedDataPath("rgbd-open3d/other_formats/TUM_depth.png");
    // TUM stores metres · 5000.
    ConvertOptions o;
    o.raw.metresPerUnit = 1.0 / 5000.0;
    auto f = metricToNearness(readDepth(tum), o);
    ASSERT_TRUE(f);
    EXPECT_GT(f->range.nearM, 0.3);
    EXPECT_LT(f->range.farM, 10.0);
    EXPECT_LT(f->range.nearM, f->range.farM);
}

TEST(DepthRealDataTest, activeStereoFarOutliersStayOutOfTheRobustRange)
{
    // GIVEN the first 5 frames of the RealSense D4xx lab clip taken together, as encode takes its
    // range (--range-frames 5): 1.8..3.1 % of their valid samples read 10..61 m (IR-stereo
    // mismatches on a lab at most ~6 m deep), which put the 99 % quantile at 18.556 m
    DT_NEED_SHARED_DATA("rgbd-realsense-lab/depth/00004.png");
    Plane<std::uint16_t> all;
    for (int n = 0; n < 5; ++n) {
        char name[64];
        std::snprintf(name, sizeof name, "rgbd-realsense-lab/depth/%05d.png", n);
        const Plane<std::uint16_t> raw = readDepth(depthtouch::testing::sharedDataPath(name));
        ASSERT_EQ(raw.width, 640);
        all.samples.insert(all.samples.end(), raw.samples.begin(), raw.samples.end());
    }
    all.width = static_cast<int>(all.samples.size());
    all.height = 1;
    // WHEN the robust range is estimated
    const auto e = estimateRange(all, RawDepthFormat{});
    ASSERT_TRUE(e);
    // THEN it matches a reference written apart (plain Python over the PNGs: sorted valid samples,
    // the 1 % / 99 % quantiles, then the farthest z <= the 99 % quantile with >= 0.5 % of the
    // samples in (z/1.1, z]): near 0.499 m, median 0.886 m, 99 % quantile 18.556 m, far 6.379 m,
    // 3.06 % of the samples beyond it, the farthest 61.236 m
    EXPECT_NEAR(e->range.nearM, 0.499, 1e-9);
    EXPECT_NEAR(e->medianM, 0.886, 1e-9);
    EXPECT_NEAR(e->quantileFarM, 18.556, 1e-9);
    EXPECT_NEAR(e->range.farM, 6.379, 1e-9);
    EXPECT_NEAR(e->beyondFraction, 0.030569, 1e-6);
    EXPECT_NEAR(e->maxM, 61.236, 1e-9);
    EXPECT_TRUE(e->tailCut);
    // AND the planes robustRange() gives (metricToNearness, touch, the receiver) are these
    const auto r = robustRange(all, RawDepthFormat{});
    ASSERT_TRUE(r);
    EXPECT_NEAR(r->farM, 6.379, 1e-9) << "was 18.556 m, the 99 % quantile, before the tail cut";
}
