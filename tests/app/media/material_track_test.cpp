// The material track's sender side (app/media material_track.h): nearest-neighbour resizing that
// never blends codes, and encodeStreams() with a material source writing a third, lossless
// libx264rgb stream titled `material` with the depth frames' PTS, read back bit-exact.
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "depthtouch/media/encode_job.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/image_io.h"
#include "depthtouch/media/material_track.h"
#include "readback.h"

namespace depthtouch::media {
namespace {

Image randomCodes(int w, int h, unsigned seed)
{
    std::mt19937 rng(seed);
    Image img = Image::make(w, h, PixelFormat::Rgb24);
    for (auto &b : img.data)
        b = static_cast<std::uint8_t>(rng() & 0xff);
    return img;
}

/// \return whether every pixel of \a out is the three codes of one pixel of \a in.
bool everyPixelIsAnInputPixel(const Image &in, const Image &out)
{
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            const std::uint8_t *p = out.row(y) + 3 * x;
            bool found = false;
            for (int sy = 0; sy < in.height && !found; ++sy)
                for (int sx = 0; sx < in.width && !found; ++sx) {
                    const std::uint8_t *q = in.row(sy) + 3 * sx;
                    found = p[0] == q[0] && p[1] == q[1] && p[2] == q[2];
                }
            if (!found)
                return false;
        }
    return true;
}

TEST(MaterialTrackTest, resizingNeverBlendsCodes)
{
    // GIVEN random codes (any blend of two pixels would be a new triple)
    const Image small = randomCodes(17, 13, 1);
    const Image large = randomCodes(64, 48, 2);
    MaterialScaler scaler;
    // WHEN enlarged, shrunk (by non-integer ratios) and kept
    auto up = scaler.resize(small, 64, 48);
    auto down = scaler.resize(large, 17, 13);
    auto same = scaler.resize(large, 64, 48);
    ASSERT_TRUE(up && down && same);
    // THEN each output pixel is one input pixel; the same size is a copy
    EXPECT_EQ(up->width, 64);
    EXPECT_EQ(up->height, 48);
    EXPECT_TRUE(everyPixelIsAnInputPixel(small, *up));
    EXPECT_TRUE(everyPixelIsAnInputPixel(large, *down));
    EXPECT_EQ(same->data, large.data);
    // AND a non-RGB picture is refused
    EXPECT_FALSE(scaler.resize(Image::make(4, 4, PixelFormat::Gray8), 8, 8));
}

TEST(MaterialTrackTest, lastFrameHoldsAndAnEmptySourceIsRefused)
{
    auto still = makeStillFrameSource(randomCodes(8, 6, 3), 30.0, "still");
    MaterialTrack track(*still);
    auto a = track.next(16, 12);
    auto b = track.next(16, 12);
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->data, b->data);
    EXPECT_EQ(track.framesRead(), 2);
}

TEST(MaterialTrackTest, encodeWritesALosslessThirdStreamWithTheDepthPts)
{
    // GIVEN still color and depth at 64x48 and material codes at 17x13
    const std::string out =
        ::testing::TempDir() + "material-" + std::to_string(::getpid()) + ".mkv";
    Image color = Image::make(64, 48, PixelFormat::Rgb24);
    Image depth = Image::make(64, 48, PixelFormat::Gray8);
    for (auto &b : depth.data)
        b = 128;
    const Image codes = randomCodes(17, 13, 4);
    auto colorSrc = makeStillFrameSource(color, 30.0, "color");
    auto depthSrc = makeStillFrameSource(depth, 30.0, "depth");
    auto materialSrc = makeStillFrameSource(codes, 30.0, "material");
    EncodeOptions o;
    o.output = out;
    o.preset = "ultrafast";
    o.maxFrames = 3;
    // WHEN encoded with the material track
    auto s = encodeStreams(*colorSrc, *depthSrc, materialSrc.get(), o);
    ASSERT_TRUE(s) << s.error().what;
    EXPECT_EQ(s->frames, 3);
    EXPECT_GT(s->materialBytes, 0);
    // THEN stream 2 is H.264 gbrp titled material with the tags, PTS equal to depth's, and its
    // frames are the codes resized nearest-neighbour, bit for bit
    const test::FileReadback rb = test::readBack(out, {0, 2});
    std::filesystem::remove(out);
    ASSERT_TRUE(rb.ok) << rb.error;
    ASSERT_EQ(rb.streams.size(), 3u);
    const test::StreamReadback &m = rb.streams[2];
    test::expectStream(
        m, {.codec = "h264",
            .pixFmt = "gbrp",
            .profile = "High 4:4:4 Predictive",
            .tags = {{"title", "material"},
                     {"material_planes", "stiffness_scale,static_friction,dynamic_friction"},
                     {"material_scales", "0.015625,0.01,0.01"}}});
    EXPECT_EQ(m.pts, rb.streams[1].pts);
    MaterialScaler scaler;
    auto expected = scaler.resize(codes, 64, 48);
    ASSERT_TRUE(expected);
    ASSERT_EQ(m.frames.size(), 3u);
    for (const Image &f : m.frames)
        EXPECT_EQ(f.data, expected->data);
    // AND probe finds it: lossless, with the ranges of the first frame
    EXPECT_EQ(rb.decodeErrors, 0);
}

TEST(MaterialTrackTest, probeReportsTheStreamLosslessAndItsRanges)
{
    const std::string out = ::testing::TempDir() + "probe-" + std::to_string(::getpid()) + ".mp4";
    Image codes = Image::make(8, 6, PixelFormat::Rgb24);
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 8; ++x) {
            std::uint8_t *p = codes.row(y) + 3 * x;
            p[0] = static_cast<std::uint8_t>(x < 4 ? 32 : 128); // stiffness scale 0.5 | 2
            p[1] = 50;                                          // μs 0.5
            p[2] = static_cast<std::uint8_t>(y < 3 ? 10 : 40);  // μd 0.1 | 0.4
        }
    auto colorSrc = makeStillFrameSource(Image::make(16, 12, PixelFormat::Rgb24), 25.0, "c");
    auto depthSrc = makeStillFrameSource(Image::make(16, 12, PixelFormat::Gray8), 25.0, "d");
    auto materialSrc = makeStillFrameSource(codes, 25.0, "m");
    EncodeOptions o;
    o.output = out;
    o.preset = "ultrafast";
    o.maxFrames = 2;
    ASSERT_TRUE(encodeStreams(*colorSrc, *depthSrc, materialSrc.get(), o));
    auto info = probeMaterialStream(out);
    std::filesystem::remove(out);
    ASSERT_TRUE(info);
    ASSERT_TRUE(info->has_value());
    const MaterialStreamInfo &m = **info;
    EXPECT_EQ(m.index, 2);
    EXPECT_EQ(m.titleFrom, "MP4 handler name");
    EXPECT_EQ(m.pixelFormat, "gbrp");
    ASSERT_TRUE(m.lossless.has_value());
    EXPECT_TRUE(*m.lossless);
    ASSERT_TRUE(m.decoded);
    EXPECT_DOUBLE_EQ(m.minValue[0], 0.5);
    EXPECT_DOUBLE_EQ(m.maxValue[0], 2.0);
    EXPECT_DOUBLE_EQ(m.minValue[1], 0.5);
    EXPECT_DOUBLE_EQ(m.maxValue[1], 0.5);
    EXPECT_DOUBLE_EQ(m.minValue[2], 0.1);
    EXPECT_DOUBLE_EQ(m.maxValue[2], 0.4);
}

// `--material FILE` reads the file's material track, found as probe finds it; a file of several
// video streams without one is refused instead of giving its colour picture as materials (a
// DepthTouch file without materials read as stiffness 0.25-3.98 and static friction up to 2.5).
TEST(MaterialTrackTest, aMaterialInputIsTheMaterialTrackOrRefused)
{
    const std::string dir = ::testing::TempDir() + "mat-src-" + std::to_string(::getpid());
    std::filesystem::create_directories(dir);
    Image color = Image::make(16, 12, PixelFormat::Rgb24);
    for (auto &b : color.data)
        b = 200; // a colour picture that would read as stiffness scale 3.1
    Image codes = Image::make(16, 12, PixelFormat::Rgb24);
    for (std::size_t i = 0; i < codes.data.size(); i += 3) {
        codes.data[i] = 32;     // stiffness scale 0.5
        codes.data[i + 1] = 50; // μs 0.5
        codes.data[i + 2] = 10; // μd 0.1
    }
    const auto encodeTo = [&](const std::string &name, bool withMaterial) {
        auto c = makeStillFrameSource(color, 25.0, "c");
        auto d = makeStillFrameSource(Image::make(16, 12, PixelFormat::Gray8), 25.0, "d");
        auto m = makeStillFrameSource(codes, 25.0, "m");
        EncodeOptions o;
        o.output = dir + "/" + name;
        o.preset = "ultrafast";
        o.maxFrames = 2;
        EXPECT_TRUE(encodeStreams(*c, *d, withMaterial ? m.get() : nullptr, o)) << name;
        return o.output;
    };
    SourceOptions so;
    so.streamTitle = "material";
    // GIVEN a DepthTouch file without a material track: refused, with the reason
    auto none = openFrameSource(encodeTo("plain.mkv", false), so);
    ASSERT_FALSE(none);
    EXPECT_EQ(none.error().code, Errc::InvalidArgument);
    EXPECT_NE(std::string(none.error().what).find("no material track"), std::string::npos);
    // AND files with one (title in Matroska, handler name in MP4, stream order in MPEG-TS): the
    // frames are the codes, not the colour
    for (const char *name : {"with.mkv", "with.mp4", "with.ts"}) {
        auto src = openFrameSource(encodeTo(name, true), so);
        ASSERT_TRUE(src) << name << ": " << src.error().what;
        auto f = (*src)->next(PixelFormat::Rgb24);
        ASSERT_TRUE(f) << name;
        EXPECT_EQ(f->image.data[0], 32) << name;
        EXPECT_EQ(f->image.data[1], 50) << name;
        EXPECT_EQ(f->image.data[2], 10) << name;
    }
    // AND a single video stream is a material video of its own
    ASSERT_TRUE(writePng(dir + "/codes.png", codes));
    EXPECT_TRUE(openFrameSource(dir + "/codes.png", so));
    std::filesystem::remove_all(dir);
}

} // namespace
} // namespace depthtouch::media
