// A stream whose pictures change size part-way (a spliced broadcast, another rendition of an HLS
// ladder): the ffmpeg decoder goes on giving frames at the size the stream was configured with,
// none lost, depth scaled nearest-neighbour (only codes that were coded) and color smoothly.
// Media made with the ffmpeg CLI at run time: two H.264 elementary streams, one after the other.

#include <algorithm>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ffmpeg_test_support.h"

namespace depthtouch {
namespace {

using namespace ffmpegtest;

/// Frames before the change: the stream is opened at the first part's size (libavformat reads
/// about the first second to learn a raw stream's parameters) and the change comes after it.
constexpr int kBefore = 90;
constexpr int kAfter = 6;

class SizeChangeTest : public FfmpegCliTest {
protected:
    SizeChangeTest() : FfmpegCliTest("dt-size-change-test-") {}
    /// \return the path of one H.264 Annex B file (lossless, \a pixFmt): kBefore frames of the
    /// colour \a before at \a beforeSize, then kAfter frames at \a afterSize (W x H) whose left
    /// half is the colour \a left and right half \a right; "" when the ffmpeg CLI fails.
    std::string spliced(const std::string &pixFmt, const std::string &before,
                        const std::string &beforeSize, const std::string &left,
                        const std::string &right, int afterWidth, int afterHeight)
    {
        const std::string encode = " -c:v libx264 -qp 0 -pix_fmt " + pixFmt + " -f h264 ";
        const std::string first = tmp_.path("before.h264");
        const std::string second = tmp_.path("after.h264");
        const std::string half =
            ":s=" + std::to_string(afterWidth / 2) + "x" + std::to_string(afterHeight) + ":r=30";
        if (!ffmpeg("-f lavfi -i color=c=" + before + ":s=" + beforeSize + ":r=30:d=3 -frames:v " +
                    std::to_string(kBefore) + encode + first) ||
            !ffmpeg("-f lavfi -i color=c=" + left + half + " -f lavfi -i color=c=" + right + half +
                    " -filter_complex hstack -frames:v " + std::to_string(kAfter) + encode +
                    second))
            return "";
        std::vector<std::uint8_t> bytes = readBytes(first);
        const std::vector<std::uint8_t> more = readBytes(second);
        bytes.insert(bytes.end(), more.begin(), more.end());
        const std::string path = tmp_.path("spliced.h264");
        FILE *f = std::fopen(path.c_str(), "wb");
        if (f == nullptr)
            return "";
        const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
        return std::fclose(f) == 0 && written && !more.empty() ? path : "";
    }
};

TEST_F(SizeChangeTest, depthThatHalvesItsSizeIsScaledBackNearestAndNoFrameIsLost)
{
    // GIVEN lossless 8-bit depth: 90 frames (3 s) at 128x96 of code 90, then 6 at 64x48 whose left
    // half is code 40 and right half code 200 (a silhouette)
    const std::string file = spliced("gray", "0x5a5a5a", "128x96", "0x282828", "0xc8c8c8", 64, 48);
    ASSERT_FALSE(file.empty());
    // WHEN the two, one after the other, are decoded as the depth stream they open as
    const Decoded d = decodeAll(file, hal::StreamKind::Depth);
    // THEN every frame comes out at 128x96: the first 90 code 90, the last six 40 and 200 only,
    // split at the middle column (nearest-neighbour: no code between the two was invented)
    ASSERT_EQ(d.stream.width, 128);
    ASSERT_EQ(d.stream.height, 96);
    ASSERT_EQ(d.frames.size(), static_cast<std::size_t>(kBefore + kAfter));
    for (std::size_t i = 0; i < d.frames.size(); ++i) {
        const std::vector<std::uint8_t> &f = d.frames[i];
        ASSERT_EQ(f.size(), 128u * 96u) << "frame " << i;
        if (i < static_cast<std::size_t>(kBefore)) {
            EXPECT_EQ(std::count(f.begin(), f.end(), 90), 128 * 96) << "frame " << i;
            continue;
        }
        const std::set<std::uint8_t> codes(f.begin(), f.end());
        EXPECT_EQ(codes, (std::set<std::uint8_t>{40, 200})) << "frame " << i;
        for (int y = 0; y < 96; y += 19) {
            EXPECT_EQ(f[static_cast<std::size_t>(y * 128 + 63)], 40) << "frame " << i;
            EXPECT_EQ(f[static_cast<std::size_t>(y * 128 + 64)], 200) << "frame " << i;
        }
    }
    EXPECT_EQ(d.stats.framesDropped, 0u);
}

TEST_F(SizeChangeTest, colorThatDoublesItsSizeIsScaledBackSmoothly)
{
    // GIVEN 4:2:0 color: 90 frames at 64x48, then 6 at 128x96 whose left half is dark and right
    // half bright
    const std::string file = spliced("yuv420p", "gray", "64x48", "0x282828", "0xc8c8c8", 128, 96);
    ASSERT_FALSE(file.empty());
    // WHEN decoded as color
    const Decoded d = decodeAll(file, hal::StreamKind::Color);
    // THEN all 96 frames are 64x48 4:2:0, and the halved silhouette's luma passes through a
    // value between the two sides (bilinear), dark on the left, bright on the right
    ASSERT_EQ(d.stream.width, 64);
    ASSERT_EQ(d.frames.size(), static_cast<std::size_t>(kBefore + kAfter));
    const std::size_t lumaBytes = 64u * 48u;
    for (auto i = static_cast<std::size_t>(kBefore); i < d.frames.size(); ++i) {
        const std::vector<std::uint8_t> &f = d.frames[i];
        ASSERT_EQ(f.size(), lumaBytes * 3 / 2) << "frame " << i;
        const std::uint8_t *row = f.data() + 24 * 64;
        EXPECT_LT(row[4], 70) << "frame " << i;
        EXPECT_GT(row[60], 170) << "frame " << i;
        const std::set<std::uint8_t> luma(f.begin(), f.begin() + static_cast<long>(lumaBytes));
        EXPECT_GT(luma.size(), 2u) << "frame " << i << ": no value between the two sides";
    }
}

} // namespace
} // namespace depthtouch
