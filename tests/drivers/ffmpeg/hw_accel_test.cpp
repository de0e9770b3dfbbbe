// Hardware decoding (the ffmpeg decoder's `hwaccel` option) and its software fallback: on any
// machine, with or without a hardware decoder, auto decodes every frame to the samples the
// software decoder gives, counts the ones a device made, and a device asked for by name either
// opens or fails configure() with NoDevice, as libavutil itself says it can or cannot be opened.
// And the copy of a hardware decoder's 10-bit frame (P010, samples in the high bits) to depth.

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

extern "C" {
#include <libavutil/frame.h>
#include <libavutil/hwcontext.h>
}

#include "ffmpeg_common.h"
#include "ffmpeg_test_support.h"

namespace depthtouch {
namespace {

using namespace ffmpegtest;

/// \return whether libavutil opens a device of \a type on this machine (the test's own check).
bool deviceOpens(AVHWDeviceType type)
{
    AVBufferRef *device = nullptr;
    if (av_hwdevice_ctx_create(&device, type, nullptr, nullptr, 0) < 0)
        return false;
    av_buffer_unref(&device);
    return true;
}

class HwAccelTest : public FfmpegCliTest {
protected:
    HwAccelTest() : FfmpegCliTest("dt-hwaccel-test-") {}
};

TEST_F(HwAccelTest, autoDecodesTheSamplesOfTheSoftwareDecoder)
{
    // GIVEN HEVC Main10 depth (luma only matters) and 8-bit H.264 color, 12 frames each
    const std::string hevc = tmp_.path("depth.mkv");
    ASSERT_TRUE(ffmpeg("-f lavfi -i testsrc2=size=96x64:rate=30:duration=0.4 -c:v libx265 "
                       "-x265-params log-level=error -pix_fmt yuv420p10le -metadata:s:v "
                       "title=depth " +
                       hevc));
    const std::string h264 = tmp_.path("color.mkv");
    ASSERT_TRUE(ffmpeg("-f lavfi -i testsrc2=size=96x64:rate=30:duration=0.4 -c:v libx264 "
                       "-pix_fmt yuv420p " +
                       h264));
    for (const auto &[url, kind] :
         {std::pair{hevc, hal::StreamKind::Depth}, std::pair{h264, hal::StreamKind::Color}}) {
        // WHEN each is decoded in software and with hwaccel=auto
        const Decoded soft = decodeAll(url, kind, "", nullptr, "hwaccel=none");
        const Decoded any = decodeAll(url, kind, "", nullptr, "hwaccel=auto");
        // THEN both give every frame, the same samples (HEVC and H.264 decoding is exact), and
        // only auto may count hardware frames
        ASSERT_EQ(soft.frames.size(), 12u) << url;
        ASSERT_EQ(any.frames.size(), soft.frames.size()) << url;
        for (std::size_t i = 0; i < soft.frames.size(); ++i)
            EXPECT_TRUE(any.frames[i] == soft.frames[i]) << url << " frame " << i;
        EXPECT_EQ(soft.stats.framesHardware, 0u);
        EXPECT_LE(any.stats.framesHardware, any.stats.framesDecoded);
    }
}

TEST_F(HwAccelTest, aDeviceAskedForByNameOpensOrFailsConfigure)
{
    const std::string hevc = tmp_.path("depth.mkv");
    ASSERT_TRUE(ffmpeg("-f lavfi -i testsrc2=size=96x64:rate=30:duration=0.1 -c:v libx265 "
                       "-x265-params log-level=error -pix_fmt yuv420p10le " +
                       hevc));
    auto src = drivers::createMediaSource("ffmpeg", hal::BackendConfig{});
    ASSERT_TRUE(src);
    ASSERT_TRUE((*src)->open(hevc.c_str()));
    const hal::StreamConfig sc = hal::StreamConfig::fromStream((*src)->info().streams[0]);
    for (const auto &[name, type] :
         {std::pair{"vaapi", AV_HWDEVICE_TYPE_VAAPI}, std::pair{"cuda", AV_HWDEVICE_TYPE_CUDA}}) {
        hal::BackendConfig cfg;
        const std::string options = std::string("hwaccel=") + name;
        cfg.options = hal::OptionList(options);
        auto dec = drivers::createVideoDecoder("ffmpeg", cfg);
        ASSERT_TRUE(dec) << name;
        auto configured = (*dec)->configure(sc);
        if (deviceOpens(type)) {
            EXPECT_TRUE(configured) << name << ": the device opens here";
        } else {
            ASSERT_FALSE(configured) << name << ": no such device here";
            EXPECT_EQ(configured.error().code, Errc::NoDevice) << name;
        }
    }
}

TEST(HwAccelOptionTest, hwaccelTakesFfmpegsNames)
{
    for (const char *ok :
         {"hwaccel=none", "hwaccel=auto", "hwaccel=vaapi", "hwaccel=cuda", "hwaccel=vdpau"}) {
        hal::BackendConfig cfg;
        cfg.options = hal::OptionList(ok);
        EXPECT_TRUE(drivers::createVideoDecoder("ffmpeg", cfg)) << ok;
    }
    hal::BackendConfig cfg;
    cfg.options = hal::OptionList("hwaccel=quicksync");
    auto bad = drivers::createVideoDecoder("ffmpeg", cfg);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().code, Errc::InvalidArgument);
    EXPECT_NE(std::string(bad.error().what).find("none, auto, vaapi, cuda or vdpau"),
              std::string::npos);
}

TEST(HwAccelCopyTest, p010LumaBecomesTheDepthSamples)
{
    // GIVEN a P010 frame (what VAAPI and NVDEC give for 10-bit 4:2:0) whose luma holds levels
    // 0..1023 in the high 10 bits
    av::FramePtr f(av_frame_alloc());
    ASSERT_TRUE(f);
    f->format = AV_PIX_FMT_P010LE;
    f->width = 8;
    f->height = 2;
    ASSERT_GE(av_frame_get_buffer(f.get(), 0), 0);
    std::vector<std::uint16_t> levels;
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 8; ++x) {
            const auto v = static_cast<std::uint16_t>((x * 146 + y * 511) % 1024);
            levels.push_back(v);
            const auto stored = static_cast<std::uint16_t>(v << 6);
            std::memcpy(f->data[0] + y * f->linesize[0] + 2 * x, &stored, 2);
        }
    std::vector<std::uint8_t> pixels(8 * 2 * 2);
    hal::ImageView dst;
    dst.width = 8;
    dst.height = 2;
    dst.format = hal::PixelFormat::Gray16;
    dst.planes[0].data = pixels.data();
    dst.planes[0].strideBytes = 16;
    av::SwsPtr sws;
    // WHEN it is copied as depth
    ASSERT_TRUE(drivers::ffmpeg::copyFrame(*f, dst, sws));
    // THEN each sample is its level widened to 16 bits as a 10-bit stream's is: (v << 6) | (v >> 4)
    for (std::size_t i = 0; i < levels.size(); ++i) {
        std::uint16_t got = 0;
        std::memcpy(&got, pixels.data() + 2 * i, 2);
        EXPECT_EQ(got, static_cast<std::uint16_t>((levels[i] << 6) | (levels[i] >> 4))) << i;
    }
}

} // namespace
} // namespace depthtouch
