// The Falcon's 16-byte packets (drivers/usb/falcon_protocol.h): encode/decode round trips, framing
// errors, reassembly from a byte stream, and the FTDI status-byte stripping.
#include "depthtouch/drivers/usb/falcon_protocol.h"

#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/drivers/usb/usb_transport.h"

namespace depthtouch::drivers::falcon {
namespace {

TEST(FalconProtocolTest, commandRoundTripKeepsSignedValuesAndFlags)
{
    for (const MotorCommands m : {MotorCommands{0, 0, 0}, MotorCommands{1, -1, 4096},
                                  MotorCommands{-32768, 32767, -1234}}) {
        CommandPacket in;
        in.motors = m;
        in.flags = kFlagHoming | kLedRed | kLedBlue;
        Packet p{};
        encodeCommand(in, p);
        EXPECT_EQ(p[0], '<');
        EXPECT_EQ(p[15], '>');
        CommandPacket out;
        ASSERT_TRUE(decodeCommand(p, out));
        EXPECT_EQ(out.motors, m);
        EXPECT_EQ(out.flags, in.flags);
    }
}

TEST(FalconProtocolTest, commandLayoutIsNibblesLeastSignificantFirst)
{
    CommandPacket c;
    c.motors = {0x1234, 0, -1};
    c.flags = kLedGreen;
    Packet p{};
    encodeCommand(c, p);
    // 0x1234 → nibbles 4, 3, 2, 1 → 'E', 'D', 'C', 'B'; −1 → 'P' ×4; flags 0x04 → 'E'; byte 14 'A'.
    const Packet expected = {'<', 'E', 'D', 'C', 'B', 'A', 'A', 'A', 'A',
                             'P', 'P', 'P', 'P', 'E', 'A', '>'};
    EXPECT_EQ(p, expected);
}

TEST(FalconProtocolTest, statusRoundTripCarriesEncodersButtonsAndHoming)
{
    StatusPacket in;
    in.encoders = {-300, 0, 2500};
    in.buttons = 0x0b;
    in.homedMask = 0x05;
    Packet p{};
    encodeStatus(in, p);
    StatusPacket out;
    ASSERT_TRUE(decodeStatus(p, out));
    EXPECT_EQ(out.encoders, in.encoders);
    EXPECT_EQ(out.buttons, 0x0b);
    EXPECT_EQ(out.homedMask, 0x05);
    // Byte 13 is 'A' + (homed << 4 | buttons).
    EXPECT_EQ(p[13], 0x41 + 0x5b);
}

TEST(FalconProtocolTest, malformedFramesAreRejected)
{
    StatusPacket st;
    Packet good{};
    encodeStatus(st, good);
    Packet p = good;
    p[0] = 'x';
    EXPECT_FALSE(decodeStatus(p, st));
    p = good;
    p[15] = '<';
    EXPECT_FALSE(decodeStatus(p, st));
    p = good;
    p[7] = 0x40; // below 'A'
    EXPECT_FALSE(decodeStatus(p, st));
    p = good;
    p[3] = 0x51; // above 'P'
    EXPECT_FALSE(decodeStatus(p, st));
    CommandPacket c;
    p = good;
    p[13] = 0x41 + 0x10; // a command's byte 13 holds flags only
    EXPECT_FALSE(decodeCommand(p, c));
    EXPECT_TRUE(decodeStatus(p, st));
}

Packet statusWith(std::int16_t e0)
{
    StatusPacket st;
    st.encoders = {e0, 0, 0};
    Packet p{};
    encodeStatus(st, p);
    return p;
}

TEST(FalconProtocolTest, assemblerJoinsSplitFramesAndSkipsGarbage)
{
    FrameAssembler a;
    const Packet p = statusWith(42);
    // GIVEN garbage, then a frame split over three pushes
    const std::uint8_t junk[] = {0x00, 'Q', '>', 0x41};
    EXPECT_EQ(a.push(junk, sizeof junk), 0u);
    EXPECT_EQ(a.droppedBytes(), sizeof junk);
    EXPECT_EQ(a.push(p.data(), 5), 0u);
    EXPECT_EQ(a.push(p.data() + 5, 9), 0u);
    EXPECT_EQ(a.push(p.data() + 14, 2), 1u);
    Packet out{};
    ASSERT_TRUE(a.takeLatest(out));
    EXPECT_EQ(out, p);
    EXPECT_FALSE(a.takeLatest(out));
}

TEST(FalconProtocolTest, assemblerResyncsOnAStartByteInsideAFrame)
{
    FrameAssembler a;
    const Packet p = statusWith(7);
    std::vector<std::uint8_t> stream(p.begin(), p.begin() + 9); // truncated frame
    stream.insert(stream.end(), p.begin(), p.end());            // then a whole one
    EXPECT_EQ(a.push(stream.data(), stream.size()), 1u);
    EXPECT_EQ(a.droppedBytes(), 9u);
    Packet out{};
    ASSERT_TRUE(a.takeOldest(out));
    EXPECT_EQ(out, p);
}

TEST(FalconProtocolTest, assemblerKeepsTheNewestOfMergedFrames)
{
    FrameAssembler a;
    std::vector<std::uint8_t> stream;
    for (std::int16_t i = 1; i <= 6; ++i) {
        const Packet p = statusWith(i);
        stream.insert(stream.end(), p.begin(), p.end());
    }
    a.push(stream.data(), stream.size());
    Packet out{};
    ASSERT_TRUE(a.takeLatest(out));
    StatusPacket st;
    ASSERT_TRUE(decodeStatus(out, st));
    EXPECT_EQ(st.encoders[0], 6);
}

TEST(FalconProtocolTest, corruptedFrameIsDropped)
{
    FrameAssembler a;
    Packet p = statusWith(9);
    p[6] = 0x21;
    EXPECT_EQ(a.push(p.data(), p.size()), 0u);
    EXPECT_GT(a.droppedBytes(), 0u);
}

TEST(FtdiTest, statusBytesAreStrippedFromEveryUsbPacket)
{
    // GIVEN two 64-byte USB packets and a short one, each starting with two status bytes
    std::vector<std::uint8_t> raw;
    std::vector<std::uint8_t> payload;
    for (int packet = 0; packet < 3; ++packet) {
        raw.push_back(0x31);
        raw.push_back(0x60);
        const int n = packet < 2 ? 62 : 5;
        for (int i = 0; i < n; ++i) {
            const auto b = static_cast<std::uint8_t>(packet * 70 + i);
            raw.push_back(b);
            payload.push_back(b);
        }
    }
    const std::size_t n = stripFtdiStatus(raw.data(), raw.size());
    ASSERT_EQ(n, payload.size());
    EXPECT_TRUE(std::equal(payload.begin(), payload.end(), raw.begin()));
    std::uint8_t statusOnly[2] = {0x31, 0x60};
    EXPECT_EQ(stripFtdiStatus(statusOnly, 2), 0u);
}

} // namespace
} // namespace depthtouch::drivers::falcon
