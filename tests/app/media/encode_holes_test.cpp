/// \file
/// \brief The sender keeps the holes of metric depth (docs/architecture.md §3 "Holes"): invalid
/// samples coded 0 under the `depth_occupancy` threshold, measured ones at their occupied code,
/// through lossless and lossy coding, resampling, enhancement and a frame without any valid sample;
/// `fillHoles` fills them as before and writes no threshold. Read back with libavformat.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "depthtouch/depth/conversion.h"
#include "depthtouch/depth/occupancy.h"
#include "depthtouch/media/encode_job.h"
#include "encode_sources.h"
#include "readback.h"

using namespace depthtouch;
using namespace depthtouch::media;

namespace {

using test::colorSource;
using test::EncodeTest;
using test::kH;
using test::kW;
using test::TestSource;

constexpr depth::DepthRange kPlanes{1.0, 2.0};

/// The known holes: a 12×10 block of 0 at the top left and a 13×17 block of saturated samples
/// (65535) at the bottom right, in a \a w × \a h frame.
bool inHole(int x, int y, int w = kW, int h = kH)
{
    return (x < 12 * w / kW && y < 10 * h / kH) || (x > 50 * w / kW && y > 30 * h / kH);
}

/// Metric depth of one plane at 1.5 m with inHole()'s holes.
Image holedPlane(int w = kW, int h = kH)
{
    Image img = Image::make(w, h, PixelFormat::Gray16);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            img.setSample16(x, y,
                            !inHole(x, y, w, h) ? 1500 : (x < w / 2 ? 0 : std::uint16_t{65535}));
    return img;
}

/// The code of the plane at 1.5 m in a stream of \a bits under \a occ.
int planeCode(int bits, const depth::Occupancy &occ)
{
    const double vmax = std::ldexp(1.0, bits) - 1.0;
    const double n = depth::metresToNearness(1.5, kPlanes, depth::DepthMapping::InverseZ, vmax);
    return static_cast<int>(std::lround(depth::occupiedLevel(n, vmax, occ)));
}

/// A decoded depth sample (Gray8 or Gray16 frames of readBack()).
int sampleOf(const Image &f, int x, int y)
{
    return f.format == PixelFormat::Gray8 ? f.row(y)[x] : f.sample16(x, y);
}

/// Asserts that every sample (x, y) of every kW×kH frame of \a frames is \a want(x, y) (an int).
template <class Want> void expectSamples(const std::vector<Image> &frames, Want want)
{
    for (const Image &f : frames)
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x)
                ASSERT_EQ(sampleOf(f, x, y), want(x, y)) << "sample (" << x << ", " << y << ")";
}

class EncodeHolesTest : public EncodeTest {
protected:
    /// Encodes 2 frames of \a depth with \a o (planes kPlanes) into out.mkv and reads it back.
    test::FileReadback encode(EncodeOptions o, TestSource &depth, EncodeSummary &summary)
    {
        TestSource color = colorSource(2);
        o.range = kPlanes;
        auto s = encodeStreams(color, depth, o);
        EXPECT_TRUE(s) << (s ? "" : s.error().what);
        if (s)
            summary = *s;
        auto rb = test::readBack(o.output);
        EXPECT_TRUE(rb.ok) << rb.error;
        EXPECT_EQ(rb.streams.size(), 2u);
        return rb;
    }

    /// \return fastOptions() into out.mkv with lossless depth: the encoding of most cases here.
    EncodeOptions losslessOptions()
    {
        EncodeOptions o = fastOptions(path("out.mkv"));
        o.depthLossless = true;
        return o;
    }

    /// Encodes 2 frames of holedPlane() with \a o as encode() does. \return the file read back.
    test::FileReadback encodeHoledPlanes(const EncodeOptions &o, EncodeSummary &summary)
    {
        TestSource depth([](int) { return holedPlane(); }, 2, 30.0, PixelFormat::Gray16);
        return encode(o, depth, summary);
    }

    /// encodeHoledPlanes() with losslessOptions() and the switch \a on (e.g.
    /// &EncodeOptions::enhance) set.
    test::FileReadback encodeHoledLosslessWith(bool EncodeOptions::*on, EncodeSummary &summary)
    {
        EncodeOptions o = losslessOptions();
        o.*on = true;
        return encodeHoledPlanes(o, summary);
    }
};

/// GIVEN metric depth with a known hole WHEN encoded losslessly (8-bit qp 0) THEN the stream and
/// the container carry depth_occupancy = occupancyFor(8, lossless).threshold, every hole sample
/// decodes to 0 (below it) and every measured one to the plane's occupied code (at or above it).
TEST_F(EncodeHolesTest, losslessHolesDecodeBelowTheThresholdAndSurfacesAbove)
{
    EncodeOptions o = losslessOptions();
    EncodeSummary s;
    const auto rb = encodeHoledPlanes(o, s);
    ASSERT_EQ(rb.streams.size(), 2u);
    const depth::Occupancy occ = depth::occupancyFor(8, true);
    EXPECT_EQ(rb.streams[1].tags.at("depth_occupancy"), std::to_string(occ.threshold));
    EXPECT_EQ(rb.tags.at("depth_occupancy"), std::to_string(occ.threshold));
    EXPECT_EQ(s.depthOccupancy, occ.threshold);
    EXPECT_EQ(s.holeSamples, 2LL * (12 * 10 + 13 * 17));
    EXPECT_EQ(s.depthSamples, 2LL * kW * kH);
    EXPECT_EQ(s.filledSamples, 0);
    const int want = planeCode(8, occ);
    ASSERT_GE(want, static_cast<int>(occ.first));
    expectSamples(rb.streams[1].frames, [want](int x, int y) { return inHole(x, y) ? 0 : want; });
}

/// GIVEN the same depth WHEN encoded at 8 and 10 bits lossy (x264 at the default --depth-crf)
/// THEN the threshold is occupancyFor(bits, false)'s and at most 1 % of the samples next to a
/// hole's border read on the wrong side of it (measured: 0 of 3072 at 8 and at 10 bits).
TEST_F(EncodeHolesTest, lossyHolesStayOnTheirSideOfTheGuardBand)
{
    for (const int bits : {8, 10}) {
        EncodeOptions o = fastOptions(path("lossy" + std::to_string(bits) + ".mkv"));
        o.depthCodec = bits == 8 ? VideoCodec::H264Gray : VideoCodec::H264Gray10;
        EncodeSummary s;
        const auto rb = encodeHoledPlanes(o, s);
        ASSERT_EQ(rb.streams.size(), 2u);
        const depth::Occupancy occ = depth::occupancyFor(bits, false);
        EXPECT_EQ(rb.streams[1].tags.at("depth_occupancy"), std::to_string(occ.threshold));
        int wrong = 0;
        for (const Image &f : rb.streams[1].frames)
            for (int y = 0; y < kH; ++y)
                for (int x = 0; x < kW; ++x)
                    wrong += (sampleOf(f, x, y) < static_cast<int>(occ.threshold)) != inHole(x, y);
        std::printf("%d-bit lossy: %d of %d samples on the wrong side of %u\n", bits, wrong,
                    2 * kW * kH, occ.threshold);
        EXPECT_LE(wrong, 2 * kW * kH / 100) << bits << " bits";
    }
}

/// GIVEN depth with holes at half the output size WHEN encoded THEN the holes are resampled by
/// nearest sample (an output sample is a hole exactly when its nearest source sample is) and no
/// hole value blends into the measured plane: every measured sample is the plane's code.
TEST_F(EncodeHolesTest, resamplingKeepsHolesApartFromMeasuredDepth)
{
    TestSource depthSrc([](int) { return holedPlane(kW / 2, kH / 2); }, 2, 30.0,
                        PixelFormat::Gray16);
    EncodeOptions o = losslessOptions();
    EncodeSummary s;
    const auto rb = encode(o, depthSrc, s);
    ASSERT_EQ(rb.streams.size(), 2u);
    EXPECT_TRUE(s.depthResampled);
    const int want = planeCode(8, depth::occupancyFor(8, true));
    expectSamples(rb.streams[1].frames,
                  [want](int x, int y) { return inHole(x / 2, y / 2, kW / 2, kH / 2) ? 0 : want; });
}

/// GIVEN depth with holes WHEN encoded with the enhancement THEN the holes stay holes (0) and no
/// measured sample falls below the threshold.
TEST_F(EncodeHolesTest, enhancementDoesNotTurnHolesIntoSurfaces)
{
    EncodeSummary s;
    const auto rb = encodeHoledLosslessWith(&EncodeOptions::enhance, s);
    ASSERT_EQ(rb.streams.size(), 2u);
    ASSERT_TRUE(s.enhance.has_value());
    const auto threshold = static_cast<int>(depth::occupancyFor(8, true).threshold);
    for (const Image &f : rb.streams[1].frames)
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x)
                ASSERT_EQ(sampleOf(f, x, y) < threshold, inHole(x, y))
                    << "sample (" << x << ", " << y << ")";
}

/// GIVEN a frame without any valid sample after a good one WHEN encoded THEN it is written all
/// holes (nothing was measured), not a copy of the frame before.
TEST_F(EncodeHolesTest, frameWithoutValidDepthIsAllHoles)
{
    TestSource depthSrc(
        [](int i) { return i == 0 ? holedPlane() : Image::make(kW, kH, PixelFormat::Gray16); }, 2,
        30.0, PixelFormat::Gray16);
    EncodeOptions o = losslessOptions();
    EncodeSummary s;
    const auto rb = encode(o, depthSrc, s);
    ASSERT_EQ(rb.streams.size(), 2u);
    ASSERT_EQ(rb.streams[1].frames.size(), 2u);
    EXPECT_EQ(s.repeatedFrames, 0);
    EXPECT_EQ(s.holeSamples, 12LL * 10 + 13 * 17 + kW * kH);
    expectSamples({rb.streams[1].frames[1]}, [](int, int) { return 0; });
}

/// GIVEN the same depth WHEN encoded with fillHoles THEN no depth_occupancy tag is written and
/// every hole carries the plane's nearness, never the far plane (0): no sample is a hole.
TEST_F(EncodeHolesTest, fillHolesFillsAndWritesNoThreshold)
{
    EncodeSummary s;
    const auto rb = encodeHoledLosslessWith(&EncodeOptions::fillHoles, s);
    ASSERT_EQ(rb.streams.size(), 2u);
    EXPECT_EQ(rb.streams[1].tags.count("depth_occupancy"), 0u);
    EXPECT_EQ(rb.tags.count("depth_occupancy"), 0u);
    EXPECT_EQ(s.depthOccupancy, 0u);
    EXPECT_EQ(s.holeSamples, 0);
    EXPECT_EQ(s.filledSamples, 2LL * (12 * 10 + 13 * 17));
    const auto want = static_cast<int>(
        std::lround(depth::metresToNearness(1.5, kPlanes, depth::DepthMapping::InverseZ, 255.0)));
    ASSERT_GT(want, 0);
    expectSamples(rb.streams[1].frames, [want](int, int) { return want; });
}

} // namespace
