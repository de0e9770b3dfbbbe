// hal::VideoDecoderBase: a decoder backend that implements only the hooks gets the state machine
// of video_decoder.h from the base (configure, packets, end of stream, flush, close), and its hooks
// are not reached in a state that does not allow them.
#include "depthtouch/hal/video_decoder_base.h"

#include <cstdint>
#include <optional>

#include <gtest/gtest.h>

#include "support/expectations.h"

namespace depthtouch::hal {
namespace {

using depthtouch::testing::errcOf;
using State = VideoDecoder::State;

class HookOnlyDecoder final : public VideoDecoderBase {
public:
    HookOnlyDecoder()
    {
        caps_.codecs = codecBit(CodecId::H264);
        caps_.maxWidth = 1920;
        caps_.maxHeight = 1080;
    }

    std::optional<Errc> failConfigure; ///< configureDevice() fails with it.
    std::optional<Errc> failQueue;     ///< queuePacketDevice() fails with it.
    int configures = 0;
    int queued = 0;
    int dequeues = 0;
    int flushes = 0;
    int closes = 0;
    bool drainingSeen = false; ///< draining() at the last dequeueFrameDevice().

    [[nodiscard]] DecoderStats stats() const noexcept override { return {}; }

protected:
    Result<void> configureDevice(const StreamConfig &) override
    {
        ++configures;
        if (failConfigure)
            return unexpected(*failConfigure, "test failure");
        return ok();
    }
    Result<void> queuePacketDevice(const Packet &) override
    {
        if (failQueue)
            return unexpected(*failQueue, "test failure");
        ++queued;
        return ok();
    }
    Result<FrameRef> dequeueFrameDevice(Deadline) override
    {
        ++dequeues;
        drainingSeen = draining();
        return unexpected(Errc::Timeout, "no frame");
    }
    void flushDevice() noexcept override { ++flushes; }
    void closeDevice() noexcept override { ++closes; }
};

StreamConfig h264(int width = 640, int height = 480)
{
    StreamConfig c;
    c.codec = CodecId::H264;
    c.width = width;
    c.height = height;
    return c;
}

Packet dataPacket()
{
    static const std::uint8_t bytes[4] = {0, 0, 1, 9};
    Packet p;
    p.data = bytes;
    p.size = sizeof bytes;
    return p;
}

TEST(VideoDecoderBaseTest, aCodecOrSizeTheCapabilitiesLackIsRefusedBeforeTheDevice)
{
    // GIVEN a closed H.264 decoder up to 1920×1080
    HookOnlyDecoder d;
    StreamConfig hevc = h264();
    hevc.codec = CodecId::Hevc;
    // WHEN asked for HEVC, a 0-wide and a 1921-wide stream
    // THEN NotSupported, InvalidArgument, InvalidArgument, the device never asked, still Closed
    EXPECT_EQ(errcOf(d.configure(hevc)), Errc::NotSupported);
    EXPECT_EQ(errcOf(d.configure(h264(0, 480))), Errc::InvalidArgument);
    EXPECT_EQ(errcOf(d.configure(h264(1921, 1080))), Errc::InvalidArgument);
    EXPECT_EQ(d.configures, 0);
    EXPECT_EQ(d.state(), State::Closed);
    // AND the largest size is taken
    EXPECT_TRUE(d.configure(h264(1920, 1080)));
    EXPECT_EQ(d.state(), State::Configured);
}

TEST(VideoDecoderBaseTest, aFailedConfigureLeavesTheStateAsItWas)
{
    HookOnlyDecoder d;
    d.failConfigure = Errc::NoDevice;
    EXPECT_EQ(errcOf(d.configure(h264())), Errc::NoDevice);
    EXPECT_EQ(d.state(), State::Closed);
    d.failConfigure.reset();
    ASSERT_TRUE(d.configure(h264()));
    d.failConfigure = Errc::OutOfResources;
    EXPECT_EQ(errcOf(d.configure(h264())), Errc::OutOfResources);
    EXPECT_EQ(d.state(), State::Configured);
}

TEST(VideoDecoderBaseTest, packetsNeedAConfiguredDecoderAndMoveItToRunning)
{
    HookOnlyDecoder d;
    // GIVEN a closed decoder: no packet, no frame, no flush
    EXPECT_EQ(errcOf(d.queuePacket(dataPacket())), Errc::InvalidState);
    EXPECT_EQ(errcOf(d.dequeueFrame(Deadline{})), Errc::InvalidState);
    EXPECT_EQ(errcOf(d.flush()), Errc::InvalidState);
    EXPECT_EQ(d.queued + d.dequeues + d.flushes, 0);
    // WHEN configured: still no frame until a packet is queued
    ASSERT_TRUE(d.configure(h264()));
    EXPECT_EQ(errcOf(d.dequeueFrame(Deadline{})), Errc::InvalidState);
    // AND a packet the device refuses leaves it Configured
    d.failQueue = Errc::Busy;
    EXPECT_EQ(errcOf(d.queuePacket(dataPacket())), Errc::Busy);
    EXPECT_EQ(d.state(), State::Configured);
    // AND an accepted one makes it Running, where frames are asked of the device
    d.failQueue.reset();
    ASSERT_TRUE(d.queuePacket(dataPacket()));
    EXPECT_EQ(d.state(), State::Running);
    EXPECT_EQ(errcOf(d.dequeueFrame(Deadline{})), Errc::Timeout);
    EXPECT_EQ(d.dequeues, 1);
    // AND configure() is refused while Running
    EXPECT_EQ(errcOf(d.configure(h264())), Errc::InvalidState);
    EXPECT_EQ(d.configures, 1);
}

TEST(VideoDecoderBaseTest, theEndOfStreamIsAFlagUntilFlushAndNoPacketFollowsIt)
{
    // GIVEN a configured decoder given the end of the stream at once
    HookOnlyDecoder d;
    ASSERT_TRUE(d.configure(h264()));
    ASSERT_TRUE(d.queuePacket(Packet{}));
    // THEN it is Running and draining, and the device saw no packet
    EXPECT_EQ(d.state(), State::Running);
    EXPECT_EQ(d.queued, 0);
    (void)d.dequeueFrame(Deadline{});
    EXPECT_TRUE(d.drainingSeen);
    // AND neither a packet nor a second end of stream is taken before flush()
    EXPECT_EQ(errcOf(d.queuePacket(dataPacket())), Errc::InvalidState);
    EXPECT_EQ(errcOf(d.queuePacket(Packet{})), Errc::InvalidState);
    EXPECT_EQ(d.queued, 0);
    // WHEN flushed: Configured, no longer draining, packets taken again
    ASSERT_TRUE(d.flush());
    EXPECT_EQ(d.flushes, 1);
    EXPECT_EQ(d.state(), State::Configured);
    ASSERT_TRUE(d.queuePacket(dataPacket()));
    (void)d.dequeueFrame(Deadline{});
    EXPECT_FALSE(d.drainingSeen);
}

TEST(VideoDecoderBaseTest, flushWhenConfiguredAndCloseWhenClosedDoNotReachTheDevice)
{
    HookOnlyDecoder d;
    d.close();
    EXPECT_EQ(d.closes, 0);
    ASSERT_TRUE(d.configure(h264()));
    ASSERT_TRUE(d.flush());
    EXPECT_EQ(d.flushes, 0);
    ASSERT_TRUE(d.queuePacket(Packet{}));
    d.close();
    EXPECT_EQ(d.closes, 1);
    EXPECT_EQ(d.state(), State::Closed);
    // AND a reconfigured decoder is not draining any more
    ASSERT_TRUE(d.configure(h264()));
    EXPECT_TRUE(d.queuePacket(dataPacket()));
}

} // namespace
} // namespace depthtouch::hal
