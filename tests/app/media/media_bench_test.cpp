// The media benchmark's measurements that can be checked without timing: PSNR, force comparison,
// the stroke, and a tiny run on a 64×48 synthetic clip through the real encoders and the receiver
// on the ffmpeg backends (bitrates, lossless round trip, CSV rows). No speed is asserted.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/media/media_bench.h"
#include "depthtouch/platform/gnuplot.h"
#include "depthtouch/platform/log.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"

namespace {

using namespace depthtouch;
using namespace depthtouch::media::bench;

std::vector<std::string> readLines(const std::string &path)
{
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);)
        lines.push_back(line);
    return lines;
}

std::vector<std::string> splitCsv(const std::string &line)
{
    std::vector<std::string> out;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');)
        out.push_back(cell);
    if (!line.empty() && line.back() == ',')
        out.emplace_back();
    return out;
}

ReceiverBackends ffmpegBackends()
{
    ReceiverBackends b;
    b.makeSource = [] { return drivers::createMediaSource("ffmpeg", hal::BackendConfig{}); };
    b.makeDecoder = [](const hal::StreamInfo &) {
        hal::BackendConfig c;
        c.options = hal::OptionList("threads=1");
        return drivers::createVideoDecoder("ffmpeg", c);
    };
    b.description = "ffmpeg, threads=1";
    return b;
}

haptics::ForceLogRow forceRow(double t, double fx, double fy, double fz)
{
    haptics::ForceLogRow r;
    r.t = t;
    r.out.force = {fx, fy, fz};
    return r;
}

TEST(MediaBenchTest, psnrOfIdenticalSamplesIsInfinite)
{
    const std::vector<std::uint8_t> a{0, 10, 200, 255};
    EXPECT_TRUE(std::isinf(psnr8(a, a)));
    EXPECT_GT(psnr8(a, a), 0.0);
}

TEST(MediaBenchTest, psnrFollowsTheMeanSquaredError)
{
    // GIVEN every sample off by one level (MSE 1) and, separately, by 16 levels (MSE 256)
    const std::vector<std::uint8_t> a(100, 100);
    const std::vector<std::uint8_t> b(100, 101);
    const std::vector<std::uint8_t> c(100, 84);
    // THEN PSNR = 10·log10(255²/MSE)
    EXPECT_NEAR(psnr8(a, b), 20.0 * std::log10(255.0), 1e-9);
    EXPECT_NEAR(psnr8(a, c), 20.0 * std::log10(255.0 / 16.0), 1e-9);
    EXPECT_TRUE(std::isnan(psnr8(a, std::vector<std::uint8_t>(99, 100))));
}

TEST(MediaBenchTest, forceErrorOfALogWithItselfIsZero)
{
    const std::vector<haptics::ForceLogRow> a{forceRow(0.0, 0, 0, 1), forceRow(0.001, 0.5, 0, 1.5)};
    const ForceError same = compareForces(a, a);
    EXPECT_EQ(same.rmsN, 0.0);
    EXPECT_EQ(same.maxN, 0.0);
}

TEST(MediaBenchTest, forceErrorIsTheRmsOfTheVectorDifference)
{
    const std::vector<haptics::ForceLogRow> a{forceRow(0.0, 0, 0, 1), forceRow(0.001, 0, 0, 1)};
    const std::vector<haptics::ForceLogRow> b{forceRow(0.0, 3, 4, 1), forceRow(0.001, 0, 0, 1)};
    const ForceError e = compareForces(a, b);
    EXPECT_NEAR(e.maxN, 5.0, 1e-12);
    EXPECT_NEAR(e.rmsN, std::sqrt(25.0 / 2.0), 1e-12);
}

TEST(MediaBenchTest, strokeEndsTwoMillimetresBelowTheSurfaceItFollows)
{
    // GIVEN a still synthetic clip's depth
    const Clip clip = makeSyntheticClip(64, 48, 10);
    std::vector<scene::DepthFrameView> frames;
    for (std::size_t i = 0; i < clip.frames(); ++i) {
        scene::DepthFrameView v;
        v.data = clip.nearness(i).data.data();
        v.width = clip.width;
        v.height = clip.height;
        v.strideBytes = clip.nearness(i).stride;
        v.pts = static_cast<double>(i) / clip.fps;
        frames.push_back(v);
    }
    const scene::SceneBox box{};
    const auto stroke = makeStroke(frames, box, 0.0);
    ASSERT_FALSE(stroke.empty());
    // THEN it starts above the surface, spans the clip and moves left to right
    EXPECT_DOUBLE_EQ(stroke.front().t, 0.0);
    EXPECT_NEAR(stroke.back().t, frames.back().pts, 1e-12);
    EXPECT_LT(stroke.front().x, stroke.back().x);
    haptics::HeightField first(box);
    ASSERT_TRUE(first.setFrames(frames.front(), nullptr));
    EXPECT_GT(stroke.front().z, first.heightAt(stroke.front().x, stroke.front().y) + 0.005);
    haptics::HeightField last(box);
    ASSERT_TRUE(last.setFrames(frames.back(), nullptr));
    EXPECT_NEAR(stroke.back().z, last.heightAt(stroke.back().x, stroke.back().y) - 0.002, 1e-9);
    EXPECT_EQ(strokeLanes(64, 48, box).size(), 17u);
}

TEST(MediaBenchTest, tinyRunWritesTheExpectedRows)
{
    platform::setLogLevel(platform::LogLevel::Error);
    depthtouch::testing::TempDir tmp("dt-media-bench-test-");
    ASSERT_FALSE(tmp.dir().empty());
    // GIVEN an 8-frame 64×48 synthetic clip, one preset and one lossy depth setting
    const Clip clip = makeSyntheticClip(64, 48, 8);
    ASSERT_EQ(clip.frames(), 8u);
    MediaBenchOptions o;
    o.presets = {"ultrafast"};
    o.depthCrfs = {30};
    o.ratePreset = "ultrafast";
    o.decodeRuns = 1;
    o.workDir = tmp.dir().string();
    const ReceiverBackends backends = ffmpegBackends();

    // WHEN the throughput and the rate/accuracy sweep run
    auto throughput = measureThroughput(clip, backends, o);
    ASSERT_TRUE(throughput) << throughput.error().what;
    auto rate = measureRateAccuracy(clip, backends, o);
    ASSERT_TRUE(rate) << rate.error().what;

    // THEN every frame was paired and both streams have a bitrate
    ASSERT_EQ(throughput->size(), 1u);
    const ThroughputRow &t = throughput->front();
    EXPECT_EQ(t.frames, 8u);
    EXPECT_GT(t.colorKbps, 0.0);
    EXPECT_GT(t.depthKbps, 0.0);
    EXPECT_EQ(t.decodeRunFps.size(), 1u);
    EXPECT_EQ(t.depthDuplicated, 0u);
    EXPECT_EQ(t.depthMissing, 0u);
    // AND lossless depth comes back bit-exact, with zero force error against itself
    EXPECT_TRUE(rate->losslessExact);
    ASSERT_EQ(rate->rows.size(), 2u);
    const RateRow &lossless = rate->rows[0];
    const RateRow &lossy = rate->rows[1];
    EXPECT_TRUE(lossless.lossless);
    EXPECT_TRUE(std::isinf(lossless.psnrDb));
    EXPECT_EQ(lossless.forceRmsN, 0.0);
    EXPECT_EQ(lossless.pressRmsN, 0.0);
    EXPECT_EQ(lossless.forceRmsNoSafetyN, 0.0);
    EXPECT_GT(lossless.forceRefRmsN, 0.0); // the strokes touched the surface
    // AND CRF 30 costs fewer bits and loses some accuracy
    EXPECT_FALSE(lossy.lossless);
    EXPECT_EQ(lossy.crf, 30);
    EXPECT_LT(lossy.depthKbps, lossless.depthKbps);
    EXPECT_TRUE(std::isfinite(lossy.psnrDb));
    EXPECT_GT(lossy.psnrDb, 20.0);
    EXPECT_GT(lossy.updates, 0u);
    // AND the scratch files are gone
    EXPECT_TRUE(std::filesystem::is_empty(tmp.dir()));

    // WHEN the report is written
    MediaBenchReport report;
    report.throughput = *throughput;
    report.rate = rate->rows;
    report.rateWidth = clip.width;
    report.rateHeight = clip.height;
    const std::string out = tmp.path("out");
    std::string error;
    std::string note;
    ASSERT_TRUE(writeReport(report, out, error, note)) << error;

    // THEN the CSVs hold a header and one row per measurement
    const auto tp = readLines(out + "/media_throughput.csv");
    ASSERT_EQ(tp.size(), 2u);
    EXPECT_EQ(splitCsv(tp[0]).size(), splitCsv(tp[1]).size());
    EXPECT_EQ(tp[1].rfind("64x48,ultrafast,8,", 0), 0u) << tp[1];
    const auto ra = readLines(out + "/rate_accuracy.csv");
    ASSERT_EQ(ra.size(), 3u);
    EXPECT_EQ(ra[0].rfind("depth,crf,depth_kbps,psnr_db,force_rms_n", 0), 0u);
    EXPECT_EQ(ra[1].rfind("lossless,,", 0), 0u) << ra[1];
    EXPECT_EQ(splitCsv(ra[1])[3], "inf");
    EXPECT_EQ(ra[2].rfind("crf30,30,", 0), 0u) << ra[2];
    EXPECT_EQ(splitCsv(ra[0]).size(), splitCsv(ra[2]).size());
    // AND the chart exists whenever gnuplot ran
    if (note.empty()) {
        EXPECT_TRUE(std::filesystem::exists(out + "/rate_vs_accuracy.png"));
    }
}

/// RMS height error (mm in the default scene box) of the clip's 16-bit nearness rounded to
/// \a vmax levels: the least error any decoder of that bit depth can have.
double roundingErrorMm(const Clip &clip, double vmax)
{
    double sq = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < clip.frames(); ++i) {
        const media::Image &fine = clip.fineNearness(i);
        for (int y = 0; y < fine.height; ++y)
            for (int x = 0; x < fine.width; ++x) {
                const double v = fine.sample16(x, y) / 65535.0;
                const double d = std::round(v * vmax) / vmax - v;
                sq += d * d;
                ++n;
            }
    }
    return 1000.0 * scene::SceneBox{}.depth * std::sqrt(sq / static_cast<double>(n));
}

TEST(MediaBenchTest, codecComparisonMeasuresEachCodecAgainstTheSixteenBitSource)
{
    platform::setLogLevel(platform::LogLevel::Error);
    depthtouch::testing::TempDir tmp("dt-media-bench-codecs-");
    ASSERT_FALSE(tmp.dir().empty());
    // GIVEN an 8-frame 64×48 synthetic clip and one CRF
    const Clip clip = makeSyntheticClip(64, 48, 8);
    ASSERT_EQ(clip.fineNearnesses.size(), clip.nearnesses.size());
    MediaBenchOptions o;
    o.decodeRuns = 1;
    o.workDir = tmp.dir().string();
    CodecPlan plan;
    plan.crfs = {18};
    plan.preset = "ultrafast";
    plan.allThreads = 1;
    const ReceiverBackends backends = ffmpegBackends();

    // WHEN the depth codecs are compared
    auto rows = measureCodecs(clip, backends, backends, plan, o);
    ASSERT_TRUE(rows) << rows.error().what;

    // THEN each codec has one row, in encode's order
    ASSERT_EQ(rows->size(), 4u);
    const char *names[] = {"h264-8", "h264-10", "hevc-10", "ffv1-16"};
    for (std::size_t k = 0; k < 4; ++k) {
        EXPECT_EQ((*rows)[k].codec, names[k]);
        EXPECT_GT((*rows)[k].depthKbps, 0.0);
        EXPECT_GT((*rows)[k].decodeFps1, 0.0);
    }
    const CodecRow &h8 = (*rows)[0];
    const CodecRow &h10 = (*rows)[1];
    const CodecRow &hevc = (*rows)[2];
    const CodecRow &ffv1 = (*rows)[3];
    // AND 16-bit FFV1 gives the source back: no height or force error
    EXPECT_TRUE(ffv1.lossless);
    EXPECT_EQ(ffv1.depthErrorMm, 0.0);
    EXPECT_EQ(ffv1.forceRmsN, 0.0);
    EXPECT_EQ(ffv1.forceMaxN, 0.0);
    // AND no lossy codec is finer than its bit depth's rounding of the source, and each costs
    // fewer bits than lossless
    EXPECT_GE(h8.depthErrorMm, 0.99 * roundingErrorMm(clip, 255.0));
    EXPECT_GE(h10.depthErrorMm, 0.99 * roundingErrorMm(clip, 1023.0));
    EXPECT_GE(hevc.depthErrorMm, 0.99 * roundingErrorMm(clip, 1023.0));
    for (const CodecRow *r : {&h8, &h10, &hevc}) {
        EXPECT_EQ(r->crf, 18);
        EXPECT_LT(r->depthKbps, ffv1.depthKbps) << r->codec;
        // A sample read at the wrong scale (10 bits as 8, or 16) is off by millimetres.
        EXPECT_LT(r->depthErrorMm, 1.0) << r->codec;
    }
    EXPECT_TRUE(std::filesystem::is_empty(tmp.dir()));

    // WHEN they are written
    const std::string out = tmp.path("out");
    std::filesystem::create_directories(out);
    std::string error;
    std::string note;
    ASSERT_TRUE(writeCodecs(*rows, 1, out, error, note)) << error;
    // THEN the CSV holds a header and the four rows
    const auto lines = readLines(out + "/depth_codecs.csv");
    ASSERT_EQ(lines.size(), 5u);
    EXPECT_EQ(lines[0].rfind("size,codec,setting,crf,depth_kbps,decode_fps_1_thread", 0), 0u);
    EXPECT_EQ(lines[1].rfind("64x48,h264-8,crf18,18,", 0), 0u) << lines[1];
    EXPECT_EQ(lines[4].rfind("64x48,ffv1-16,lossless,,", 0), 0u) << lines[4];
    EXPECT_EQ(splitCsv(lines[0]).size(), splitCsv(lines[3]).size());
    EXPECT_EQ(splitCsv(lines[4]).back(), "0.00000"); // FFV1's height error
    if (note.empty()) {
        EXPECT_TRUE(std::filesystem::exists(out + "/depth_codecs.png"));
    }
}

TEST(MediaBenchTest, kitchenClipNeedsItsFolder)
{
    auto clip = loadKitchenClip("/nonexistent-dt-folder", 4, 64, 48);
    ASSERT_FALSE(clip);
    EXPECT_EQ(clip.error().code, Errc::Io);
    EXPECT_FALSE(loadKitchenClip("/nonexistent-dt-folder", 4, 63, 48));
}

TEST(MediaBenchTest, kitchenClipIsStretchedToTheClipSize)
{
    DT_NEED_SHARED_DATA("rgbd-7scenes-redkitchen/frame-000000.depth.png");
    const std::string scene = depthtouch::testing::sharedDataPath("rgbd-7scenes-redkitchen");
    // GIVEN the first 5 frames read as a 72×50 clip
    auto clip = loadKitchenClip(scene, 5, 72, 50);
    ASSERT_TRUE(clip) << clip.error().what;
    // THEN they are stored once each, in order, at the clip size
    EXPECT_EQ(clip->frames(), 5u);
    ASSERT_EQ(clip->colors.size(), 5u);
    EXPECT_EQ(clip->order, (std::vector<std::size_t>{0, 1, 2, 3, 4}));
    EXPECT_EQ(clip->color(0).width, 72);
    EXPECT_EQ(clip->nearness(4).height, 50);
}

TEST(MediaBenchTest, gnuplotReportsAScriptThatFails)
{
    depthtouch::testing::TempDir tmp("dt-gnuplot-test-");
    const std::string script = tmp.path("bad.gp");
    std::ofstream(script) << "this is not gnuplot\n";
    const platform::PlotStatus s = platform::runGnuplot(script);
    EXPECT_NE(s, platform::PlotStatus::Drawn);
    EXPECT_NE(std::string(platform::plotStatusNote(s)), "");
}

} // namespace
