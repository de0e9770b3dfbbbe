/// \file
/// \brief Image I/O through FFmpeg: bit-exact PNG round trips, JPEG/PGM reading, damaged files.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>


#include "depthtouch/media/image_io.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"

using namespace depthtouch;
using namespace depthtouch::media;

namespace {

/// A scratch folder per test, removed at its end.
class ImageIoTest : public depthtouch::testing::TempDirTest {
protected:
    ImageIoTest() : TempDirTest("dt-media-test-") {}
};

std::vector<char> readBytes(const std::string &p)
{
    std::ifstream in(p, std::ios::binary);
    return std::vector<char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeBytes(const std::string &p, const std::vector<char> &bytes)
{
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// Deterministic incompressible-ish bytes (xorshift), so PNG data spans many bytes.
std::uint32_t nextRandom(std::uint32_t &s)
{
    s ^= s << 13;
    s ^= s >> 17;
    s ^= s << 5;
    return s;
}

Image noiseImage(int w, int h, PixelFormat f, std::uint32_t seed)
{
    Image img = Image::make(w, h, f);
    for (auto &b : img.data)
        b = static_cast<std::uint8_t>(nextRandom(seed) >> 24);
    return img;
}

} // namespace

TEST_F(ImageIoTest, gray8PngRoundTripIsBitExact)
{
    // GIVEN every 8-bit value in an odd-sized image
    Image img = Image::make(37, 23, PixelFormat::Gray8);
    for (std::size_t i = 0; i < img.data.size(); ++i)
        img.data[i] = static_cast<std::uint8_t>(i * 7);
    // WHEN written and read back in the file's own layout
    ASSERT_TRUE(writePng(path("g8.png"), img));
    const auto back = readImage(path("g8.png"));
    ASSERT_TRUE(back);
    // THEN it is the same picture
    EXPECT_EQ(back->format, PixelFormat::Gray8);
    EXPECT_EQ(back->width, 37);
    EXPECT_EQ(back->height, 23);
    EXPECT_EQ(back->data, img.data);
}

TEST_F(ImageIoTest, gray16PngRoundTripIsBitExactInNativeOrder)
{
    // GIVEN 16-bit samples whose two bytes differ (a byte-order slip would show)
    Image img = Image::make(64, 48, PixelFormat::Gray16);
    std::uint32_t seed = 12345;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x)
            img.setSample16(x, y, static_cast<std::uint16_t>(nextRandom(seed)));
    img.setSample16(0, 0, 0x00ff);
    img.setSample16(1, 0, 0xff00);
    img.setSample16(2, 0, 65535);
    img.setSample16(3, 0, 0);
    ASSERT_TRUE(writePng(path("g16.png"), img));
    const auto back = readImage(path("g16.png"));
    ASSERT_TRUE(back);
    EXPECT_EQ(back->format, PixelFormat::Gray16);
    EXPECT_EQ(back->data, img.data);
    EXPECT_EQ(back->sample16(1, 0), 0xff00);
    // Read as 8-bit: the high byte.
    const auto as8 = readImage(path("g16.png"), PixelFormat::Gray8);
    ASSERT_TRUE(as8);
    for (int x = 0; x < 4; ++x)
        EXPECT_NEAR(as8->row(0)[x], img.sample16(x, 0) >> 8, 1) << "x=" << x;
    // Plane conversion keeps the values.
    EXPECT_EQ(toPlane16(*back).at(1, 0), 0xff00);
    EXPECT_EQ(fromPlane(toPlane16(*back)).data, img.data);
}

TEST_F(ImageIoTest, rgbPngRoundTripIsBitExact)
{
    const Image img = noiseImage(31, 17, PixelFormat::Rgb24, 99);
    ASSERT_TRUE(writePng(path("rgb.png"), img));
    const auto back = readImage(path("rgb.png"), PixelFormat::Rgb24);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->format, PixelFormat::Rgb24);
    EXPECT_EQ(back->data, img.data);
}

TEST_F(ImageIoTest, missingFileIsAnIoError)
{
    const auto r = readImage(path("does-not-exist.png"));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::Io);
}

TEST_F(ImageIoTest, garbageFileIsRefused)
{
    std::vector<char> junk(4096);
    std::uint32_t seed = 7;
    for (char &c : junk)
        c = static_cast<char>(nextRandom(seed) >> 24);
    writeBytes(path("junk.png"), junk);
    EXPECT_FALSE(readImage(path("junk.png")));
    writeBytes(path("empty.png"), {});
    EXPECT_FALSE(readImage(path("empty.png")));
}

TEST_F(ImageIoTest, truncatedPngIsRefused)
{
    // GIVEN a valid noisy 16-bit PNG cut to 60 % of its size
    ASSERT_TRUE(writePng(path("full.png"), noiseImage(128, 96, PixelFormat::Gray16, 3)));
    std::vector<char> bytes = readBytes(path("full.png"));
    ASSERT_GT(bytes.size(), 10000u);
    bytes.resize(bytes.size() * 6 / 10);
    writeBytes(path("cut.png"), bytes);
    // THEN reading fails cleanly
    const auto r = readImage(path("cut.png"));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::InvalidArgument);
}

TEST_F(ImageIoTest, corruptPngDataIsRefused)
{
    // GIVEN a valid PNG with bytes flipped in the middle of its compressed data
    ASSERT_TRUE(writePng(path("ok.png"), noiseImage(128, 96, PixelFormat::Gray8, 5)));
    std::vector<char> bytes = readBytes(path("ok.png"));
    for (std::size_t i = bytes.size() / 2; i < bytes.size() / 2 + 64; ++i)
        bytes[i] = static_cast<char>(~bytes[i]);
    writeBytes(path("bad.png"), bytes);
    EXPECT_FALSE(readImage(path("bad.png")));
}

TEST_F(ImageIoTest, writeRefusesEmptyImagesAndUnwritablePaths)
{
    EXPECT_EQ(writePng(path("e.png"), Image{}).error().code, Errc::InvalidArgument);
    Image bad = Image::make(4, 4, PixelFormat::Rgb24);
    bad.data.resize(10);
    EXPECT_EQ(writePng(path("b.png"), bad).error().code, Errc::InvalidArgument);
    EXPECT_EQ(
        writePng(path("no-such-dir/x.png"), Image::make(4, 4, PixelFormat::Gray8)).error().code,
        Errc::Io);
}

TEST_F(ImageIoTest, readsRealJpegColorAndTruncatedJpegFails)
{
    DT_NEED_SHARED_DATA("rgbd-7scenes-redkitchen/frame-000000.color.jpg");
    const std::string jpg =
        depthtouch::testing::sharedDataPath("rgbd-7scenes-redkitchen/frame-000000.color.jpg");
    // WHEN the 7-Scenes colour frame is read
    const auto rgb = readImage(jpg);
    ASSERT_TRUE(rgb);
    // THEN it is 640×480 RGB with real content (not flat)
    EXPECT_EQ(rgb->format, PixelFormat::Rgb24);
    EXPECT_EQ(rgb->width, 640);
    EXPECT_EQ(rgb->height, 480);
    int lo = 255;
    int hi = 0;
    for (const std::uint8_t b : rgb->data) {
        lo = std::min<int>(lo, b);
        hi = std::max<int>(hi, b);
    }
    EXPECT_GT(hi - lo, 100);
    const auto gray = readImage(jpg, PixelFormat::Gray8);
    ASSERT_TRUE(gray);
    EXPECT_EQ(gray->data.size(), 640u * 480u);

    // AND the same JPEG cut in half is refused
    std::vector<char> bytes = readBytes(jpg);
    bytes.resize(bytes.size() / 2);
    writeBytes(path("cut.jpg"), bytes);
    EXPECT_FALSE(readImage(path("cut.jpg")));
}

TEST_F(ImageIoTest, readsReal16BitDepthPngAndBigEndianPgm)
{
    DT_NEED_SHARED_DATA("rgbd-7scenes-redkitchen/frame-000000.depth.png");
    const auto depth = readImage(
        depthtouch::testing::sharedDataPath("rgbd-7scenes-redkitchen/frame-000000.depth.png"));
    ASSERT_TRUE(depth);
    EXPECT_EQ(depth->format, PixelFormat::Gray16);
    EXPECT_EQ(depth->width, 640);
    // Kinect depth in mm: the median valid sample lies within 0.4..8 m.
    std::vector<std::uint16_t> valid;
    for (const std::uint16_t v : toPlane16(*depth).samples)
        if (v != 0 && v != 65535)
            valid.push_back(v);
    ASSERT_GT(valid.size(), 100000u);
    std::nth_element(valid.begin(), valid.begin() + static_cast<std::ptrdiff_t>(valid.size() / 2),
                     valid.end());
    EXPECT_GT(valid[valid.size() / 2], 400);
    EXPECT_LT(valid[valid.size() / 2], 8000);

    DT_NEED_SHARED_DATA("rgbd-open3d/other_formats/NYU_depth.pgm");
    const auto nyu =
        readImage(depthtouch::testing::sharedDataPath("rgbd-open3d/other_formats/NYU_depth.pgm"));
    ASSERT_TRUE(nyu);
    EXPECT_EQ(nyu->format, PixelFormat::Gray16);
    EXPECT_GT(nyu->width, 0);
}
