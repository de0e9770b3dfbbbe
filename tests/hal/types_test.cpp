#include "depthtouch/hal/types.h"

#include <cstring>
#include <set>
#include <string>

#include <gtest/gtest.h>
#if __has_include(<libdrm/drm_fourcc.h>)
#include <libdrm/drm_fourcc.h> // constants only: checks the HAL's copies
#endif

#include "depthtouch/hal/media_source.h"
#include "depthtouch/hal/video_decoder.h"

namespace depthtouch::hal {
namespace {

constexpr PixelFormat kAllFormats[] = {
    PixelFormat::Unknown, PixelFormat::Gray8, PixelFormat::Gray10, PixelFormat::Gray16,
    PixelFormat::Yuv420p, PixelFormat::Nv12,  PixelFormat::Rgb24,  PixelFormat::Rgba8,
    PixelFormat::Yuyv,    PixelFormat::Z16,   PixelFormat::Mjpeg};

TEST(PixelFormatTest, namesAreDistinct)
{
    std::set<std::string> names;
    for (PixelFormat f : kAllFormats)
        names.insert(pixelFormatName(f));
    EXPECT_EQ(names.size(), std::size(kAllFormats));
}

TEST(PixelFormatTest, planarLayoutsRoundChromaUp)
{
    // GIVEN an odd-sized image  WHEN laying out 4:2:0 formats  THEN chroma covers every luma pixel
    EXPECT_EQ(planeCount(PixelFormat::Yuv420p), 3);
    const PlaneLayout y = planeLayout(PixelFormat::Yuv420p, 5, 3, 0);
    const PlaneLayout u = planeLayout(PixelFormat::Yuv420p, 5, 3, 1);
    EXPECT_EQ(y.rowBytes, 5);
    EXPECT_EQ(y.rows, 3);
    EXPECT_EQ(u.rowBytes, 3);
    EXPECT_EQ(u.rows, 2);
    EXPECT_EQ(imageBytes(PixelFormat::Yuv420p, 5, 3), 15u + 2u * 6u);

    const PlaneLayout uv = planeLayout(PixelFormat::Nv12, 5, 3, 1);
    EXPECT_EQ(uv.rowBytes, 6);
    EXPECT_EQ(uv.rows, 2);
    EXPECT_EQ(planeLayout(PixelFormat::Nv12, 5, 3, 2).rowBytes, 0); // no third plane
}

TEST(PixelFormatTest, packedLayouts)
{
    EXPECT_EQ(planeLayout(PixelFormat::Z16, 4, 2, 0).rowBytes, 8);
    EXPECT_EQ(planeLayout(PixelFormat::Gray10, 4, 2, 0).rowBytes, 8);
    EXPECT_EQ(planeLayout(PixelFormat::Rgb24, 4, 2, 0).rowBytes, 12);
    EXPECT_EQ(planeLayout(PixelFormat::Rgba8, 4, 2, 0).rowBytes, 16);
    EXPECT_EQ(planeLayout(PixelFormat::Yuyv, 3, 2, 0).rowBytes, 8); // width rounded up to even
    EXPECT_EQ(bitsPerSample(PixelFormat::Gray10), 10);
    EXPECT_EQ(bitsPerSample(PixelFormat::Z16), 16);
}

TEST(PixelFormatTest, compressedUnknownAndEmptyHaveNoLayout)
{
    EXPECT_EQ(imageBytes(PixelFormat::Mjpeg, 64, 48), 0u);
    EXPECT_EQ(imageBytes(PixelFormat::Unknown, 64, 48), 0u);
    EXPECT_EQ(imageBytes(PixelFormat::Gray8, 0, 48), 0u);
    EXPECT_EQ(planeLayout(PixelFormat::Gray8, 4, 4, -1).rows, 0);
}

TEST(ImageViewTest, rowAddressesFollowStride)
{
    std::uint8_t pixels[4 * 10] = {};
    ImageView v;
    v.width = 3;
    v.height = 4;
    v.format = PixelFormat::Gray8;
    v.planes[0] = {pixels, 10};
    EXPECT_EQ(v.row(0, 2), pixels + 20);
    EXPECT_FALSE(v.empty());
    EXPECT_TRUE(ImageView{}.empty());
}

TEST(Vec3Test, arithmetic)
{
    const Vec3 a{1.0, 2.0, 3.0};
    const Vec3 b{0.5, -1.0, 2.0};
    EXPECT_EQ(a + b, (Vec3{1.5, 1.0, 5.0}));
    EXPECT_EQ(a - b, (Vec3{0.5, 3.0, 1.0}));
    EXPECT_EQ(2.0 * a, (Vec3{2.0, 4.0, 6.0}));
    EXPECT_DOUBLE_EQ(dot(a, b), 0.5 - 2.0 + 6.0);
    EXPECT_DOUBLE_EQ(norm(Vec3{3.0, 4.0, 12.0}), 13.0);
    EXPECT_TRUE(isFinite(a));
    EXPECT_FALSE(isFinite(Vec3{0.0, std::nan(""), 0.0}));
}

TEST(StreamConfigTest, fromStreamCopiesTheDecodeParameters)
{
    StreamInfo s;
    s.index = 1;
    s.kind = StreamKind::Depth;
    s.codec = CodecId::H264;
    s.format = PixelFormat::Gray8;
    s.width = 320;
    s.height = 240;
    s.frameRate = {30000, 1001};
    s.extradata = {1, 2, 3};
    const StreamConfig c = StreamConfig::fromStream(s);
    EXPECT_EQ(c.codec, CodecId::H264);
    EXPECT_EQ(c.kind, StreamKind::Depth);
    EXPECT_EQ(c.format, PixelFormat::Gray8);
    EXPECT_EQ(c.width, 320);
    EXPECT_EQ(c.height, 240);
    EXPECT_NEAR(c.frameRate.toDouble(), 29.97, 1e-3);
    EXPECT_EQ(c.extradata, s.extradata);
}

TEST(PacketTest, endOfStreamPacketIsRecognised)
{
    EXPECT_TRUE(Packet::endOfStream(2).isEndOfStream());
    EXPECT_EQ(Packet::endOfStream(2).streamIndex, 2);
    const std::uint8_t byte = 0;
    Packet p;
    p.data = &byte;
    p.size = 1;
    EXPECT_FALSE(p.isEndOfStream());
}

TEST(CapabilitiesTest, codecMask)
{
    VideoDecoderCapabilities caps;
    caps.codecs = codecBit(CodecId::H264) | codecBit(CodecId::Hevc);
    EXPECT_TRUE(caps.supports(CodecId::H264));
    EXPECT_TRUE(caps.supports(CodecId::Hevc));
    EXPECT_FALSE(caps.supports(CodecId::Mock));
    EXPECT_STREQ(codecName(CodecId::Ffv1), "ffv1");
    EXPECT_STREQ(streamKindName(StreamKind::Depth), "depth");
}

} // namespace
} // namespace depthtouch::hal

namespace depthtouch::hal {
namespace {

#if __has_include(<libdrm/drm_fourcc.h>)
static_assert(kDrmFormatNv12 == DRM_FORMAT_NV12);
static_assert(kDrmFormatYuv420 == DRM_FORMAT_YUV420);
static_assert(kDrmFormatModLinear == DRM_FORMAT_MOD_LINEAR);
static_assert(kDrmFormatModInvalid == DRM_FORMAT_MOD_INVALID);
#endif

TEST(DmaBufImageTest, aFrameHasNoDmaBufByDefault)
{
    // GIVEN a default frame  THEN it carries no dma-buf, and its planes hold no fd
    const Frame f{};
    EXPECT_TRUE(f.dmabuf.empty());
    EXPECT_EQ(f.dmabuf.fourcc, 0u);
    EXPECT_EQ(f.dmabuf.modifier, kDrmFormatModInvalid);
    for (const DmaBufPlane &p : f.dmabuf.planes)
        EXPECT_EQ(p.fd, -1);
}

TEST(DmaBufImageTest, fourccCodesAreLittleEndianCharacters)
{
    // GIVEN the DRM fourcc of "NV12"  THEN 'N' is the lowest byte (drm_fourcc.h fourcc_code)
    EXPECT_EQ(kDrmFormatNv12, 0x3231564eu);
    EXPECT_EQ(kDrmFormatYuv420, 0x32315559u);
    EXPECT_EQ(drmPlaneCount(kDrmFormatNv12), 2);
    EXPECT_EQ(drmPlaneCount(kDrmFormatYuv420), 3);
    EXPECT_EQ(drmPlaneCount(drmFourcc('X', 'R', '2', '4')), 0);
}

} // namespace
} // namespace depthtouch::hal
