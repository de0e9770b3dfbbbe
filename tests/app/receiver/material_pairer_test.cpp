// The material track's pure rules: which stream is the material (identifyStreams) and which
// material frame goes with a depth frame (MaterialPairer); and the hole threshold of decoded depth
// frames (depthHoleBelow).
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/receiver/material_pairer.h"
#include "depthtouch/receiver/stream_roles.h"
#include "test_support.h"

namespace depthtouch::receivertest {
namespace {

using receiver::identifyStreams;
using std::chrono::milliseconds;
using Track = receiver::MaterialPairer<int>;
using Match = Track::Match;

hal::StreamInfo stream(int index, const std::string &title, hal::PixelFormat format,
                       const char *from = "title")
{
    hal::StreamInfo s;
    s.index = index;
    s.title = title;
    s.titleFrom = title.empty() ? "" : from;
    s.format = format;
    s.width = 64;
    s.height = 48;
    return s;
}

hal::MediaInfo mediaOf(std::vector<hal::StreamInfo> streams)
{
    hal::MediaInfo mi;
    mi.streams = std::move(streams);
    return mi;
}

/// Expects the streams \a r found: \a color, \a depth and \a material (indexes; -1: none).
void expectRoles(const receiver::StreamRoles &r, int color, int depth, int material)
{
    EXPECT_EQ(r.color, color);
    EXPECT_EQ(r.depth, depth);
    EXPECT_EQ(r.material, material);
}

TEST(MaterialRolesTest, titledMaterialIsFoundInAnyCase)
{
    // GIVEN color, depth and a stream titled "Material"
    const auto r = identifyStreams(mediaOf({stream(0, "color", hal::PixelFormat::Yuv420p),
                                            stream(1, "depth", hal::PixelFormat::Gray8),
                                            stream(2, "Material", hal::PixelFormat::Rgb24)}));
    // THEN it is the material track, by title
    expectRoles(r, 0, 1, 2);
    EXPECT_STREQ(r.materialReason, "title");
    EXPECT_FALSE(hasNoteWith(r, "ignored"));
}

TEST(MaterialRolesTest, mp4HandlerNameNamesTheMaterial)
{
    const auto r =
        identifyStreams(mediaOf({stream(0, "color", hal::PixelFormat::Yuv420p, "MP4 handler name"),
                                 stream(1, "material", hal::PixelFormat::Rgb24, "MP4 handler name"),
                                 stream(2, "depth", hal::PixelFormat::Gray8, "MP4 handler name")}));
    EXPECT_EQ(r.material, 1);
    EXPECT_STREQ(r.materialReason, "MP4 handler name");
    EXPECT_EQ(r.depth, 2);
}

TEST(MaterialRolesTest, untitledRgbStreamAfterColorAndDepthIsTheMaterialByStreamOrder)
{
    // GIVEN three untitled streams: yuv420p, gray, RGB 4:4:4
    const auto r = identifyStreams(
        mediaOf({stream(0, "", hal::PixelFormat::Yuv420p), stream(1, "", hal::PixelFormat::Gray8),
                 stream(2, "", hal::PixelFormat::Rgb24)}));
    expectRoles(r, 0, 1, 2);
    EXPECT_STREQ(r.materialReason, "stream order");
    EXPECT_TRUE(hasNoteWith(r, "material track by stream order"));

    // AND a third stream that is not RGB, or is titled otherwise, stays ignored
    const auto yuv = identifyStreams(
        mediaOf({stream(0, "", hal::PixelFormat::Yuv420p), stream(1, "", hal::PixelFormat::Gray8),
                 stream(2, "", hal::PixelFormat::Yuv420p)}));
    EXPECT_EQ(yuv.material, -1);
    EXPECT_TRUE(hasNoteWith(yuv, "ignored"));
    const auto named = identifyStreams(
        mediaOf({stream(0, "", hal::PixelFormat::Yuv420p), stream(1, "", hal::PixelFormat::Gray8),
                 stream(2, "right", hal::PixelFormat::Rgb24)}));
    EXPECT_EQ(named.material, -1);
    // AND only the first such stream is taken
    const auto twoRgb = identifyStreams(mediaOf(
        {stream(0, "color", hal::PixelFormat::Yuv420p), stream(1, "depth", hal::PixelFormat::Gray8),
         stream(2, "", hal::PixelFormat::Rgb24), stream(3, "", hal::PixelFormat::Rgb24)}));
    EXPECT_EQ(twoRgb.material, 2);
    EXPECT_TRUE(hasNoteWith(twoRgb, "stream 3 (untitled) ignored"));
}

TEST(MaterialRolesTest, materialIsNeverTakenAsColorOrDepth)
{
    // GIVEN only a depth stream (untitled, gray) and a material track, the material first
    const auto r = identifyStreams(mediaOf(
        {stream(0, "material", hal::PixelFormat::Rgb24), stream(1, "", hal::PixelFormat::Gray8)}));
    // THEN depth is found and there is no color (the material is not taken by stream order)
    expectRoles(r, -1, 1, 0);
    // AND with an untitled non-gray stream, that one is color, never the material
    const auto c = identifyStreams(mediaOf({stream(0, "material", hal::PixelFormat::Rgb24),
                                            stream(1, "", hal::PixelFormat::Yuv420p),
                                            stream(2, "", hal::PixelFormat::Yuv420p)}));
    expectRoles(c, 1, 2, 0);
    // AND a lone material track is neither color nor depth
    const auto lone = identifyStreams(mediaOf({stream(0, "material", hal::PixelFormat::Rgb24)}));
    expectRoles(lone, -1, -1, 0);
}

TEST(MaterialRolesTest, secondMaterialTrackIsIgnored)
{
    const auto r = identifyStreams(mediaOf({stream(0, "color", hal::PixelFormat::Yuv420p),
                                            stream(1, "material", hal::PixelFormat::Rgb24),
                                            stream(2, "material", hal::PixelFormat::Rgb24),
                                            stream(3, "", hal::PixelFormat::Gray8)}));
    EXPECT_EQ(r.material, 1);
    EXPECT_EQ(r.depth, 3);
    EXPECT_TRUE(hasNoteWith(r, "stream 2 (material) ignored"));
}

constexpr hal::Pts kTol = milliseconds(20);

Track makeTrack(int window = 4)
{
    return Track(window, kTol, milliseconds(40));
}

TEST(MaterialPairerTest, sameTimeWithinToleranceIsTheMatch)
{
    Track t = makeTrack();
    EXPECT_TRUE(t.push(milliseconds(0), 10));
    EXPECT_TRUE(t.push(milliseconds(41), 11)); // 1 ms off: within τ
    int got = -1;
    hal::Pts at = hal::kNoPts;
    EXPECT_TRUE(t.ready(milliseconds(40)));
    EXPECT_EQ(t.find(milliseconds(40), got, at), Match::Same);
    EXPECT_EQ(got, 11);
    EXPECT_EQ(at, milliseconds(41));
    // a depth frame at 80 ms is not settled until a frame at or after 60 ms arrives or the end
    EXPECT_FALSE(t.ready(milliseconds(80)));
    EXPECT_EQ(t.find(milliseconds(80), got, at), Match::Held);
    EXPECT_EQ(got, 11);
    t.endOfStream();
    EXPECT_TRUE(t.ready(milliseconds(80)));
}

TEST(MaterialPairerTest, stillHoldsAndNothingBeforeIsMissing)
{
    Track t = makeTrack();
    int got = -1;
    hal::Pts at = hal::kNoPts;
    EXPECT_FALSE(t.ready(milliseconds(0)));
    EXPECT_EQ(t.find(milliseconds(0), got, at), Match::Missing);
    EXPECT_EQ(got, -1);
    EXPECT_TRUE(t.push(milliseconds(40), 7));
    EXPECT_EQ(t.find(milliseconds(0), got, at), Match::Missing); // the only frame is later
    t.endOfStream();
    for (int i = 1; i < 100; ++i) {
        t.release(milliseconds(40 * i));
        EXPECT_EQ(t.find(milliseconds(40 * i), got, at), i == 1 ? Match::Same : Match::Held);
        EXPECT_EQ(got, 7);
    }
    EXPECT_EQ(t.size(), 1u);
}

TEST(MaterialPairerTest, releaseKeepsTheFrameThatStillHoldsAndBoundsTheQueue)
{
    Track t = makeTrack(2); // 5 frames at most
    for (int i = 0; i < 4; ++i)
        EXPECT_TRUE(t.push(milliseconds(40 * i), int{i}));
    t.release(milliseconds(120)); // frames 0..2 are of no use at 120 ms and later
    EXPECT_EQ(t.size(), 1u);
    int got = -1;
    hal::Pts at = hal::kNoPts;
    EXPECT_EQ(t.find(milliseconds(120), got, at), Match::Same);
    EXPECT_EQ(got, 3);
    // a gap: depth at 200 ms holds frame 3, which release() keeps
    t.release(milliseconds(200));
    EXPECT_EQ(t.find(milliseconds(200), got, at), Match::Held);
    EXPECT_EQ(got, 3);
    // a material running ahead drops its oldest frames, never grows
    for (int i = 4; i < 20; ++i)
        EXPECT_TRUE(t.push(milliseconds(40 * i), int{i}));
    EXPECT_EQ(t.size(), 5u);
    EXPECT_EQ(t.stats().dropped, 12u);
}

// The receiver's order for each paired frame i: find(t_i), find(t_i+1), release(t_i). With material
// frames 3 and 4 lost (a gap of two, the material running one frame ahead), depth frames 3 and 4
// hold frame 2's material, as frame i and as frame i+1; never none.
TEST(MaterialPairerTest, aGapOfTwoFramesHoldsTheLastMaterialThroughIt)
{
    Track t = makeTrack();
    auto has = [](int k) { return k != 3 && k != 4; };
    int pushed = 0;
    for (int i = 0; i < 9; ++i) {
        // what has arrived: the material frames up to the first one after t_i+1 − τ
        for (; pushed < 10 && !t.ready(milliseconds(40 * (i + 1))); ++pushed) {
            if (has(pushed)) {
                EXPECT_TRUE(t.push(milliseconds(40 * pushed), int{pushed}));
            }
        }
        const int expected = has(i) ? i : 2;
        const int expectedNext = has(i + 1) ? i + 1 : 2;
        int got = -1;
        int next = -1;
        hal::Pts at = hal::kNoPts;
        EXPECT_EQ(t.find(milliseconds(40 * i), got, at), has(i) ? Match::Same : Match::Held)
            << "depth frame " << i;
        EXPECT_EQ(got, expected) << "depth frame " << i;
        EXPECT_NE(t.find(milliseconds(40 * (i + 1)), next, at), Match::Missing)
            << "depth frame " << i + 1;
        EXPECT_EQ(next, expectedNext) << "depth frame " << i + 1;
        t.release(milliseconds(40 * i));
    }
}

TEST(MaterialPairerTest, duplicateBackwardAndMissingTimestamps)
{
    Track t = makeTrack();
    EXPECT_TRUE(t.push(milliseconds(40), 1));
    EXPECT_FALSE(t.push(milliseconds(40), 2));
    EXPECT_FALSE(t.push(milliseconds(0), 3));
    EXPECT_TRUE(t.push(hal::kNoPts, 4)); // previous + period
    int got = -1;
    hal::Pts at = hal::kNoPts;
    EXPECT_EQ(t.find(milliseconds(80), got, at), Match::Same);
    EXPECT_EQ(got, 4);
    EXPECT_EQ(t.stats().ptsDuplicates, 1u);
    EXPECT_EQ(t.stats().ptsNonMonotonic, 1u);
    EXPECT_EQ(t.stats().ptsMissing, 1u);
}

TEST(MaterialPairerTest, resetCarriesTheFrameAtOrBeforeTheTargetUntilNewerOnesCome)
{
    // GIVEN a still at 0 and frames around 1 s
    Track t = makeTrack();
    EXPECT_TRUE(t.push(milliseconds(0), 0));
    t.endOfStream();
    // WHEN seeking forward to 2 s
    t.reset(milliseconds(2000));
    EXPECT_FALSE(t.ended());
    int got = -1;
    hal::Pts at = hal::kNoPts;
    // THEN the still holds there
    EXPECT_EQ(t.find(milliseconds(2000), got, at), Match::Held);
    EXPECT_EQ(got, 0);
    // AND a frame read after the seek that is not after the carried one replaces it
    Track u = makeTrack();
    EXPECT_TRUE(u.push(milliseconds(960), 24));
    EXPECT_TRUE(u.push(milliseconds(1000), 25));
    EXPECT_TRUE(u.push(milliseconds(1040), 26));
    u.reset(milliseconds(1010)); // keeps 25 only
    EXPECT_EQ(u.size(), 1u);
    EXPECT_TRUE(u.push(milliseconds(800), 20)); // the demuxer restarts at a keyframe before
    EXPECT_EQ(u.size(), 1u);
    EXPECT_EQ(u.find(milliseconds(800), got, at), Match::Same);
    EXPECT_EQ(got, 20);
    // AND a seek before every frame keeps none
    u.reset(milliseconds(100));
    EXPECT_EQ(u.size(), 0u);
}

/// GIVEN a 10-bit depth stream with depth_occupancy t WHEN decoded as Gray16 (the decoders widen by
/// bit replication, (v << 6) | (v >> 4)) THEN the frames' threshold splits the widened samples
/// exactly as t splits their 10-bit sources, and is the smallest 16-bit value whose source is ≥ t.
TEST(DepthHolesTest, tenBitThresholdIsWidenedAsTheSamplesAre)
{
    hal::StreamInfo s = stream(1, "depth", hal::PixelFormat::Gray10);
    s.depth.bits = 10;
    for (const std::uint32_t t : {1u, 24u, 96u, 500u, 1023u}) {
        s.depth.occupancy = t;
        const std::uint32_t h = receiver::depthHoleBelow(s, hal::PixelFormat::Gray16);
        std::uint32_t smallest = 0;
        while ((smallest >> 6) < t)
            ++smallest;
        EXPECT_EQ(h, smallest) << t;
        for (std::uint32_t v = 0; v < 1024; ++v)
            ASSERT_EQ(((v << 6) | (v >> 4)) < h, v < t) << "threshold " << t << ", sample " << v;
    }
    // 8-bit depth keeps its threshold; a stream without depth_occupancy has no holes
    hal::StreamInfo s8 = stream(1, "depth", hal::PixelFormat::Gray8);
    s8.depth.occupancy = 24;
    EXPECT_EQ(receiver::depthHoleBelow(s8, hal::PixelFormat::Gray8), 24u);
    s8.depth.occupancy = 0;
    EXPECT_EQ(receiver::depthHoleBelow(s8, hal::PixelFormat::Gray8), 0u);
}

} // namespace
} // namespace depthtouch::receivertest
