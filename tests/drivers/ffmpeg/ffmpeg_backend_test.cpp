// FFmpeg backends without media files (label unit): selection, options, state errors.
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"

namespace depthtouch {
namespace {

TEST(FfmpegBackendTest, backendsAreInTheTablesAndRejectUnknownOptions)
{
    EXPECT_NE(drivers::mediaSourceBackends().find("ffmpeg"), nullptr);
    EXPECT_NE(drivers::videoDecoderBackends().find("ffmpeg"), nullptr);
    EXPECT_NE(drivers::videoDecoderBackends().find("v4l2m2m"), nullptr);
    hal::BackendConfig cfg;
    cfg.options = hal::OptionList("bogus=1");
    EXPECT_EQ(drivers::createMediaSource("ffmpeg", cfg).error().code, Errc::InvalidArgument);
    EXPECT_EQ(drivers::createVideoDecoder("ffmpeg", cfg).error().code, Errc::InvalidArgument);
    cfg.options = hal::OptionList("pool=0");
    EXPECT_EQ(drivers::createVideoDecoder("ffmpeg", cfg).error().code, Errc::InvalidArgument);
}

TEST(FfmpegBackendTest, drmPrimeOptionIsABooleanAndEnlargesThePool)
{
    // GIVEN the drm-prime option  THEN the pool covers a receiver's held colour frames (24) unless
    // pool is given, and a value that is not a boolean is refused
    hal::BackendConfig cfg;
    cfg.options = hal::OptionList("drm-prime");
    auto dec = drivers::createVideoDecoder("ffmpeg", cfg);
    ASSERT_TRUE(dec);
    EXPECT_EQ((*dec)->capabilities().poolFrames, 24);
    cfg.options = hal::OptionList("drm-prime=1,pool=6");
    dec = drivers::createVideoDecoder("ffmpeg", cfg);
    ASSERT_TRUE(dec);
    EXPECT_EQ((*dec)->capabilities().poolFrames, 6);
    cfg.options = hal::OptionList("drm-prime=0");
    dec = drivers::createVideoDecoder("ffmpeg", cfg);
    ASSERT_TRUE(dec);
    EXPECT_EQ((*dec)->capabilities().poolFrames, 4);
    cfg.options = hal::OptionList("drm-prime=maybe");
    EXPECT_EQ(drivers::createVideoDecoder("ffmpeg", cfg).error().code, Errc::InvalidArgument);
}

TEST(FfmpegBackendTest, missingFileIsNoDeviceAndTheSourceStaysClosed)
{
    hal::BackendConfig cfg;
    auto src = drivers::createMediaSource("ffmpeg", cfg);
    ASSERT_TRUE(src);
    auto r = (*src)->open("/nonexistent/dir/clip.mkv");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::NoDevice);
    EXPECT_EQ((*src)->state(), hal::MediaSource::State::Closed);
    EXPECT_EQ((*src)->readPacket().error().code, Errc::InvalidState);
    EXPECT_EQ((*src)->open("").error().code, Errc::InvalidArgument);
}

TEST(FfmpegBackendTest, v4l2m2mIsAbsentOrDecodesH264Only)
{
    hal::BackendConfig cfg;
    auto dec = drivers::createVideoDecoder("v4l2m2m", cfg);
    if (!dec) {
        EXPECT_EQ(dec.error().code, Errc::NoDevice);
        return;
    }
    EXPECT_TRUE((*dec)->capabilities().hardware);
    EXPECT_TRUE((*dec)->capabilities().supports(hal::CodecId::H264));
    EXPECT_FALSE((*dec)->capabilities().supports(hal::CodecId::Ffv1));
}

TEST(FfmpegBackendTest, decoderRefusesWhatItCannotDecode)
{
    hal::BackendConfig cfg;
    auto dec = drivers::createVideoDecoder("ffmpeg", cfg);
    ASSERT_TRUE(dec);
    const auto &caps = (*dec)->capabilities();
    EXPECT_TRUE(caps.supports(hal::CodecId::H264));
    EXPECT_TRUE(caps.supports(hal::CodecId::Ffv1));
    EXPECT_TRUE(caps.supports(hal::CodecId::RawVideo));
    EXPECT_FALSE(caps.supports(hal::CodecId::Mock));
    EXPECT_FALSE(caps.hardware);
    hal::StreamConfig sc;
    sc.codec = hal::CodecId::Mock;
    sc.width = 16;
    sc.height = 16;
    EXPECT_EQ((*dec)->configure(sc).error().code, Errc::NotSupported);
    sc.codec = hal::CodecId::RawVideo;
    sc.width = 100'000;
    EXPECT_EQ((*dec)->configure(sc).error().code, Errc::InvalidArgument);
    sc.width = 16;
    sc.format = hal::PixelFormat::Gray16;
    ASSERT_TRUE((*dec)->configure(sc));
    // A raw 16×16 gray16 image decodes to itself.
    std::vector<std::uint8_t> img(16u * 16u * 2u);
    for (std::size_t i = 0; i < img.size(); ++i)
        img[i] = static_cast<std::uint8_t>(i * 13u);
    hal::Packet p;
    p.data = img.data();
    p.size = img.size();
    p.pts = std::chrono::milliseconds(40);
    p.keyframe = true;
    ASSERT_TRUE((*dec)->queuePacket(p));
    auto f = (*dec)->dequeueFrame(platform::SteadyClock::instance().now());
    ASSERT_TRUE(f) << f.error().what;
    EXPECT_EQ((*f)->pts, std::chrono::milliseconds(40));
    EXPECT_EQ((*f)->image.format, hal::PixelFormat::Gray16);
    EXPECT_EQ(std::memcmp((*f)->image.row(0, 0), img.data(), img.size()), 0);
    EXPECT_EQ((*dec)->configure(sc).error().code, Errc::InvalidState); // Running
    ASSERT_TRUE((*dec)->flush());
    EXPECT_EQ((*dec)->configure(sc).error().code, Errc::Busy); // frame still held
    f->reset();
    EXPECT_TRUE((*dec)->configure(sc));
}

} // namespace
} // namespace depthtouch
