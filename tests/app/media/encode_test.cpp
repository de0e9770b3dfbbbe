/// \file
/// \brief The sender (app/media): frame sources, encoders, muxer and the encode pipeline, checked
/// by reading the output back with libavformat/libavcodec (readback.h): lossless depth bit-exact
/// (H.264 gray qp 0, H.264 gray10 qp 0, FFV1 gray16), color PSNR, stream titles and depth tags,
/// identical PTS per pair, metric conversion (its holes: encode_holes_test.cpp), resampling, stop,
/// containers, a UDP URL, and the bad inputs.

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "depthtouch/depth/conversion.h"
#include "depthtouch/media/encode_job.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/image_io.h"
#include "encode_sources.h"
#include "readback.h"
#include "support/temp_dir.h"

using namespace depthtouch;
using namespace depthtouch::media;
namespace fs = std::filesystem;

namespace {

using test::colorSource;
using test::EncodeTest;
using test::kH;
using test::kW;
using test::makeColor;
using test::makeMetric;
using test::makeNearness8;
using test::metricSource;
using test::nearness8Source;
using test::TestSource;

/// GIVEN color + 8-bit nearness WHEN encoded with lossless depth (H.264 gray, qp 0) into MKV
/// THEN depth decodes bit-exact, color is close, titles/tags are there and each pair shares a PTS.
TEST_F(EncodeTest, lossless8BitDepthRoundTripsBitExact)
{
    constexpr int kFrames = 8;
    TestSource color = colorSource(kFrames);
    TestSource depthSrc = nearness8Source(kFrames);
    EncodeOptions o = fastOptions(path("out.mkv"));
    o.depthLossless = true;
    auto s = encodeStreams(color, depthSrc, o);
    ASSERT_TRUE(s) << s.error().what;
    EXPECT_EQ(s->frames, kFrames);
    EXPECT_FALSE(s->metric);
    EXPECT_EQ(s->endedBy, "color");
    EXPECT_EQ(files(), std::vector<std::string>{"out.mkv"}) << "no temporary file left";

    const auto rb = test::readBack(path("out.mkv"));
    ASSERT_TRUE(rb.ok) << rb.error;
    ASSERT_EQ(rb.streams.size(), 2u);
    EXPECT_EQ(rb.decodeErrors, 0);
    const auto &c = rb.streams[0];
    const auto &d = rb.streams[1];
    test::expectStream(c, {.codec = "h264", .tags = {{"title", "color"}}});
    test::expectStream(d, {.codec = "h264",
                           .profile = "High 4:4:4 Predictive",
                           .tags = {{"title", "depth"},
                                    {"depth_bits", "8"},
                                    {"depth_mapping", "inverse_z"},
                                    {"depth_near", "unknown"}}});
    EXPECT_EQ(rb.tags.at("depth_bits"), "8");
    ASSERT_EQ(c.frames.size(), static_cast<std::size_t>(kFrames));
    ASSERT_EQ(d.frames.size(), static_cast<std::size_t>(kFrames));
    for (int i = 0; i < kFrames; ++i) {
        const Image want = makeNearness8(i);
        const Image &got = d.frames[static_cast<std::size_t>(i)];
        ASSERT_EQ(got.format, PixelFormat::Gray8);
        EXPECT_EQ(got.data, want.data) << "depth frame " << i << " is not bit-exact";
        EXPECT_GT(test::psnr(c.frames[static_cast<std::size_t>(i)], makeColor(i)), 30.0)
            << "color frame " << i;
        EXPECT_DOUBLE_EQ(c.pts[static_cast<std::size_t>(i)], d.pts[static_cast<std::size_t>(i)]);
        EXPECT_NEAR(c.pts[static_cast<std::size_t>(i)], i / 30.0, 0.0015);
    }
}

/// GIVEN a DepthTouch file WHEN read back as sources by stream title THEN the depth source gives
/// the lossless levels as they are (luma plane, no range conversion) and the color source color.
TEST_F(EncodeTest, encodedFileReadsBackAsSourcesByTitle)
{
    TestSource color = colorSource(3);
    TestSource depthSrc = nearness8Source(3);
    EncodeOptions o = fastOptions(path("out.mkv"));
    o.depthLossless = true;
    ASSERT_TRUE(encodeStreams(color, depthSrc, o));
    SourceOptions so;
    so.streamTitle = "depth";
    auto d = openFrameSource(path("out.mkv"), so);
    ASSERT_TRUE(d) << d.error().what;
    ASSERT_NE(d.value()->info().tag("depth_bits"), nullptr);
    EXPECT_EQ(*d.value()->info().tag("depth_bits"), "8");
    EXPECT_EQ(*d.value()->info().tag("title"), "depth");
    EXPECT_EQ(d.value()->info().nativeFormat, PixelFormat::Rgb24) << "gray H.264 decodes as YUV";
    so.streamTitle = "color";
    auto c = openFrameSource(path("out.mkv"), so);
    ASSERT_TRUE(c) << c.error().what;
    for (int i = 0; i < 3; ++i) {
        auto f = d.value()->next(PixelFormat::Gray8);
        ASSERT_TRUE(f) << f.error().what;
        EXPECT_EQ(f->image.data, makeNearness8(i).data) << "frame " << i;
        auto g = c.value()->next(PixelFormat::Rgb24);
        ASSERT_TRUE(g);
        EXPECT_GT(test::psnr(g->image, makeColor(i)), 30.0);
        EXPECT_DOUBLE_EQ(f->pts, g->pts);
    }
}

/// GIVEN a DepthTouch file made from metric depth WHEN transcoded (its own streams as sources)
/// THEN its planes and mapping travel into the new file's tags.
TEST_F(EncodeTest, transcodeKeepsDepthTags)
{
    TestSource color = colorSource(3);
    TestSource depthSrc = metricSource(3);
    EncodeOptions o = fastOptions(path("first.mkv"));
    o.range = depth::DepthRange{0.75, 3.5};
    o.mapping = depth::DepthMapping::Linear;
    ASSERT_TRUE(encodeStreams(color, depthSrc, o));

    SourceOptions so;
    so.streamTitle = "color";
    auto c = openFrameSource(path("first.mkv"), so);
    so.streamTitle = "depth";
    auto d = openFrameSource(path("first.mkv"), so);
    ASSERT_TRUE(c && d);
    auto s = encodeStreams(**c, **d, fastOptions(path("second.mkv")));
    ASSERT_TRUE(s) << s.error().what;
    EXPECT_EQ(s->frames, 3);
    // the summary (encode's "depth: ... linear mapping" line) gives the mapping written, the
    // source's, not the options' default (inverse_z)
    EXPECT_EQ(s->mapping, depth::DepthMapping::Linear);
    const auto rb = test::readBack(path("second.mkv"), {0}, false);
    ASSERT_EQ(rb.streams.size(), 2u);
    test::expectStream(
        rb.streams[1],
        {.tags = {{"depth_near", "0.75"}, {"depth_far", "3.5"}, {"depth_mapping", "linear"}}});
}

/// GIVEN 16-bit metric depth and given planes WHEN encoded as FFV1 gray16 THEN the decoded samples
/// equal the dt_depth nearness conversion, coded above the lossless hole threshold
/// (depth/occupancy.h), bit for bit, and the tags carry the planes and the threshold.
TEST_F(EncodeTest, ffv1Gray16RoundTripsBitExact)
{
    constexpr int kFrames = 4;
    TestSource color = colorSource(kFrames, 25.0);
    TestSource depthSrc = metricSource(kFrames, 25.0);
    EncodeOptions o = fastOptions(path("out.mkv"));
    o.depthCodec = VideoCodec::Ffv1Gray16;
    o.range = depth::DepthRange{0.5, 4.0};
    o.mapping = depth::DepthMapping::Linear;
    auto s = encodeStreams(color, depthSrc, o);
    ASSERT_TRUE(s) << s.error().what;
    EXPECT_TRUE(s->metric);
    EXPECT_EQ(s->depthBits, 16);
    EXPECT_EQ(s->mapping, depth::DepthMapping::Linear);

    const auto rb = test::readBack(path("out.mkv"));
    ASSERT_TRUE(rb.ok) << rb.error;
    ASSERT_EQ(rb.streams.size(), 2u);
    const auto &d = rb.streams[1];
    test::expectStream(d, {.codec = "ffv1",
                           .pixFmt = "gray16le",
                           .tags = {{"depth_near", "0.5"},
                                    {"depth_far", "4"},
                                    {"depth_mapping", "linear"},
                                    {"depth_bits", "16"},
                                    {"depth_occupancy", "1"}}});
    ASSERT_EQ(d.frames.size(), static_cast<std::size_t>(kFrames));
    depth::ConvertOptions co;
    co.mapping = depth::DepthMapping::Linear;
    co.vmax = 65535.0;
    co.range = depth::DepthRange{0.5, 4.0};
    for (int i = 0; i < kFrames; ++i) {
        auto n = depth::metricToNearness(toPlane16(makeMetric(i)), co);
        ASSERT_TRUE(n);
        std::size_t holes = 0;
        const Image want = fromPlane(depth::quantizeOccupied(n->nearness, n->valid, 65535.0,
                                                             depth::occupancyFor(16, true), holes));
        EXPECT_EQ(holes, 0u);
        EXPECT_EQ(d.frames[static_cast<std::size_t>(i)].data, want.data) << "frame " << i;
        EXPECT_DOUBLE_EQ(rb.streams[0].pts[static_cast<std::size_t>(i)],
                         d.pts[static_cast<std::size_t>(i)]);
    }
}

/// Expects the depth stream (1) of \a rb to hold \a frames frames whose samples are
/// makeNearness8()'s levels scaled to 0..1023 exactly, each with its color frame's PTS.
void expectTenBitLevelsOf8BitNearness(const test::FileReadback &rb, int frames)
{
    const auto &d = rb.streams[1];
    ASSERT_EQ(d.frames.size(), static_cast<std::size_t>(frames));
    for (int i = 0; i < frames; ++i) {
        const Image src = makeNearness8(i);
        const Image &got = d.frames[static_cast<std::size_t>(i)];
        ASSERT_EQ(got.format, PixelFormat::Gray16);
        int mismatches = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const auto want =
                    static_cast<std::uint16_t>(std::lround(src.row(y)[x] * 1023.0 / 255.0));
                mismatches += got.sample16(x, y) != want;
            }
        EXPECT_EQ(mismatches, 0) << "frame " << i;
        EXPECT_DOUBLE_EQ(rb.streams[0].pts[static_cast<std::size_t>(i)],
                         d.pts[static_cast<std::size_t>(i)]);
    }
}

/// Encodes \a frames frames of colour and 8-bit nearness (30 fps) with \a o, the depth lossless in
/// \a codec. \return the summary, or the error, of encodeStreams().
Result<EncodeSummary> encodeLosslessNearness8(EncodeOptions o, VideoCodec codec, int frames)
{
    TestSource color = colorSource(frames);
    TestSource depthSrc = nearness8Source(frames);
    o.depthCodec = codec;
    o.depthLossless = true;
    return encodeStreams(color, depthSrc, o);
}

/// GIVEN 8-bit nearness WHEN encoded as lossless H.264 gray10 into MP4 THEN samples are the 8-bit
/// levels scaled to 0..1023, and MP4 carries the titles (handler names) and the container tags.
TEST_F(EncodeTest, gray10LosslessInMp4)
{
    constexpr int kFrames = 3;
    auto s = encodeLosslessNearness8(fastOptions(path("out.mp4")), VideoCodec::H264Gray10, kFrames);
    ASSERT_TRUE(s) << s.error().what;
    const auto rb = test::readBack(path("out.mp4"));
    ASSERT_TRUE(rb.ok) << rb.error;
    EXPECT_NE(rb.format.find("mp4"), std::string::npos);
    ASSERT_EQ(rb.streams.size(), 2u);
    EXPECT_EQ(rb.streams[0].tags.at("handler_name"), "color");
    EXPECT_EQ(rb.streams[1].tags.at("handler_name"), "depth");
    EXPECT_EQ(rb.tags.at("depth_bits"), "10");
    EXPECT_EQ(rb.tags.at("depth_mapping"), "inverse_z");
    expectTenBitLevelsOf8BitNearness(rb, kFrames);
}

/// GIVEN 8-bit nearness WHEN encoded as lossless HEVC Main10 into MPEG-TS THEN ffprobe sees HEVC
/// Main 10 4:2:0 (what set-top hardware decoders take), the luma holds the 8-bit levels scaled to
/// 0..1023 exactly, the PTS match color's, and the depth tags say 10 bits.
TEST_F(EncodeTest, hevcMain10LosslessInMpegTs)
{
    constexpr int kFrames = 3;
    auto s = encodeLosslessNearness8(fastOptions(path("out.ts")), VideoCodec::HevcMain10, kFrames);
    ASSERT_TRUE(s) << s.error().what;
    EXPECT_EQ(s->depthBits, 10);
    const auto rb = test::readBack(path("out.ts"));
    ASSERT_TRUE(rb.ok) << rb.error;
    ASSERT_GE(rb.streams.size(), 2u);
    test::expectStream(rb.streams[1], {.codec = "hevc", .pixFmt = "yuv420p10le"});
    expectTenBitLevelsOf8BitNearness(rb, kFrames);
}

/// GIVEN metric depth without planes WHEN encoded THEN near/far come from the first frames' robust
/// range, once: the tags hold exactly the planes reported, the same for the whole file.
TEST_F(EncodeTest, robustRangeDecidedOnceFromFirstFrames)
{
    TestSource color = colorSource(8);
    // Later frames move far away; the planes must not follow them.
    TestSource depthSrc(
        [](int i) {
            Image img = makeMetric(0);
            if (i >= 5)
                for (int y = 0; y < kH; ++y)
                    for (int x = 0; x < kW; ++x)
                        img.setSample16(x, y, static_cast<std::uint16_t>(img.sample16(x, y) * 3));
            return img;
        },
        8, 30.0, PixelFormat::Gray16);
    EncodeOptions o = fastOptions(path("out.mkv"));
    auto s = encodeStreams(color, depthSrc, o);
    ASSERT_TRUE(s) << s.error().what;
    ASSERT_TRUE(s->metric);
    auto expected = depth::robustRange(toPlane16(makeMetric(0)), depth::RawDepthFormat{});
    ASSERT_TRUE(expected);
    EXPECT_NEAR(s->range.nearM, expected->nearM, 1e-9);
    EXPECT_NEAR(s->range.farM, expected->farM, 1e-9);
    const auto rb = test::readBack(path("out.mkv"), {0}, false);
    ASSERT_EQ(rb.streams.size(), 2u);
    const auto tags = depthTags(s->range, depth::DepthMapping::InverseZ, 8);
    for (const auto &[k, v] : tags) {
        EXPECT_EQ(rb.streams[1].tags.at(k), v) << k;
        EXPECT_EQ(rb.tags.at(k), v) << k;
    }
}

/// GIVEN depth at half the color size WHEN encoded THEN it is resampled to the color grid, with one
/// warning.
TEST_F(EncodeTest, depthOfAnotherSizeIsResampledWithWarning)
{
    TestSource color = colorSource(3);
    TestSource depthSrc([](int i) { return makeNearness8(i, kW / 2, kH / 2); }, 3, 30.0,
                        PixelFormat::Gray8);
    std::vector<std::string> warnings;
    EncodeCallbacks cb;
    cb.warning = [&warnings](const std::string &w) { warnings.push_back(w); };
    auto s = encodeStreams(color, depthSrc, fastOptions(path("out.mkv")), nullptr, cb);
    ASSERT_TRUE(s) << s.error().what;
    EXPECT_TRUE(s->depthResampled);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("resampled"), std::string::npos);
    const auto rb = test::readBack(path("out.mkv"), {0}, false);
    ASSERT_EQ(rb.streams.size(), 2u);
    EXPECT_EQ(rb.streams[1].width, kW);
    EXPECT_EQ(rb.streams[1].height, kH);
}

/// GIVEN an endless source WHEN the stop flag is raised after 5 pairs THEN the encoders are
/// flushed, the trailer written and the file decodes with 5 frames per stream.
TEST_F(EncodeTest, stopFlagLeavesCompletePlayableFile)
{
    TestSource color([](int i) { return makeColor(i % 20); }, -1, 30.0, PixelFormat::Rgb24);
    TestSource depthSrc = nearness8Source(-1);
    std::atomic<bool> stop{false};
    EncodeCallbacks cb;
    cb.progress = [&stop](const EncodeProgress &p) {
        if (p.frames == 5)
            stop = true;
    };
    auto s = encodeStreams(color, depthSrc, fastOptions(path("out.mkv")), &stop, cb);
    ASSERT_TRUE(s) << s.error().what;
    EXPECT_TRUE(s->interrupted);
    EXPECT_EQ(s->frames, 5);
    const auto rb = test::readBack(path("out.mkv"), {0}, false);
    ASSERT_TRUE(rb.ok);
    ASSERT_EQ(rb.streams.size(), 2u);
    EXPECT_EQ(rb.decodeErrors, 0);
    EXPECT_EQ(rb.streams[0].pts.size(), 5u);
    EXPECT_EQ(rb.streams[1].pts.size(), 5u);
}

/// GIVEN --frames and --duration limits WHEN encoding an endless source THEN they end it.
TEST_F(EncodeTest, frameAndDurationLimits)
{
    for (const bool byFrames : {true, false}) {
        TestSource color([](int i) { return makeColor(i % 20); }, -1, 30.0, PixelFormat::Rgb24);
        TestSource depthSrc = nearness8Source(-1);
        EncodeOptions o = fastOptions(path(byFrames ? "f.mkv" : "d.mkv"));
        if (byFrames)
            o.maxFrames = 4;
        else
            o.maxDuration = 0.2; // 6 frames at 30 fps
        std::vector<EncodeProgress> progress;
        EncodeCallbacks callbacks;
        callbacks.progress = [&progress](const EncodeProgress &p) { progress.push_back(p); };
        auto s = encodeStreams(color, depthSrc, o, nullptr, callbacks);
        ASSERT_TRUE(s) << s.error().what;
        const int want = byFrames ? 4 : 6;
        EXPECT_EQ(s->frames, want);
        EXPECT_EQ(s->endedBy, byFrames ? "frames" : "duration");
        // The progress a terminal shows: one report a pair, each knowing the total the limit
        // sets (the endless source has none), the pair's PTS, and a time since the start that
        // grows and stays within the whole encode's
        ASSERT_EQ(progress.size(), static_cast<std::size_t>(want));
        double lastElapsed = 0.0;
        for (std::size_t i = 0; i < progress.size(); ++i) {
            EXPECT_EQ(progress[i].frames, static_cast<long long>(i + 1));
            EXPECT_EQ(progress[i].totalFrames, want) << "report " << i;
            EXPECT_NEAR(progress[i].pts, static_cast<double>(i) / 30.0, 1e-9);
            EXPECT_GE(progress[i].elapsed, lastElapsed);
            EXPECT_LE(progress[i].elapsed, s->elapsed);
            lastElapsed = progress[i].elapsed;
        }
    }
}

/// GIVEN MPEG-TS WHEN encoded THEN both streams share each PTS and the depth tags travel in a
/// third, timed ID3 stream.
TEST_F(EncodeTest, mpegTsKeepsPairedPtsAndTags)
{
    TestSource color = colorSource(5);
    TestSource depthSrc = nearness8Source(5);
    auto s = encodeStreams(color, depthSrc, fastOptions(path("out.ts")));
    ASSERT_TRUE(s) << s.error().what;
    const auto rb = test::readBack(path("out.ts"), {0}, false);
    ASSERT_TRUE(rb.ok);
    EXPECT_EQ(rb.format, "mpegts");
    ASSERT_EQ(rb.streams.size(), 3u);
    EXPECT_EQ(rb.streams[2].codec, "timed_id3");
    ASSERT_EQ(rb.streams[0].pts.size(), 5u);
    EXPECT_EQ(rb.streams[0].pts, rb.streams[1].pts);
}

/// Nonsense options are refused before anything is opened.
TEST_F(EncodeTest, badOptionsAreRefused)
{
    const auto bad = [this](auto change) {
        EncodeOptions o = fastOptions(path("out.mkv"));
        change(o);
        return !o.validate();
    };
    EXPECT_TRUE(bad([](EncodeOptions &o) { o.crf = -1; }));
    EXPECT_TRUE(bad([](EncodeOptions &o) { o.depthCrf = 52; }));
    EXPECT_TRUE(bad([](EncodeOptions &o) { o.range = depth::DepthRange{2.0, 1.0}; }));
    EXPECT_TRUE(bad([](EncodeOptions &o) { o.range = depth::DepthRange{1.0, 1.0}; }));
    EXPECT_TRUE(bad([](EncodeOptions &o) { o.raw.metresPerUnit = -0.001; }));
    EXPECT_TRUE(bad([](EncodeOptions &o) {
        o.width = 63;
        o.height = 48;
    }));
    EXPECT_TRUE(bad([](EncodeOptions &o) { o.maxFrames = -3; }));
    EXPECT_TRUE(bad([](EncodeOptions &o) { o.maxDuration = -1.0; }));
    EXPECT_TRUE(bad([this](EncodeOptions &o) {
        o.output = path("out.mp4");
        o.depthCodec = VideoCodec::Ffv1Gray16;
    }));
    EXPECT_TRUE(bad([](EncodeOptions &o) { o.output.clear(); }));
    EXPECT_FALSE(bad([](EncodeOptions &) {}));
    EXPECT_FALSE(parseContainer("avi"));
    EXPECT_TRUE(files().empty());
}

/// GIVEN an output in a missing directory, or a bad preset WHEN encoding THEN a clear error and no
/// file (not even a temporary one).
TEST_F(EncodeTest, unwritableOutputAndEncoderErrorsLeaveNoFile)
{
    TestSource color = colorSource(3);
    TestSource depthSrc = nearness8Source(3);
    auto s = encodeStreams(color, depthSrc, fastOptions(path("missing/dir/out.mkv")));
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error().code, Errc::InvalidArgument); // a bad output path, not a lost output

    TestSource color2 = colorSource(3);
    TestSource depth2 = nearness8Source(3);
    EncodeOptions o = fastOptions(path("out.mkv"));
    o.preset = "turbo";
    auto s2 = encodeStreams(color2, depth2, o);
    ASSERT_FALSE(s2);
    EXPECT_EQ(s2.error().code, Errc::InvalidArgument);
    EXPECT_TRUE(files().empty());

    // An odd color size cannot be 4:2:0.
    TestSource color3([](int i) { return makeColor(i, 63, 48); }, 3, 30.0, PixelFormat::Rgb24);
    TestSource depth3 = nearness8Source(3);
    auto s3 = encodeStreams(color3, depth3, fastOptions(path("out.mkv")));
    ASSERT_FALSE(s3);
    EXPECT_TRUE(files().empty());

    // Metric depth with no valid sample at all.
    TestSource color4 = colorSource(3);
    TestSource depth4([](int) { return Image::make(kW, kH, PixelFormat::Gray16); }, 3, 30.0,
                      PixelFormat::Gray16);
    auto s4 = encodeStreams(color4, depth4, fastOptions(path("out.mkv")));
    ASSERT_FALSE(s4);
    EXPECT_EQ(s4.error().code, Errc::InvalidArgument);
    EXPECT_TRUE(files().empty());
}

/// GIVEN a local UDP receiver WHEN encoding to udp://127.0.0.1:PORT THEN MPEG-TS packets arrive.
TEST_F(EncodeTest, streamsToUdpUrl)
{
    const int sock = ::socket(AF_INET, SOCK_DGRAM, 0);
    ASSERT_GE(sock, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = 0;
    ASSERT_EQ(::bind(sock, reinterpret_cast<sockaddr *>(&addr), sizeof addr), 0);
    socklen_t len = sizeof addr;
    ASSERT_EQ(::getsockname(sock, reinterpret_cast<sockaddr *>(&addr), &len), 0);
    const int rcvbuf = 4 << 20;
    ::setsockopt(sock, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);

    TestSource color = colorSource(3);
    TestSource depthSrc = nearness8Source(3);
    const std::string url = "udp://127.0.0.1:" + std::to_string(ntohs(addr.sin_port));
    EXPECT_EQ(containerForOutput(url), Container::MpegTs);
    auto s = encodeStreams(color, depthSrc, fastOptions(url));
    ASSERT_TRUE(s) << s.error().what;
    EXPECT_TRUE(files().empty()) << "a URL output writes no local file";

    std::size_t bytes = 0;
    std::size_t syncOk = 0;
    std::size_t datagrams = 0;
    std::uint8_t buf[65536];
    for (;;) {
        const ssize_t n = ::recv(sock, buf, sizeof buf, MSG_DONTWAIT);
        if (n <= 0)
            break;
        ++datagrams;
        bytes += static_cast<std::size_t>(n);
        syncOk += (n % 188 == 0 && buf[0] == 0x47) ? 1u : 0u;
    }
    ::close(sock);
    EXPECT_GT(datagrams, 0u);
    EXPECT_EQ(syncOk, datagrams) << "every datagram holds whole TS packets";
    EXPECT_GT(bytes, 1000u);
}

} // namespace
