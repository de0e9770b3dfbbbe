// Receiver on the ffmpeg backends, on small files written in the test with libavformat/libavcodec.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/drivers/mock/mock_media_source.h"
#include "test_media.h"

namespace depthtouch::receivertest {
namespace {

using receiver::ReceiverConfig;
using receiver::ReceiverMode;
using std::chrono::milliseconds;

hal::Pts framePts(int i, int fps)
{
    return hal::Pts(static_cast<std::int64_t>(i) * 1'000'000'000 / fps);
}

/// Milliseconds of \a t (Matroska keeps millisecond timestamps).
double ms(hal::Pts t)
{
    return static_cast<double>(t.count()) * 1e-6;
}

class ReceiverMediaTest : public ::testing::Test {
protected:
    std::string write(const std::string &name, const Clip &clip)
    {
        const std::string path = tmp_.path(name);
        const std::string err = writeClip(path, clip);
        EXPECT_EQ(err, "") << name;
        return path;
    }
    TempDir tmp_;
};

TEST_F(ReceiverMediaTest, standardFilePairsFramesAndReadsTheDepthMetadata)
{
    const std::string path = write("std.mkv", Clip::standard(64, 48, 12));
    auto r = openFfmpeg(path);
    ASSERT_TRUE(r) << r.error().what;
    const receiver::ReceiverInfo &info = (*r)->info();
    EXPECT_EQ(info.mode, ReceiverMode::ColorAndDepth);
    EXPECT_STREQ(info.roles.colorReason, "title");
    EXPECT_STREQ(info.roles.depthReason, "title");
    EXPECT_EQ(info.depthFormat, hal::PixelFormat::Gray8); // luma of the 4:0:0 stream
    EXPECT_DOUBLE_EQ(info.depth.depth.nearMetres, 0.5);
    EXPECT_DOUBLE_EQ(info.depth.depth.farMetres, 4.0);
    EXPECT_EQ(info.depth.depth.mapping, "inverse");
    EXPECT_EQ(info.depth.depth.bits, 8);
    const auto frames = drain(**r);
    ASSERT_EQ(frames.size(), 12u);
    for (int i = 0; i < 12; ++i) {
        const Record &f = frames[static_cast<std::size_t>(i)];
        EXPECT_NEAR(ms(f.pts), ms(framePts(i, 30)), 1.0) << i;
        EXPECT_EQ(f.depthPts, f.pts) << i;
        // lossless depth: the sample is the pattern of frame i exactly
        EXPECT_EQ(f.depthSample, depthPattern(0, 0, i)) << i;
        EXPECT_EQ(f.hasNext, i < 11);
        if (i < 11) {
            EXPECT_NEAR(ms(f.nextPts), ms(framePts(i + 1, 30)), 1.0);
        }
        EXPECT_FALSE(f.depthDuplicated || f.depthMissing || f.concealed);
    }
    const auto s = (*r)->stats();
    EXPECT_EQ(s.decodeErrors + s.readErrors + s.ptsGaps + s.depthUnpaired, 0u);
}

TEST_F(ReceiverMediaTest, untitledStreamsAreIdentifiedByPixelFormatOrOrder)
{
    // gray FFV1 depth: found by its pixel format
    Clip ffv1 = Clip::standard(32, 24, 5);
    ffv1.color.title.clear();
    ffv1.depth.title.clear();
    ffv1.depth.metadata.clear();
    ffv1.depth.encoder = "ffv1";
    auto r = openFfmpeg(write("ffv1.mkv", ffv1));
    ASSERT_TRUE(r);
    EXPECT_STREQ((*r)->info().roles.depthReason, "gray pixel format");
    EXPECT_EQ((*r)->info().roles.depth, 1);
    EXPECT_EQ(drain(**r).size(), 5u);

    // gray H.264 (libavcodec says 4:2:0): metadata of its own tells, else its 4:0:0 SPS
    Clip meta = Clip::standard(32, 24, 5);
    meta.color.title.clear();
    meta.depth.title.clear();
    auto m = openFfmpeg(write("meta.mkv", meta));
    ASSERT_TRUE(m);
    EXPECT_STREQ((*m)->info().roles.depthReason, "depth metadata");

    meta.depth.metadata.clear();
    auto g = openFfmpeg(write("gray264.mkv", meta));
    ASSERT_TRUE(g);
    EXPECT_STREQ((*g)->info().roles.depthReason, "gray pixel format");
    EXPECT_EQ((*g)->info().roles.depth, 1);

    // depth in a 4:2:0 H.264 stream, untitled and untagged: stream order (reported)
    meta.depth.gray = false;
    auto o = openFfmpeg(write("order.mkv", meta));
    ASSERT_TRUE(o);
    EXPECT_STREQ((*o)->info().roles.depthReason, "stream order");
    EXPECT_FALSE((*o)->info().notes.empty());
    const auto frames = drain(**o);
    ASSERT_EQ(frames.size(), 5u);
    EXPECT_EQ(frames[2].depthSample, depthPattern(0, 0, 2));
}

TEST_F(ReceiverMediaTest, singleStreamFilesPlayDepthOnlyOrColorOnly)
{
    Clip depth = Clip::standard(32, 24, 6);
    depth.color.enabled = false;
    depth.depth.title.clear();
    depth.depth.metadata.clear();
    const std::string path = write("depth-only.mkv", depth);
    // gray H.264 alone is depth by its 4:0:0 SPS (once: it played as color), and when the
    // caller wants depth (touch)
    auto auto_ = openFfmpeg(path);
    ASSERT_TRUE(auto_);
    EXPECT_EQ((*auto_)->info().mode, ReceiverMode::DepthOnly);
    ReceiverConfig wantDepth;
    wantDepth.single = receiver::SingleStream::Depth;
    wantDepth.requireDepth = true;
    auto d = openFfmpeg(path, wantDepth);
    ASSERT_TRUE(d);
    EXPECT_EQ((*d)->info().mode, ReceiverMode::DepthOnly);
    const auto frames = drain(**d);
    ASSERT_EQ(frames.size(), 6u);
    EXPECT_EQ(frames[5].depthSample, depthPattern(0, 0, 5));
    EXPECT_TRUE(frames[4].hasNext);

    Clip color = Clip::standard(32, 24, 6);
    color.depth.enabled = false;
    auto c = openFfmpeg(write("color-only.mkv", color));
    ASSERT_TRUE(c);
    EXPECT_EQ((*c)->info().mode, ReceiverMode::ColorOnly);
    for (const auto &f : drain(**c))
        EXPECT_TRUE(f.depthMissing);
    ReceiverConfig needDepth;
    needDepth.requireDepth = true;
    auto missing = openFfmpeg(tmp_.path("color-only.mkv"), needDepth);
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error().code, Errc::NotSupported);
}

TEST_F(ReceiverMediaTest, differentFrameRatesAndLengthsFollowTheColorTimeline)
{
    // color 30 fps × 30 frames (1 s), depth 15 fps × 10 frames (0.67 s)
    Clip clip = Clip::standard(32, 24, 30, 30);
    clip.depth.fps = 15;
    clip.depth.frames = 10;
    auto r = openFfmpeg(write("rates.mkv", clip));
    ASSERT_TRUE(r);
    const auto frames = drain(**r);
    ASSERT_EQ(frames.size(), 30u);
    for (int i = 0; i < 20; ++i) {
        const Record &f = frames[static_cast<std::size_t>(i)];
        EXPECT_NEAR(ms(f.depthPts), ms(framePts(i / 2, 15)), 1.0) << i;
        EXPECT_EQ(f.depthDuplicated, i % 2 == 1) << i;
        EXPECT_EQ(f.depthSample, depthPattern(0, 0, i / 2)) << i;
    }
    for (int i = 20; i < 30; ++i) { // the depth video has ended: its last frame stays
        EXPECT_TRUE(frames[static_cast<std::size_t>(i)].depthDuplicated);
        EXPECT_FALSE(frames[static_cast<std::size_t>(i)].hasNext);
    }
    EXPECT_EQ((*r)->stats().depthDuplicated, 20u);
}

TEST_F(ReceiverMediaTest, shorterDepthStreamWithBFramesKeepsItsLastFrames)
{
    // GIVEN B-frames (the decoders hold frames back) and a depth stream ending before the color
    Clip clip = Clip::standard(32, 24, 30, 30);
    clip.color.bframes = 2;
    clip.depth.bframes = 2;
    clip.depth.fps = 15;
    clip.depth.frames = 11;
    clip.gop = 30;
    auto r = openFfmpeg(write("bframes.mkv", clip));
    ASSERT_TRUE(r);
    const auto frames = drain(**r);
    ASSERT_EQ(frames.size(), 30u);
    // THEN every depth frame is used at its time, the held-back last ones included
    for (int i = 0; i < 22; ++i)
        EXPECT_NEAR(ms(frames[static_cast<std::size_t>(i)].depthPts), ms(framePts(i / 2, 15)), 1.0)
            << i;
    for (int i = 22; i < 30; ++i)
        EXPECT_NEAR(ms(frames[static_cast<std::size_t>(i)].depthPts), ms(framePts(10, 15)), 1.0);
    const auto s = (*r)->stats();
    EXPECT_EQ(s.depthUnpaired, 0u);
    EXPECT_EQ(s.pairingForced, 0u);
}

TEST_F(ReceiverMediaTest, ptsGapsAreCountedAndBridged)
{
    Clip clip = Clip::standard(32, 24, 10, 30);
    clip.color.pts = {0, 1, 2, 3, 4, 10, 11, 12, 13, 14};
    clip.depth.pts = {0, 1, 2, 3, 4, 10, 11, 12, 13, 14};
    auto r = openFfmpeg(write("gap.mkv", clip));
    ASSERT_TRUE(r);
    const auto frames = drain(**r);
    ASSERT_EQ(frames.size(), 10u);
    EXPECT_NEAR(ms(frames[5].pts), ms(framePts(10, 30)), 1.0);
    EXPECT_NEAR(ms(frames[5].depthPts), ms(framePts(10, 30)), 1.0);
    EXPECT_NEAR(ms(frames[4].nextPts), ms(framePts(10, 30)), 1.0); // interpolate across the gap
    EXPECT_EQ((*r)->stats().ptsGaps, 2u);
}

TEST_F(ReceiverMediaTest, truncatedFilesEndCleanly)
{
    const std::string path = write("long.mkv", Clip::standard(64, 48, 60));
    const auto size = std::filesystem::file_size(path);
    for (const double keep : {0.9, 0.5}) {
        const std::string cut = tmp_.path("cut.mkv");
        std::filesystem::copy_file(path, cut, std::filesystem::copy_options::overwrite_existing);
        std::filesystem::resize_file(cut,
                                     static_cast<std::uintmax_t>(static_cast<double>(size) * keep));
        auto r = openFfmpeg(cut);
        ASSERT_TRUE(r) << keep;
        const auto frames = drain(**r);
        EXPECT_LT(frames.size(), 60u) << keep;
        EXPECT_GT(frames.size(), 0u) << keep;
        for (std::size_t i = 1; i < frames.size(); ++i)
            EXPECT_GT(frames[i].pts, frames[i - 1].pts);
    }
    // cut inside the header: a clear open error
    const std::string stub = tmp_.path("stub.mkv");
    std::filesystem::copy_file(path, stub);
    std::filesystem::resize_file(stub, 40);
    auto r = openFfmpeg(stub);
    EXPECT_FALSE(r);
    // not a video at all
    std::ofstream(tmp_.path("text.mkv")) << "not a video file\n";
    EXPECT_FALSE(openFfmpeg(tmp_.path("text.mkv")));
    EXPECT_FALSE(openFfmpeg(tmp_.path("missing.mkv")));
}

TEST_F(ReceiverMediaTest, corruptedPacketsAreConcealedOrCountedAndDecodingGoesOn)
{
    const std::string path = write("c.mkv", Clip::standard(64, 48, 20));
    auto src = drivers::createMediaSource("ffmpeg", hal::BackendConfig{});
    ASSERT_TRUE(src);
    std::vector<std::uint8_t> damaged;
    // damage the middle of packets 10..15 (both streams, P-frames)
    FaultySource::PacketEdit edit = [&damaged](hal::Packet &p, std::uint64_t ordinal) {
        if (ordinal < 10 || ordinal > 15 || p.size < 8)
            return true;
        damaged.assign(p.data, p.data + p.size);
        for (std::size_t i = p.size / 3; i < p.size; i += 3)
            damaged[i] = static_cast<std::uint8_t>(damaged[i] ^ 0xa5);
        p.data = damaged.data();
        return true;
    };
    auto faulty = std::make_unique<FaultySource>(std::move(*src), nullptr, edit);
    receiver::DecoderFactory factory = [](const hal::StreamInfo &) {
        return drivers::createVideoDecoder("ffmpeg", hal::BackendConfig{});
    };
    auto r = receiver::Receiver::open(std::move(faulty), path.c_str(), factory);
    ASSERT_TRUE(r);
    const auto frames = drain(**r);
    const auto s = (*r)->stats();
    // THEN the damage shows in the counters and the frames after it still come out
    EXPECT_GT(s.framesConcealed + s.decodeErrors + s.depthDuplicated, 0u);
    EXPECT_GE(frames.size(), 14u);
    EXPECT_NEAR(ms(frames.back().pts), ms(framePts(19, 30)), 1.0);
}

TEST_F(ReceiverMediaTest, aStreamWhoseFramesOnlyLagDecodesOnWithoutWaitingForAKeyFrame)
{
    // GIVEN one key frame (frame 0) and ten depth packets in the middle that decode to no picture
    // (an access unit delimiter alone: the decoder takes them and gives nothing, as libavcodec
    // withholds pictures after a loss) while the color frames fill the pairing window
    Clip clip = Clip::standard(64, 48, 60);
    clip.gop = 60;
    const std::string path = write("lag.mkv", clip);
    auto src = drivers::createMediaSource("ffmpeg", hal::BackendConfig{});
    ASSERT_TRUE(src);
    static constexpr std::uint8_t kDelimiter[] = {0, 0, 0, 2, 0x09, 0xf0}; // length-prefixed NAL
    std::uint64_t depthPackets = 0;
    FaultySource::PacketEdit edit = [&depthPackets](hal::Packet &p, std::uint64_t) {
        if (p.streamIndex != 1)
            return true;
        if (const std::uint64_t n = depthPackets++; n >= 20 && n < 30) {
            p.data = kDelimiter;
            p.size = sizeof kDelimiter;
        }
        return true;
    };
    auto faulty = std::make_unique<FaultySource>(std::move(*src), nullptr, edit);
    receiver::DecoderFactory factory = [](const hal::StreamInfo &) {
        return drivers::createVideoDecoder("ffmpeg", hal::BackendConfig{});
    };
    auto r = receiver::Receiver::open(std::move(faulty), path.c_str(), factory);
    ASSERT_TRUE(r);
    const auto frames = drain(**r);
    const auto s = (*r)->stats();
    // THEN its packets never stopped: the depth decoder is not drained and flushed (which would
    // hold every depth frame until a key frame that never comes) and decodes the frames after
    // the gap from the pictures it has
    EXPECT_EQ(depthPackets, 60u);
    EXPECT_EQ(s.streamsResumed, 0u);
    EXPECT_GE(s.depthFrames, 45u);
    EXPECT_EQ(frames.size(), 60u);
}

TEST_F(ReceiverMediaTest, unsupportedCodecIsAClearError)
{
    // the ffmpeg decoders cannot decode the mock codec
    receiver::DecoderFactory factory = [](const hal::StreamInfo &) {
        return drivers::createVideoDecoder("ffmpeg", hal::BackendConfig{});
    };
    auto r =
        receiver::Receiver::open(std::make_unique<drivers::MockMediaSource>(), "mock://x", factory);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::NotSupported);
}

TEST_F(ReceiverMediaTest, streamsAboveTheSizeLimitAreRefused)
{
    // GIVEN a 64x48 clip, and limits at its size, one pixel below in width or in height alone
    const std::string path = write("big.mkv", Clip::standard(64, 48, 3));
    struct Case {
        int maxWidth, maxHeight;
        bool opens;
    };
    for (const Case c : {Case{64, 48, true}, Case{63, 48, false}, Case{64, 47, false},
                         Case{32, 4096, false}, Case{4096, 24, false}}) {
        ReceiverConfig cfg;
        cfg.maxWidth = c.maxWidth;
        cfg.maxHeight = c.maxHeight;
        auto r = openFfmpeg(path, cfg);
        // THEN a stream at the limit plays and one larger in either dimension is refused
        ASSERT_EQ(static_cast<bool>(r), c.opens) << c.maxWidth << "x" << c.maxHeight;
        if (!c.opens)
            EXPECT_EQ(r.error().code, Errc::InvalidArgument) << c.maxWidth << "x" << c.maxHeight;
        else
            EXPECT_EQ(drain(**r).size(), 3u);
    }
}

TEST_F(ReceiverMediaTest, mp4AndMpegTsPairToo)
{
    for (const char *name : {"clip.mp4", "clip.ts"}) {
        auto r = openFfmpeg(write(name, Clip::standard(32, 24, 8)));
        ASSERT_TRUE(r) << name;
        EXPECT_EQ((*r)->info().mode, ReceiverMode::ColorAndDepth) << name;
        const auto frames = drain(**r);
        ASSERT_EQ(frames.size(), 8u) << name;
        for (std::size_t i = 0; i < frames.size(); ++i) {
            EXPECT_EQ(frames[i].depthPts, frames[i].pts) << name << " " << i;
            EXPECT_EQ(frames[i].depthSample, depthPattern(0, 0, static_cast<int>(i))) << name;
        }
    }
}

} // namespace
} // namespace depthtouch::receivertest
