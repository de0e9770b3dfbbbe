/// \file
/// \brief The sender's frame sources (app/media/frame_source.h): image sequences by pattern and
/// glob, raw video with demuxer options, spec prefixes and providers, and the bad inputs.

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "depthtouch/media/encode_job.h"
#include "depthtouch/media/encoder.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/image_io.h"
#include "encode_sources.h"
#include "support/temp_dir.h"

using namespace depthtouch;
using namespace depthtouch::media;
namespace fs = std::filesystem;

namespace {

using test::EncodeTest;
using test::kH;
using test::kW;
using test::makeColor;
using test::makeMetric;
using test::TestSource;

class FrameSourceTest : public EncodeTest {};

/// GIVEN three 16-bit PNGs WHEN opened by printf pattern and by glob THEN both give the samples
/// bit-exact, in order, at --fps, and then end.
TEST_F(FrameSourceTest, pngSequenceByPatternAndGlob)
{
    for (int i = 0; i < 3; ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "d-%04d.png", i);
        ASSERT_TRUE(writePng(path(name), makeMetric(i)));
    }
    for (const std::string &spec : {path("d-%04d.png"), path("d-*.png")}) {
        SourceOptions so;
        so.fps = 15.0;
        auto src = openFrameSource(spec, so);
        ASSERT_TRUE(src) << spec << ": " << src.error().what;
        const SourceInfo &info = (*src)->info();
        EXPECT_EQ(info.width, kW);
        EXPECT_EQ(info.height, kH);
        EXPECT_DOUBLE_EQ(info.fps, 15.0);
        EXPECT_EQ(info.nativeFormat, PixelFormat::Gray16);
        EXPECT_EQ(info.frameCount, 3);
        for (int i = 0; i < 3; ++i) {
            auto f = (*src)->next(PixelFormat::Gray16);
            ASSERT_TRUE(f) << f.error().what;
            EXPECT_EQ(f->image.data, makeMetric(i).data) << spec << " frame " << i;
            EXPECT_NEAR(f->pts, i / 15.0, 1e-9);
        }
        auto end = (*src)->next(PixelFormat::Gray16);
        ASSERT_FALSE(end);
        EXPECT_EQ(end.error().code, Errc::EndOfStream);
    }
}

/// GIVEN raw gray16le bytes WHEN opened with the rawvideo demuxer and its options THEN the samples
/// come out as written; a looping still repeats.
TEST_F(FrameSourceTest, rawVideoOptionsAndLoopingStill)
{
    {
        std::ofstream out(path("d.raw"), std::ios::binary);
        for (int i = 0; i < 2; ++i) {
            const Image img = makeMetric(i);
            out.write(reinterpret_cast<const char *>(img.data.data()),
                      static_cast<std::streamsize>(img.data.size()));
        }
    }
    SourceOptions so;
    so.format = "rawvideo";
    so.videoSize = std::to_string(kW) + "x" + std::to_string(kH);
    so.pixelFormat = "gray16le";
    so.fps = 10.0;
    auto src = openFrameSource(path("d.raw"), so);
    ASSERT_TRUE(src) << src.error().what;
    EXPECT_EQ((*src)->info().nativeFormat, PixelFormat::Gray16);
    for (int i = 0; i < 2; ++i) {
        auto f = (*src)->next(PixelFormat::Gray16);
        ASSERT_TRUE(f) << f.error().what;
        EXPECT_EQ(f->image.data, makeMetric(i).data);
    }
    EXPECT_FALSE((*src)->next(PixelFormat::Gray16));

    ASSERT_TRUE(writePng(path("still.png"), makeColor(0)));
    SourceOptions loop;
    loop.loop = true;
    auto still = openFrameSource(path("still.png"), loop);
    ASSERT_TRUE(still) << still.error().what;
    for (int i = 0; i < 5; ++i) {
        auto f = (*still)->next(PixelFormat::Rgb24);
        ASSERT_TRUE(f) << "looping still ended at " << i;
        EXPECT_EQ(f->image.data, makeColor(0).data);
    }
}

/// GIVEN a three-frame video file (FFV1, lossless) at 10 fps WHEN opened with loop THEN it plays
/// 0, 1, 2, 0, 1, 2, 0, 1 bit-exact with PTS going on at 1/10 s across each seam (ffmpeg's
/// -stream_loop -1); without loop it ends after three frames.
TEST_F(FrameSourceTest, aLoopedVideoFileStartsAgainWithItsTimestampsGoingOn)
{
    {
        MuxerOptions mo;
        mo.output = path("v.mkv");
        auto muxer = Muxer::open(mo);
        ASSERT_TRUE(muxer) << muxer.error().what;
        VideoEncoderConfig vc;
        vc.codec = VideoCodec::Ffv1Gray16;
        vc.width = kW;
        vc.height = kH;
        vc.fps = 10.0;
        auto enc = VideoEncoder::create(vc, **muxer);
        ASSERT_TRUE(enc) << enc.error().what;
        ASSERT_TRUE((*muxer)->start());
        for (int i = 0; i < 3; ++i)
            ASSERT_TRUE((*enc)->encode(makeMetric(i), i / 10.0));
        ASSERT_TRUE((*enc)->flush());
        ASSERT_TRUE((*muxer)->finish());
    }
    SourceOptions once;
    auto plain = openFrameSource(path("v.mkv"), once);
    ASSERT_TRUE(plain) << plain.error().what;
    for (int i = 0; i < 3; ++i)
        ASSERT_TRUE((*plain)->next(PixelFormat::Gray16)) << i;
    EXPECT_FALSE((*plain)->next(PixelFormat::Gray16));

    SourceOptions loop;
    loop.loop = true;
    auto looped = openFrameSource(path("v.mkv"), loop);
    ASSERT_TRUE(looped) << looped.error().what;
    EXPECT_EQ((*looped)->info().frameCount, 0); // endless
    for (int i = 0; i < 8; ++i) {
        auto f = (*looped)->next(PixelFormat::Gray16);
        ASSERT_TRUE(f) << "the looped video ended at frame " << i << ": " << f.error().what;
        EXPECT_EQ(f->image.data, makeMetric(i % 3).data) << "frame " << i;
        EXPECT_NEAR(f->pts, i / 10.0, 1e-6) << "frame " << i;
    }
}

/// GIVEN a file of two untitled FFV1 streams (frames 0.. and 5..) with a container tag
/// depth_near=9 WHEN opened with SourceOptions::streamIndex THEN that stream is read (1: frames
/// 5.., 0: frames 0..), a number that is no video stream is InvalidArgument, and the tags given
/// in SourceOptions::tags come before the file's own and win over them.
TEST_F(FrameSourceTest, aStreamChosenByItsContainerNumberWithTagsFromElsewhere)
{
    {
        MuxerOptions mo;
        mo.output = path("two.mkv");
        mo.tags = {{"depth_near", "9"}, {"depth_far", "12"}};
        auto muxer = Muxer::open(mo);
        ASSERT_TRUE(muxer) << muxer.error().what;
        VideoEncoderConfig vc;
        vc.codec = VideoCodec::Ffv1Gray16;
        vc.width = kW;
        vc.height = kH;
        vc.fps = 10.0;
        auto first = VideoEncoder::create(vc, **muxer);
        auto second = VideoEncoder::create(vc, **muxer);
        ASSERT_TRUE(first && second);
        ASSERT_TRUE((*muxer)->start());
        for (int i = 0; i < 2; ++i) {
            ASSERT_TRUE((*first)->encode(makeMetric(i), i / 10.0));
            ASSERT_TRUE((*second)->encode(makeMetric(i + 5), i / 10.0));
        }
        ASSERT_TRUE((*first)->flush());
        ASSERT_TRUE((*second)->flush());
        ASSERT_TRUE((*muxer)->finish());
    }
    for (const int stream : {1, 0}) {
        SourceOptions so;
        so.streamIndex = stream;
        so.tags = {{"depth_near", "0.25"}};
        auto src = openFrameSource(path("two.mkv"), so);
        ASSERT_TRUE(src) << src.error().what;
        for (int i = 0; i < 2; ++i) {
            auto f = (*src)->next(PixelFormat::Gray16);
            ASSERT_TRUE(f) << "stream " << stream << " frame " << i;
            EXPECT_EQ(f->image.data, makeMetric(i + (stream == 1 ? 5 : 0)).data)
                << "stream " << stream << " frame " << i;
        }
        const std::string *near = (*src)->info().tag("depth_near");
        const std::string *far = (*src)->info().tag("depth_far");
        ASSERT_TRUE(near != nullptr && far != nullptr);
        EXPECT_EQ(*near, "0.25");
        EXPECT_EQ(*far, "12");
    }
    SourceOptions none;
    none.streamIndex = 2;
    auto bad = openFrameSource(path("two.mkv"), none);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().code, Errc::InvalidArgument);
}

/// Source specs: prefixes parsed in one place; v4l2:/synthetic: are "not built in" without a
/// provider and reach the provider when there is one.
TEST_F(FrameSourceTest, specPrefixesAndProviders)
{
    auto v = parseSourceSpec("v4l2:/dev/video3");
    ASSERT_TRUE(v);
    EXPECT_EQ(v->kind, SourceKind::V4l2);
    EXPECT_EQ(v->target, "/dev/video3");
    auto syn = parseSourceSpec("synthetic:sphere");
    ASSERT_TRUE(syn);
    EXPECT_EQ(syn->kind, SourceKind::Synthetic);
    auto f = parseSourceSpec("udp://1.2.3.4:5");
    ASSERT_TRUE(f);
    EXPECT_EQ(f->kind, SourceKind::Ffmpeg);
    EXPECT_FALSE(parseSourceSpec(""));
    EXPECT_FALSE(parseSourceSpec("v4l2:"));

    auto none = openFrameSource("v4l2:/dev/video0", SourceOptions{});
    ASSERT_FALSE(none);
    EXPECT_EQ(none.error().code, Errc::NotSupported);
    auto none2 = openFrameSource("synthetic:cube", SourceOptions{});
    ASSERT_FALSE(none2);
    EXPECT_EQ(none2.error().code, Errc::NotSupported);

    SourceProviders providers;
    std::string asked;
    providers.synthetic = [&asked](const std::string &target,
                                   const SourceOptions &) -> Result<std::unique_ptr<FrameSource>> {
        asked = target;
        return std::unique_ptr<FrameSource>(std::make_unique<TestSource>(
            [](int i) { return makeColor(i); }, 1, 30.0, PixelFormat::Rgb24));
    };
    auto s = openFrameSource("synthetic:cube", SourceOptions{}, providers);
    ASSERT_TRUE(s);
    EXPECT_EQ(asked, "cube");
}

/// Missing file, no match, not media, no video stream, bad options, a corrupt image mid-sequence.
TEST_F(FrameSourceTest, badInputsGiveClearErrors)
{
    auto missing = openFrameSource(path("nothing.mkv"), SourceOptions{});
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error().code, Errc::Io);
    auto noMatch = openFrameSource(path("f-%06d.png"), SourceOptions{});
    ASSERT_FALSE(noMatch);
    EXPECT_EQ(noMatch.error().code, Errc::Io);

    {
        std::ofstream(path("junk.mkv")) << "this is not a video file at all, just text\n";
    }
    auto junk = openFrameSource(path("junk.mkv"), SourceOptions{});
    ASSERT_FALSE(junk);
    EXPECT_EQ(junk.error().code, Errc::InvalidArgument);

    // A WAV file: media, but no video stream (header + 0.1 s of 8 kHz 8-bit silence).
    {
        std::ofstream w(path("a.wav"), std::ios::binary);
        const auto u32 = [&w](std::uint32_t v) { w.write(reinterpret_cast<const char *>(&v), 4); };
        const auto u16 = [&w](std::uint16_t v) { w.write(reinterpret_cast<const char *>(&v), 2); };
        const std::uint32_t n = 800;
        w << "RIFF";
        u32(36 + n);
        w << "WAVEfmt ";
        u32(16);
        u16(1);
        u16(1);
        u32(8000);
        u32(8000);
        u16(1);
        u16(8);
        w << "data";
        u32(n);
        w << std::string(n, '\x80');
    }
    auto wav = openFrameSource(path("a.wav"), SourceOptions{});
    ASSERT_FALSE(wav);
    EXPECT_EQ(wav.error().code, Errc::InvalidArgument);
    EXPECT_STREQ(wav.error().what, "The input has no video stream");

    SourceOptions badFps;
    badFps.fps = -1.0;
    EXPECT_FALSE(openFrameSource(path("a.wav"), badFps));
    SourceOptions badPix;
    badPix.format = "rawvideo";
    badPix.pixelFormat = "nonsense";
    EXPECT_FALSE(openFrameSource(path("a.wav"), badPix));
    SourceOptions badDemuxer;
    badDemuxer.format = "nonsense";
    EXPECT_FALSE(openFrameSource(path("a.wav"), badDemuxer));

    // Frame 1 of 3 truncated: frames before it decode, then a clear error (not a crash or hang).
    for (int i = 0; i < 3; ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "c-%02d.png", i);
        ASSERT_TRUE(writePng(path(name), makeColor(i)));
    }
    fs::resize_file(path("c-01.png"), 60);
    auto seq = openFrameSource(path("c-%02d.png"), SourceOptions{});
    ASSERT_TRUE(seq) << seq.error().what;
    ASSERT_TRUE((*seq)->next(PixelFormat::Rgb24));
    bool failed = false;
    for (int i = 0; i < 3 && !failed; ++i) {
        auto r = (*seq)->next(PixelFormat::Rgb24);
        if (!r) {
            failed = true;
            EXPECT_NE(r.error().code, Errc::EndOfStream) << "a damaged frame is not an end";
        }
    }
    EXPECT_TRUE(failed);
}

} // namespace
