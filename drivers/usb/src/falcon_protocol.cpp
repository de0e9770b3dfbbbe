#include "depthtouch/drivers/usb/falcon_protocol.h"

#include <algorithm>
#include <chrono>

#include "depthtouch/drivers/usb/usb_transport.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Falcon)

namespace depthtouch::drivers::falcon {

namespace {

constexpr std::uint8_t kFrameStart = '<';
constexpr std::uint8_t kFrameEnd = '>';
constexpr std::uint8_t kNibbleBase = 0x41;

bool isNibbleByte(std::uint8_t b) noexcept
{
    return b >= kNibbleBase && b < kNibbleBase + 16;
}

std::uint8_t nibble(std::uint8_t b) noexcept
{
    return static_cast<std::uint8_t>((b - kNibbleBase) & 0x0f);
}

/// Byte 13 carries a 7-bit value: one nibble of flags on the way out, the buttons and the homing
/// status on the way in; every other payload byte carries one nibble.
constexpr std::uint8_t kByte13Max = 0x7f;

bool fitsAt(std::size_t pos, std::uint8_t b) noexcept
{
    if (pos == 0)
        return b == kFrameStart;
    if (pos == kPacketSize - 1)
        return b == kFrameEnd;
    if (pos == 13)
        return b >= kNibbleBase && b <= kNibbleBase + kByte13Max;
    return isNibbleByte(b);
}

void encodeFrame(const std::array<std::uint16_t, 3> &values, std::uint8_t byte13,
                 Packet &out) noexcept
{
    out[0] = kFrameStart;
    for (std::size_t i = 0; i < 3; ++i)
        for (std::size_t n = 0; n < 4; ++n)
            out[1 + 4 * i + n] =
                static_cast<std::uint8_t>(kNibbleBase + ((values[i] >> (4 * n)) & 0x0f));
    out[13] = static_cast<std::uint8_t>(kNibbleBase + (byte13 & kByte13Max));
    out[14] = kNibbleBase;
    out[15] = kFrameEnd;
}

bool decodeFrame(const Packet &in, std::array<std::uint16_t, 3> &values,
                 std::uint8_t &byte13) noexcept
{
    for (std::size_t i = 0; i < kPacketSize; ++i)
        if (!fitsAt(i, in[i]))
            return false;
    for (std::size_t i = 0; i < 3; ++i) {
        std::uint16_t v = 0;
        for (std::size_t n = 0; n < 4; ++n)
            v = static_cast<std::uint16_t>(v | (nibble(in[1 + 4 * i + n]) << (4 * n)));
        values[i] = v;
    }
    byte13 = static_cast<std::uint8_t>(in[13] - kNibbleBase);
    return true;
}

} // namespace

void encodeCommand(const CommandPacket &cmd, Packet &out) noexcept
{
    encodeFrame({static_cast<std::uint16_t>(cmd.motors[0]),
                 static_cast<std::uint16_t>(cmd.motors[1]),
                 static_cast<std::uint16_t>(cmd.motors[2])},
                static_cast<std::uint8_t>(cmd.flags & 0x0f), out);
}

void encodeStatus(const StatusPacket &st, Packet &out) noexcept
{
    encodeFrame({static_cast<std::uint16_t>(st.encoders[0]),
                 static_cast<std::uint16_t>(st.encoders[1]),
                 static_cast<std::uint16_t>(st.encoders[2])},
                static_cast<std::uint8_t>((st.buttons & 0x0f) | ((st.homedMask & 0x07) << 4)),
                out);
}

bool decodeCommand(const Packet &in, CommandPacket &cmd) noexcept
{
    std::array<std::uint16_t, 3> v{};
    std::uint8_t b13 = 0;
    if (!decodeFrame(in, v, b13) || (b13 >> 4) != 0)
        return false;
    for (std::size_t i = 0; i < 3; ++i)
        cmd.motors[i] = static_cast<std::int16_t>(v[i]);
    cmd.flags = b13;
    return true;
}

bool decodeStatus(const Packet &in, StatusPacket &st) noexcept
{
    std::array<std::uint16_t, 3> v{};
    std::uint8_t b13 = 0;
    if (!decodeFrame(in, v, b13) || (b13 & 0x80) != 0)
        return false;
    for (std::size_t i = 0; i < 3; ++i)
        st.encoders[i] = static_cast<std::int16_t>(v[i]);
    st.buttons = static_cast<std::uint8_t>(b13 & 0x0f);
    st.homedMask = static_cast<std::uint8_t>((b13 >> 4) & 0x07);
    return true;
}

std::size_t FrameAssembler::push(const std::uint8_t *data, std::size_t size) noexcept
{
    for (std::size_t k = 0; k < size; ++k) {
        const std::uint8_t b = data[k];
        const std::size_t pos = partialSize_;
        if (!fitsAt(pos, b)) {
            // A start byte in the middle begins a new frame; anything else drops the partial one.
            dropped_ += pos;
            partialSize_ = 0;
            if (b == kFrameStart)
                partial_[partialSize_++] = b;
            else
                ++dropped_;
            continue;
        }
        partial_[partialSize_++] = b;
        if (partialSize_ == kPacketSize) {
            partialSize_ = 0;
            if (frameCount_ == kFrames) { // full: drop the oldest
                firstFrame_ = (firstFrame_ + 1) % kFrames;
                --frameCount_;
                dropped_ += kPacketSize;
            }
            frames_[(firstFrame_ + frameCount_) % kFrames] = partial_;
            ++frameCount_;
        }
    }
    return frameCount_;
}

bool FrameAssembler::takeLatest(Packet &out) noexcept
{
    if (frameCount_ == 0)
        return false;
    out = frames_[(firstFrame_ + frameCount_ - 1) % kFrames];
    firstFrame_ = 0;
    frameCount_ = 0;
    return true;
}

bool FrameAssembler::takeOldest(Packet &out) noexcept
{
    if (frameCount_ == 0)
        return false;
    out = frames_[firstFrame_];
    firstFrame_ = (firstFrame_ + 1) % kFrames;
    --frameCount_;
    return true;
}

Result<void> setNormalMode(UsbTransport &usb)
{
    DT_TRY(usb.control(FtdiRequest::LatencyTimer, 1));
    DT_TRY(usb.control(FtdiRequest::BaudRate, kFtdiBaud1456312));
    DT_TRY(usb.control(FtdiRequest::LineProperty, kFtdiLine8N1));
    DT_TRY(usb.control(FtdiRequest::Reset, kFtdiPurgeRx));
    DT_TRY(usb.control(FtdiRequest::Reset, kFtdiPurgeTx));
    return ok();
}

namespace {

constexpr platform::Duration kLoaderTimeout = std::chrono::milliseconds(1000);

/// Writes \a msg and checks that the loader answers \a reply.
template <std::size_t N, std::size_t M>
Result<void> handshake(UsbTransport &usb, const std::array<std::uint8_t, N> &msg,
                       const std::array<std::uint8_t, M> &reply, const char *step)
{
    auto w = usb.write(msg.data(), msg.size(), kLoaderTimeout);
    if (!w)
        return unexpected(w.error());
    std::array<std::uint8_t, M> got{};
    auto r = usb.read(got.data(), got.size(), kLoaderTimeout);
    if (!r)
        return unexpected(r.error());
    if (*r != M || got != reply) {
        DT_LOG(Falcon, Error, "Failed to start the Falcon's firmware loader: no answer to the %s",
               step);
        return unexpected(Errc::Io, "Falcon firmware loader did not answer its handshake");
    }
    return ok();
}

} // namespace

Result<void> uploadFirmware(UsbTransport &usb, std::span<const std::uint8_t> image)
{
    if (image.size() < kFirmwareMinBytes || image.size() > kFirmwareMaxBytes)
        return unexpected(Errc::InvalidArgument, "Falcon firmware image has an impossible size");
    DT_TRY(usb.control(FtdiRequest::Reset, kFtdiPurgeRx));
    DT_TRY(usb.control(FtdiRequest::Reset, kFtdiPurgeTx));
    // The loader's checks fail with a shorter latency timer.
    DT_TRY(usb.control(FtdiRequest::LatencyTimer, 16));
    DT_TRY(usb.control(FtdiRequest::BaudRate, kFtdiBaud9600));
    DT_TRY(usb.control(FtdiRequest::LineProperty, kFtdiLine8N1));
    DT_TRY(usb.control(FtdiRequest::FlowControl, 0));
    DT_TRY(usb.control(FtdiRequest::BitMode, kFtdiBitModeReset));
    DT_TRY(usb.control(FtdiRequest::ModemControl, kFtdiRtsLow));
    // A DTR low-high pulse resets the microcontroller into its loader.
    DT_TRY(usb.control(FtdiRequest::ModemControl, kFtdiDtrLow));
    DT_TRY(usb.control(FtdiRequest::ModemControl, kFtdiDtrHigh));
    DT_TRY(handshake(usb, kLoaderHello, kLoaderHelloReply, "hello"));
    DT_TRY(usb.control(FtdiRequest::ModemControl, kFtdiDtrLow));
    DT_TRY(usb.control(FtdiRequest::BaudRate, kFtdiBaud140000));
    DT_TRY(handshake(usb, kLoaderStart, kLoaderStartReply, "start request"));

    std::array<std::uint8_t, kFirmwareChunk> echo{};
    for (std::size_t at = 0; at < image.size(); at += kFirmwareChunk) {
        const std::size_t n = std::min(kFirmwareChunk, image.size() - at);
        auto w = usb.write(image.data() + at, n, kLoaderTimeout);
        if (!w)
            return unexpected(w.error());
        auto r = usb.read(echo.data(), n, kLoaderTimeout);
        if (!r)
            return unexpected(r.error());
        if (*w != n || *r != n ||
            !std::equal(echo.begin(), echo.begin() + static_cast<std::ptrdiff_t>(n),
                        image.begin() + static_cast<std::ptrdiff_t>(at))) {
            DT_LOG(Falcon, Error,
                   "Failed to upload the Falcon firmware: the loader echoed %zu of %zu bytes at "
                   "offset %zu differently",
                   *r, n, at);
            return unexpected(Errc::Io, "Falcon firmware upload: echo mismatch");
        }
    }
    return setNormalMode(usb);
}

} // namespace depthtouch::drivers::falcon

namespace depthtouch::drivers {

std::size_t stripFtdiStatus(std::uint8_t *data, std::size_t size,
                            std::size_t maxPacketSize) noexcept
{
    if (maxPacketSize <= 2)
        return 0;
    std::size_t out = 0;
    for (std::size_t at = 0; at < size; at += maxPacketSize) {
        const std::size_t n = std::min(maxPacketSize, size - at);
        if (n <= 2)
            break;
        for (std::size_t k = 2; k < n; ++k)
            data[out++] = data[at + k];
    }
    return out;
}

} // namespace depthtouch::drivers
