/// \file
/// \brief The sender on real RGB-D data: the first 30 frames (10 enhanced) of 7-Scenes "redkitchen"
/// (JPEG color, 16-bit mm depth PNG with holes) encoded to MKV with and without the §V.B
/// enhancement, then read back with libavformat as ffprobe would; its holes stay holes through
/// 8-bit lossy coding (docs/architecture.md §3 "Holes"). Skips (exit code 77) when the shared data
/// lacks the frames, or fails when DT_REQUIRE_SHARED_DATA=1.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "depthtouch/depth/occupancy.h"
#include "depthtouch/media/encode_job.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/image_io.h"
#include "readback.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"

using namespace depthtouch;
using namespace depthtouch::media;
namespace fs = std::filesystem;

namespace {

constexpr int kFrames = 30;
/// The enhancement costs ~0.1 s per 640×480 frame: fewer frames keep the program short.
constexpr int kEnhancedFrames = 10;

struct EncodeRun {
    EncodeSummary summary;
    test::FileReadback readback;
};

EncodeRun encode(const std::string &dir, const std::string &out, bool enhance, int frames,
                 bool keepFrames = false)
{
    EncodeRun run;
    auto color = openFrameSource(dir + "/frame-%06d.color.jpg", SourceOptions{});
    auto depthSrc = openFrameSource(dir + "/frame-%06d.depth.png", SourceOptions{});
    EXPECT_TRUE(color && depthSrc);
    if (!color || !depthSrc)
        return run;
    EXPECT_EQ((*depthSrc)->info().nativeFormat, PixelFormat::Gray16);
    EncodeOptions o;
    o.output = out;
    o.preset = "ultrafast";
    o.maxFrames = frames;
    o.enhance = enhance;
    auto s = encodeStreams(**color, **depthSrc, o);
    EXPECT_TRUE(s) << (s ? "" : s.error().what);
    if (!s)
        return run;
    run.summary = *s;
    run.readback = test::readBack(out, {0}, keepFrames);
    return run;
}

void expectProbeFacts(const EncodeRun &run, int frames)
{
    const test::FileReadback &rb = run.readback;
    ASSERT_TRUE(rb.ok) << rb.error;
    EXPECT_NE(rb.format.find("matroska"), std::string::npos);
    ASSERT_EQ(rb.streams.size(), 2u) << "two video streams";
    EXPECT_EQ(rb.decodeErrors, 0);
    EXPECT_EQ(rb.streams[0].tags.at("title"), "color");
    EXPECT_EQ(rb.streams[1].tags.at("title"), "depth");
    for (const auto &st : rb.streams) {
        EXPECT_EQ(st.codec, "h264");
        EXPECT_EQ(st.width, 640);
        EXPECT_EQ(st.height, 480);
        EXPECT_EQ(st.pts.size(), static_cast<std::size_t>(frames));
    }
    EXPECT_EQ(rb.streams[0].pts, rb.streams[1].pts) << "paired frames share their PTS";
    // Kinect depth in a kitchen: planes well inside the sensor's 0.5..8 m.
    const auto &tags = rb.streams[1].tags;
    const double nearM = std::stod(tags.at("depth_near"));
    const double farM = std::stod(tags.at("depth_far"));
    EXPECT_GT(nearM, 0.3);
    EXPECT_LT(farM, 8.0);
    EXPECT_LT(nearM, farM);
    EXPECT_EQ(tags.at("depth_mapping"), "inverse_z");
    EXPECT_EQ(tags.at("depth_bits"), "8");
    EXPECT_EQ(rb.tags.at("depth_near"), tags.at("depth_near"));
    EXPECT_TRUE(run.summary.metric);
    EXPECT_GT(run.summary.holeSamples, 0) << "7-Scenes depth has holes";
    EXPECT_EQ(run.summary.filledSamples, 0);
    EXPECT_EQ(tags.at("depth_occupancy"), std::to_string(depth::occupancyFor(8, false).threshold));
}

/// The decoded samples of \a run on the wrong side of the hole threshold: holes (0 or 65535 in
/// the clip's PNGs) read as measured, and measured samples read as holes.
std::pair<long, long> misread(const EncodeRun &run, const std::string &dir, int frames)
{
    const auto threshold = static_cast<int>(depth::occupancyFor(8, false).threshold);
    long holesAsMeasured = 0;
    long measuredAsHoles = 0;
    for (int i = 0; i < frames; ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "/frame-%06d.depth.png", i);
        auto raw = readImage(dir + name, PixelFormat::Gray16);
        EXPECT_TRUE(raw);
        if (!raw)
            break;
        const Image &d = run.readback.streams[1].frames[static_cast<std::size_t>(i)];
        for (int y = 0; y < d.height; ++y)
            for (int x = 0; x < d.width; ++x) {
                const std::uint16_t v = raw->sample16(x, y);
                const bool hole = v == 0 || v == 65535;
                const bool readHole = d.row(y)[x] < threshold;
                holesAsMeasured += hole && !readHole ? 1 : 0;
                measuredAsHoles += !hole && readHole ? 1 : 0;
            }
    }
    return {holesAsMeasured, measuredAsHoles};
}

TEST(EncodeRealDataTest, sevenScenesWithAndWithoutEnhancement)
{
    DT_NEED_SHARED_DATA("rgbd-7scenes-redkitchen/frame-000000.depth.png");
    const std::string dir = depthtouch::testing::sharedDataPath("rgbd-7scenes-redkitchen");
    const depthtouch::testing::TempDir scratch("dt-encode-realdata-");
    const fs::path &tmp = scratch.dir();

    const EncodeRun plain = encode(dir, (tmp / "plain.mkv").string(), false, kFrames, true);
    expectProbeFacts(plain, kFrames);
    EXPECT_FALSE(plain.summary.enhance.has_value());
    ASSERT_EQ(plain.readback.streams.size(), 2u);
    ASSERT_EQ(plain.readback.streams[1].frames.size(), static_cast<std::size_t>(kFrames));
    const auto [holesAsMeasured, measuredAsHoles] = misread(plain, dir, kFrames);
    const double samples = 640.0 * 480.0 * kFrames;
    std::printf("7-Scenes 8-bit lossy: holes %.2f %% of the samples; %ld holes read as measured, "
                "%ld measured read as holes (%.3f %% of the samples)\n",
                100.0 * static_cast<double>(plain.summary.holeSamples) / samples, holesAsMeasured,
                measuredAsHoles,
                100.0 * static_cast<double>(holesAsMeasured + measuredAsHoles) / samples);
    EXPECT_LT(static_cast<double>(holesAsMeasured + measuredAsHoles), 0.001 * samples)
        << "the guard band keeps all but a few samples on their side of the threshold";

    const EncodeRun enhanced = encode(dir, (tmp / "enhanced.mkv").string(), true, kEnhancedFrames);
    expectProbeFacts(enhanced, kEnhancedFrames);
    ASSERT_TRUE(enhanced.summary.enhance.has_value());
    const EnhanceTotals &t = *enhanced.summary.enhance;
    EXPECT_EQ(t.frames, kEnhancedFrames);
    EXPECT_EQ(t.pixels, 640LL * 480 * kEnhancedFrames);
    EXPECT_GT(t.points, 0);
    EXPECT_LT(t.points, t.pixels / 4) << "the mesh keeps far fewer points than pixels";
    EXPECT_LT(t.roughnessOutput, t.roughnessInput) << "sensor noise on flat regions is removed";
    EXPECT_GT(t.edgeContrastOutput, 0.8 * t.edgeContrastInput) << "edges are kept";
    std::printf(
        "7-Scenes: %d frames plain %.2f s, %d frames enhanced %.2f s; points %.2f %% of pixels, "
        "mean |error| %.3f levels, roughness %.3f -> %.3f, edge contrast %.1f -> %.1f\n",
        kFrames, plain.summary.elapsed, kEnhancedFrames, enhanced.summary.elapsed,
        100.0 * static_cast<double>(t.points) / static_cast<double>(t.pixels), t.meanAbsError,
        t.roughnessInput, t.roughnessOutput, t.edgeContrastInput, t.edgeContrastOutput);
    std::error_code ec;
    fs::remove_all(tmp, ec);
}

} // namespace
