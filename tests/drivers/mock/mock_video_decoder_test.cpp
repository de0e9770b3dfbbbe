#include "depthtouch/drivers/mock/mock_video_decoder.h"

#include <cmath>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/drivers/mock/mock_media_source.h"
#include "mock_test_util.h"

namespace depthtouch::drivers {
namespace {

using std::chrono::milliseconds;
using testing::errcOf;
using testing::TestPacket;

constexpr int kW = 32;
constexpr int kH = 24;

hal::StreamConfig colorConfig()
{
    hal::StreamConfig c;
    c.codec = hal::CodecId::Mock;
    c.kind = hal::StreamKind::Color;
    c.format = hal::PixelFormat::Yuv420p;
    c.width = kW;
    c.height = kH;
    c.frameRate = {25, 1};
    return c;
}

hal::StreamConfig depthConfig(hal::PixelFormat format = hal::PixelFormat::Gray8)
{
    hal::StreamConfig c = colorConfig();
    c.kind = hal::StreamKind::Depth;
    c.format = format;
    return c;
}

class MockVideoDecoderTest : public ::testing::Test {
protected:
    hal::Deadline soon() const { return clock_.now() + milliseconds(100); }

    platform::ManualClock clock_;
    MockVideoDecoder dec_{clock_};
};

TEST_F(MockVideoDecoderTest, colorFramesCarryTheFrameIndexAndGradient)
{
    ASSERT_TRUE(dec_.configure(colorConfig()));
    for (std::uint32_t i = 0; i < 3; ++i) {
        const TestPacket p(hal::StreamKind::Color, 7 + i, kW, kH);
        ASSERT_TRUE(dec_.queuePacket(p.packet));
        auto f = dec_.dequeueFrame(soon());
        ASSERT_TRUE(f);
        const hal::ImageView &img = (*f)->image;
        EXPECT_EQ(readMockFrameIndex(img), 7 + i);
        EXPECT_EQ(img.row(0, 5)[9], mockColorLuma(9, 5, 7 + i));
        EXPECT_EQ((*f)->pts, p.packet.pts);
        EXPECT_EQ((*f)->sequence, i);
        EXPECT_EQ((*f)->time, clock_.now());
    }
}

TEST_F(MockVideoDecoderTest, depthFramesAreTheMovingBump)
{
    ASSERT_TRUE(dec_.configure(depthConfig()));
    std::vector<std::pair<int, int>> peaks;
    for (std::uint32_t frame : {0u, 25u}) { // t = 0 s and t = 1 s (a quarter turn)
        const TestPacket p(hal::StreamKind::Depth, frame, kW, kH);
        ASSERT_TRUE(dec_.queuePacket(p.packet));
        auto f = dec_.dequeueFrame(soon());
        ASSERT_TRUE(f);
        const hal::ImageView &img = (*f)->image;
        const double t = frame / 25.0;
        int best = -1;
        std::pair<int, int> at;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const int v = img.row(0, y)[x];
                EXPECT_EQ(v, std::lround(mockDepthNearness(x, y, kW, kH, t) * 255.0));
                if (v > best) {
                    best = v;
                    at = {x, y};
                }
            }
        EXPECT_GE(best, 250); // the bump peak is near the maximum nearness
        peaks.push_back(at);
    }
    EXPECT_NE(peaks[0], peaks[1]);
}

TEST_F(MockVideoDecoderTest, sixteenBitDepthUsesTheFullRange)
{
    ASSERT_TRUE(dec_.configure(depthConfig(hal::PixelFormat::Gray16)));
    const TestPacket p(hal::StreamKind::Depth, 0, kW, kH);
    ASSERT_TRUE(dec_.queuePacket(p.packet));
    auto f = dec_.dequeueFrame(soon());
    ASSERT_TRUE(f);
    std::uint16_t v = 0;
    std::memcpy(&v, (*f)->image.row(0, 3) + 2 * 4, 2);
    EXPECT_EQ(v, std::lround(mockDepthNearness(4, 3, kW, kH, 0.0) * 65535.0));
}

TEST_F(MockVideoDecoderTest, failNextConfigureFailsOnceAndChangesNothing)
{
    dec_.failNextConfigure(Errc::NoDevice);
    EXPECT_EQ(errcOf(dec_.configure(colorConfig())), Errc::NoDevice);
    EXPECT_EQ(dec_.state(), hal::VideoDecoder::State::Closed);
    EXPECT_TRUE(dec_.configure(colorConfig()));
}

TEST_F(MockVideoDecoderTest, refusesFormatsItCannotOutput)
{
    hal::StreamConfig c = colorConfig();
    c.format = hal::PixelFormat::Nv12;
    EXPECT_EQ(errcOf(dec_.configure(c)), Errc::NotSupported);
    c = depthConfig(hal::PixelFormat::Rgb24);
    EXPECT_EQ(errcOf(dec_.configure(c)), Errc::NotSupported);
    c = colorConfig();
    c.width = 5000;
    EXPECT_EQ(errcOf(dec_.configure(c)), Errc::InvalidArgument);
}

TEST_F(MockVideoDecoderTest, failedPacketIsIoAtDequeueThenDecodingGoesOn)
{
    ASSERT_TRUE(dec_.configure(colorConfig()));
    dec_.failPacket(1);
    for (std::uint32_t i = 0; i < 3; ++i) {
        ASSERT_TRUE(dec_.queuePacket(TestPacket(hal::StreamKind::Color, i, kW, kH).packet));
    }
    auto f0 = dec_.dequeueFrame(soon());
    ASSERT_TRUE(f0);
    EXPECT_EQ(errcOf(dec_.dequeueFrame(soon())), Errc::Io);
    auto f2 = dec_.dequeueFrame(soon());
    ASSERT_TRUE(f2);
    EXPECT_EQ(readMockFrameIndex((*f2)->image), 2u);
    EXPECT_EQ(dec_.stats().framesDropped, 1u);
    EXPECT_EQ(dec_.stats().framesDecoded, 2u);
}

TEST_F(MockVideoDecoderTest, damagedPacketIsConcealed)
{
    ASSERT_TRUE(dec_.configure(colorConfig()));
    TestPacket p(hal::StreamKind::Color, 4, kW, kH);
    p.bytes.back() ^= 0xff;
    ASSERT_TRUE(dec_.queuePacket(p.packet));
    auto f = dec_.dequeueFrame(soon());
    ASSERT_TRUE(f);
    EXPECT_TRUE((*f)->corrupt);
    EXPECT_EQ((*f)->image.row(0, 3)[3], 128);
    EXPECT_EQ(dec_.stats().framesConcealed, 1u);
}

TEST_F(MockVideoDecoderTest, malformedPacketIsRefusedAndCountedAsDropped)
{
    ASSERT_TRUE(dec_.configure(colorConfig()));
    const std::uint8_t junk[40] = {1, 2, 3};
    hal::Packet p;
    p.data = junk;
    p.size = sizeof(junk);
    EXPECT_EQ(errcOf(dec_.queuePacket(p)), Errc::InvalidArgument);
    EXPECT_EQ(dec_.stats().framesDropped, 1u);
    EXPECT_EQ(dec_.stats().packetsQueued, 0u);
}

TEST_F(MockVideoDecoderTest, exhaustPoolMakesDequeueBusy)
{
    ASSERT_TRUE(dec_.configure(colorConfig()));
    ASSERT_TRUE(dec_.queuePacket(TestPacket(hal::StreamKind::Color, 0, kW, kH).packet));
    dec_.exhaustPool(true);
    EXPECT_EQ(errcOf(dec_.dequeueFrame(soon())), Errc::Busy);
    dec_.exhaustPool(false);
    EXPECT_TRUE(dec_.dequeueFrame(soon()));
}

TEST_F(MockVideoDecoderTest, frameRefsReturnFramesToThePool)
{
    ASSERT_TRUE(dec_.configure(colorConfig()));
    std::vector<hal::FrameRef> held;
    for (std::uint32_t i = 0; i < 5; ++i) {
        ASSERT_TRUE(dec_.queuePacket(TestPacket(hal::StreamKind::Color, i, kW, kH).packet));
    }
    for (int i = 0; i < 4; ++i)
        held.push_back(std::move(*dec_.dequeueFrame(soon())));
    EXPECT_EQ(dec_.framesLent(), 4);
    EXPECT_EQ(errcOf(dec_.dequeueFrame(soon())), Errc::Busy);
    held.pop_back();
    EXPECT_EQ(dec_.framesLent(), 3);
    EXPECT_TRUE(dec_.dequeueFrame(soon())); // dropped at once
    held.clear();
    EXPECT_EQ(dec_.framesLent(), 0);
}

TEST_F(MockVideoDecoderTest, flushDropsQueuedPackets)
{
    ASSERT_TRUE(dec_.configure(colorConfig()));
    for (std::uint32_t i = 0; i < 3; ++i) {
        ASSERT_TRUE(dec_.queuePacket(TestPacket(hal::StreamKind::Color, i, kW, kH).packet));
    }
    ASSERT_TRUE(dec_.flush());
    EXPECT_EQ(dec_.stats().framesDropped, 3u);
    EXPECT_EQ(errcOf(dec_.dequeueFrame(soon())), Errc::InvalidState);
}

TEST_F(MockVideoDecoderTest, waitingForAFrameSleepsOnTheClockUntilTheDeadline)
{
    ASSERT_TRUE(dec_.configure(colorConfig()));
    ASSERT_TRUE(dec_.queuePacket(TestPacket(hal::StreamKind::Color, 0, kW, kH).packet));
    ASSERT_TRUE(dec_.dequeueFrame(soon()));
    const platform::TimePoint deadline = clock_.now() + milliseconds(40);
    EXPECT_EQ(errcOf(dec_.dequeueFrame(deadline)), Errc::Timeout);
    EXPECT_EQ(clock_.now(), deadline);
}

TEST_F(MockVideoDecoderTest, optionsSizeThePoolAndQueue)
{
    const hal::BackendConfig cfg = testing::configWith(&clock_, "pool=2,queue=3");
    auto d = MockVideoDecoder::create(cfg);
    ASSERT_TRUE(d);
    EXPECT_EQ((*d)->capabilities().poolFrames, 2);
    EXPECT_EQ((*d)->capabilities().queuePackets, 3);
    testing::expectOptionsRefused(&MockVideoDecoder::create, cfg, {"pool=0", "pools=2"});
}

TEST(MockPipelineTest, sourceCorruptionIsConcealedByTheDecoder)
{
    // GIVEN a file whose packet 2 (frame 1, color) is damaged
    platform::ManualClock clock;
    MockMediaSettings s;
    s.width = kW;
    s.height = kH;
    s.frames = 3;
    s.depth = false;
    MockMediaSource src(s);
    src.corruptPacket(1);
    ASSERT_TRUE(src.open("mock:"));
    MockVideoDecoder dec(clock);
    ASSERT_TRUE(dec.configure(hal::StreamConfig::fromStream(src.info().streams[0])));
    // WHEN decoding the whole stream  THEN only frame 1 is concealed
    std::vector<bool> corrupt;
    while (auto p = src.readPacket()) {
        ASSERT_TRUE(dec.queuePacket(*p));
        auto f = dec.dequeueFrame(clock.now());
        ASSERT_TRUE(f);
        corrupt.push_back((*f)->corrupt);
    }
    EXPECT_EQ(corrupt, (std::vector<bool>{false, true, false}));
}

} // namespace
} // namespace depthtouch::drivers
