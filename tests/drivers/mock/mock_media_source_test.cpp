#include "depthtouch/drivers/mock/mock_media_source.h"

#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/drivers/mock/mock_pattern.h"
#include "support/expectations.h"

namespace depthtouch::drivers {
namespace {

using depthtouch::testing::errcOf;

MockMediaSettings small()
{
    MockMediaSettings s;
    s.width = 16;
    s.height = 8;
    s.fps = 10;
    s.frames = 6;
    s.gop = 3;
    return s;
}

TEST(MockMediaSourceTest, describesTheSyntheticFile)
{
    MockMediaSource src(small());
    ASSERT_TRUE(src.open("mock:"));
    const hal::MediaInfo &info = src.info();
    ASSERT_EQ(info.streams.size(), 2u);
    EXPECT_EQ(info.streams[0].kind, hal::StreamKind::Color);
    EXPECT_EQ(info.streams[0].format, hal::PixelFormat::Yuv420p);
    EXPECT_EQ(info.streams[1].kind, hal::StreamKind::Depth);
    EXPECT_EQ(info.streams[1].format, hal::PixelFormat::Gray8);
    EXPECT_EQ(info.streams[1].codec, hal::CodecId::Mock);
    EXPECT_EQ(info.streams[1].depth.mapping, "inverse");
    EXPECT_EQ(info.streams[1].depth.bits, 8);
    EXPECT_DOUBLE_EQ(info.streams[1].depth.nearMetres, 0.5);
    EXPECT_EQ(info.duration, std::chrono::milliseconds(600));
    EXPECT_TRUE(info.seekable);
}

TEST(MockMediaSourceTest, packetsInterleaveFrameByFrameAndCarryTheFrameIndex)
{
    MockMediaSource src(small());
    ASSERT_TRUE(src.open("mock:"));
    for (std::uint32_t frame = 0; frame < 6; ++frame) {
        for (int stream = 0; stream < 2; ++stream) {
            auto p = src.readPacket();
            ASSERT_TRUE(p);
            EXPECT_EQ(p->streamIndex, stream);
            EXPECT_EQ(p->pts, std::chrono::milliseconds(100 * frame));
            EXPECT_EQ(p->dts, p->pts);
            EXPECT_EQ(p->keyframe, frame % 3 == 0);
            MockPacketHeader h;
            ASSERT_EQ(parseMockPacket(p->data, p->size, h), MockPacketCheck::Ok);
            EXPECT_EQ(h.frameIndex, frame);
            EXPECT_EQ(h.kind, static_cast<std::uint8_t>(stream == 0 ? hal::StreamKind::Color
                                                                    : hal::StreamKind::Depth));
            EXPECT_EQ(h.width, 16);
        }
    }
    EXPECT_EQ(errcOf(src.readPacket()), Errc::EndOfStream);
    EXPECT_EQ(src.packetsRead(), 12u);
}

TEST(MockMediaSourceTest, urlQueryOverridesSettings)
{
    MockMediaSource src(small());
    ASSERT_TRUE(src.open("mock://clip?frames=2&color=0&depth_bits=16&width=4"));
    ASSERT_EQ(src.info().streams.size(), 1u);
    EXPECT_EQ(src.info().streams[0].kind, hal::StreamKind::Depth);
    EXPECT_EQ(src.info().streams[0].index, 0);
    EXPECT_EQ(src.info().streams[0].format, hal::PixelFormat::Gray16);
    EXPECT_EQ(src.info().streams[0].width, 4);
    EXPECT_EQ(src.settings().frames, 2);
    src.close();
    // Back to the constructor settings on the next open.
    ASSERT_TRUE(src.open("mock:"));
    EXPECT_EQ(src.info().streams.size(), 2u);
}

TEST(MockMediaSourceTest, refusesOtherSchemesAndBadOptions)
{
    MockMediaSource src(small());
    EXPECT_EQ(errcOf(src.open("file.mkv")), Errc::NotSupported);
    // No URL is a malformed request, for every backend alike (hal::MediaSourceBase).
    EXPECT_EQ(errcOf(src.open(nullptr)), Errc::InvalidArgument);
    EXPECT_EQ(errcOf(src.open("mock:?frames=0")), Errc::InvalidArgument);
    EXPECT_EQ(errcOf(src.open("mock:?framez=3")), Errc::InvalidArgument);
    EXPECT_EQ(errcOf(src.open("mock:?color=0&depth=0")), Errc::InvalidArgument);
    EXPECT_EQ(src.state(), hal::MediaSource::State::Closed);

    hal::BackendConfig cfg;
    cfg.options = hal::OptionList("width=abc");
    EXPECT_FALSE(MockMediaSource::create(cfg));
    cfg.options = hal::OptionList("width=8,frames=3");
    EXPECT_TRUE(MockMediaSource::create(cfg));
}

TEST(MockMediaSourceTest, seekGoesToThePreviousKeyframe)
{
    MockMediaSource src(small());
    ASSERT_TRUE(src.open("mock:"));
    ASSERT_TRUE(src.seek(std::chrono::milliseconds(450))); // frame 4 → keyframe 3
    auto p = src.readPacket();
    ASSERT_TRUE(p);
    EXPECT_EQ(p->pts, std::chrono::milliseconds(300));
    EXPECT_TRUE(p->keyframe);
    EXPECT_EQ(p->streamIndex, 0);
    ASSERT_TRUE(src.seek(std::chrono::seconds(100))); // past the end → last keyframe
    EXPECT_EQ(src.readPacket()->pts, std::chrono::milliseconds(300));
    ASSERT_TRUE(src.seek(std::chrono::seconds(-1)));
    EXPECT_EQ(src.readPacket()->pts, hal::Pts::zero());
}

TEST(MockMediaSourceTest, unseekableFileRefusesSeek)
{
    MockMediaSettings s = small();
    s.seekable = false;
    MockMediaSource src(s);
    ASSERT_TRUE(src.open("mock:"));
    EXPECT_EQ(errcOf(src.seek(hal::Pts::zero())), Errc::NotSupported);
}

TEST(MockMediaSourceTest, failNextOpenFailsOnce)
{
    MockMediaSource src(small());
    src.failNextOpen(Errc::NoDevice);
    EXPECT_EQ(errcOf(src.open("mock:")), Errc::NoDevice);
    EXPECT_EQ(src.state(), hal::MediaSource::State::Closed);
    EXPECT_TRUE(src.open("mock:"));
}

TEST(MockMediaSourceTest, corruptPacketDamagesOnlyThatPayload)
{
    MockMediaSource src(small());
    src.corruptPacket(3); // frame 1, depth
    ASSERT_TRUE(src.open("mock:"));
    for (int i = 0; i < 6; ++i) {
        auto p = src.readPacket();
        ASSERT_TRUE(p);
        MockPacketHeader h;
        EXPECT_EQ(parseMockPacket(p->data, p->size, h),
                  i == 3 ? MockPacketCheck::Damaged : MockPacketCheck::Ok)
            << "packet " << i;
    }
}

TEST(MockMediaSourceTest, truncatedFileFailsWithIoUntilSeekBack)
{
    MockMediaSource src(small());
    src.truncateAt(5);
    ASSERT_TRUE(src.open("mock:"));
    for (int i = 0; i < 5; ++i) {
        ASSERT_TRUE(src.readPacket());
    }
    EXPECT_EQ(errcOf(src.readPacket()), Errc::Io);
    EXPECT_EQ(errcOf(src.readPacket()), Errc::Io);
    EXPECT_EQ(src.state(), hal::MediaSource::State::Open);
    ASSERT_TRUE(src.seek(hal::Pts::zero()));
    EXPECT_TRUE(src.readPacket());
}

TEST(MockMediaSourceTest, twoSourcesProduceIdenticalBytes)
{
    MockMediaSource a(small());
    MockMediaSource b(small());
    ASSERT_TRUE(a.open("mock:"));
    ASSERT_TRUE(b.open("mock:"));
    for (;;) {
        auto pa = a.readPacket();
        auto pb = b.readPacket();
        ASSERT_EQ(pa.has_value(), pb.has_value());
        if (!pa)
            break;
        ASSERT_EQ(std::vector<std::uint8_t>(pa->data, pa->data + pa->size),
                  std::vector<std::uint8_t>(pb->data, pb->data + pb->size));
    }
}

} // namespace
} // namespace depthtouch::drivers
