// media::ImageConverter: the libswscale rules of readImage() on in-memory images (8 → 16 bit by
// 257, 16 → 8 bit the high byte, color → gray the luma, gray → RGB replicated), resizing, copies,
// and refusals of empty or inconsistent images.
#include <cstdint>

#include <gtest/gtest.h>

#include "depthtouch/media/image_convert.h"

namespace depthtouch::media {
namespace {

Image ramp8(int w, int h)
{
    Image img = Image::make(w, h, PixelFormat::Gray8);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            img.row(y)[x] = static_cast<std::uint8_t>((x * 255) / (w - 1));
    return img;
}

TEST(ImageConverterTest, sameLayoutAndSizeIsACopy)
{
    ImageConverter conv;
    Image src = ramp8(20, 6);
    src.stride = 24; // padded rows come out tightly packed
    src.data.assign(24 * 6, 0);
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 20; ++x)
            src.row(y)[x] = static_cast<std::uint8_t>(x + y);
    auto out = conv.convert(src, PixelFormat::Gray8);
    ASSERT_TRUE(out);
    EXPECT_EQ(out->stride, 20u);
    EXPECT_EQ(out->row(5)[19], 24);
}

TEST(ImageConverterTest, grayDepthsAndColorFollowTheReadImageRules)
{
    ImageConverter conv;
    const Image g8 = ramp8(32, 4);
    auto g16 = conv.convert(g8, PixelFormat::Gray16);
    ASSERT_TRUE(g16) << g16.error().what;
    EXPECT_EQ(g16->sample16(31, 0), 65535);
    EXPECT_EQ(g16->sample16(0, 0), 0);
    EXPECT_EQ(g16->sample16(16, 2), g8.row(2)[16] * 257);

    auto back = conv.convert(*g16, PixelFormat::Gray8);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->data, g8.data);

    auto rgb = conv.convert(g8, PixelFormat::Rgb24);
    ASSERT_TRUE(rgb);
    const std::uint8_t *px = rgb->row(1) + 3 * 16;
    EXPECT_EQ(px[0], g8.row(1)[16]);
    EXPECT_EQ(px[1], px[0]);
    EXPECT_EQ(px[2], px[0]);

    Image red = Image::make(8, 8, PixelFormat::Rgb24);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            red.row(y)[3 * x] = 255;
    auto luma = conv.convert(red, PixelFormat::Gray8);
    ASSERT_TRUE(luma);
    EXPECT_NEAR(luma->row(4)[4], 76, 2); // BT.601: 0.299 · 255
}

TEST(ImageConverterTest, otherSizesAreScaled)
{
    ImageConverter conv;
    const Image g8 = ramp8(64, 48);
    auto half = conv.convert(g8, PixelFormat::Gray8, 32, 24);
    ASSERT_TRUE(half);
    EXPECT_EQ(half->width, 32);
    EXPECT_EQ(half->height, 24);
    EXPECT_LT(half->row(10)[2], half->row(10)[29]); // the ramp survives
}

TEST(ImageConverterTest, aNewHeightAloneIsScaledNotCopied)
{
    // GIVEN a vertical ramp, 16 x 32 Gray8: row y holds 8 y
    ImageConverter conv;
    Image src = Image::make(16, 32, PixelFormat::Gray8);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 16; ++x)
            src.row(y)[x] = static_cast<std::uint8_t>(8 * y);
    // WHEN only the height changes (same format and width), to 8 rows
    auto out = conv.convert(src, PixelFormat::Gray8, 16, 8);
    ASSERT_TRUE(out) << out.error().what;
    ASSERT_EQ(out->height, 8);
    // THEN each output row samples the source 4 rows per row (row k near 8 (4k + 1.5)), not row k:
    // the last row reads the bottom of the ramp (about 244), where a copy of row 7 would read 56
    for (int k = 0; k < 8; ++k)
        EXPECT_NEAR(out->row(k)[8], 8.0 * (4 * k + 1.5), 12.0) << "row " << k;
}

TEST(ImageConverterTest, emptyOrInconsistentImagesAreRefused)
{
    ImageConverter conv;
    auto empty = conv.convert(Image{}, PixelFormat::Gray8);
    ASSERT_FALSE(empty);
    EXPECT_EQ(empty.error().code, Errc::InvalidArgument);
    Image shortData = ramp8(16, 16);
    shortData.data.resize(100);
    EXPECT_FALSE(conv.convert(shortData, PixelFormat::Rgb24));
    EXPECT_FALSE(conv.convert(ramp8(16, 16), PixelFormat::Gray8, -1, 4));
}

} // namespace
} // namespace depthtouch::media
