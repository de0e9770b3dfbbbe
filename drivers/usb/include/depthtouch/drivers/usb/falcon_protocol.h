#pragma once
/// \file
/// \brief The Novint Falcon's wire protocol (the firmware distributed with Novint's SDK, as
/// documented by the libnifalcon project): FTDI setup, firmware upload and the 16-byte framed
/// packets of the servo loop.
///
/// Packet (both directions): byte 0 '<', bytes 1..14 each carry one nibble as 'A' + nibble
/// (0x41..0x50), byte 15 '>'. Bytes 1..12 hold three 16-bit values, four nibbles each, least
/// significant first: motor commands on the way out, encoder counts on the way in (signed). Byte 13
/// is 'A' + a 7-bit value: out, the flags (homing mode 0x01, LEDs red 0x02, green 0x04, blue 0x08);
/// in, the grip's buttons in bits 0..3 and the homing status of motors 0..2 in bits 4..6 (set =
/// homed). Byte 14 is 'A' (0).
///
/// Thread-safety: the codec functions and FrameAssembler are reentrant and real-time safe; the
/// setup sequences are for a non-real-time thread.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "depthtouch/drivers/usb/falcon_kinematics.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers {

class UsbTransport;

namespace falcon {

inline constexpr std::size_t kPacketSize = 16;
using Packet = std::array<std::uint8_t, kPacketSize>;

/// Flags of byte 13 of a command packet.
enum FalconFlag : std::uint8_t {
    kFlagHoming = 0x01,
    kLedRed = 0x02,
    kLedGreen = 0x04,
    kLedBlue = 0x08,
};

/// What the host sends every servo period.
struct CommandPacket {
    MotorCommands motors{};   ///< Signed motor commands (see falcon_kinematics.h).
    std::uint8_t flags = 0;   ///< FalconFlag bits.
};

/// What the device answers.
struct StatusPacket {
    EncoderCounts encoders{};   ///< Signed encoder counts of motors 0..2.
    std::uint8_t buttons = 0;   ///< Grip buttons, bits 0..3.
    std::uint8_t homedMask = 0; ///< Bit i set when motor i is homed.
};

/// Encodes \a cmd into \a out.
void encodeCommand(const CommandPacket &cmd, Packet &out) noexcept;
/// Encodes \a st into \a out (the device side; used by the emulator and tests).
void encodeStatus(const StatusPacket &st, Packet &out) noexcept;
/// Decodes a command packet. \return false when \a in is not a well-formed frame.
[[nodiscard]] bool decodeCommand(const Packet &in, CommandPacket &cmd) noexcept;
/// Decodes a status packet. \return false when \a in is not a well-formed frame.
[[nodiscard]] bool decodeStatus(const Packet &in, StatusPacket &st) noexcept;

/// \brief Reassembles 16-byte frames from a byte stream that may split, merge or garble them.
/// Fixed capacity; bytes that cannot start a frame are dropped and counted.
class FrameAssembler {
public:
    /// Appends \a size bytes. \return the number of complete, well-formed frames now available.
    std::size_t push(const std::uint8_t *data, std::size_t size) noexcept;
    /// Takes the newest complete frame, discarding older ones. \return false when there is none.
    [[nodiscard]] bool takeLatest(Packet &out) noexcept;
    /// Takes the oldest complete frame. \return false when there is none.
    [[nodiscard]] bool takeOldest(Packet &out) noexcept;
    /// Bytes dropped because they could not be part of a well-formed frame.
    [[nodiscard]] std::uint64_t droppedBytes() const noexcept { return dropped_; }
    /// Forgets partial and complete frames.
    void clear() noexcept
    {
        partialSize_ = 0;
        frameCount_ = 0;
    }

private:
    static constexpr std::size_t kFrames = 4; ///< Complete frames kept; older ones are dropped.

    Packet partial_{};
    std::size_t partialSize_ = 0;
    std::array<Packet, kFrames> frames_{};
    std::size_t firstFrame_ = 0;
    std::size_t frameCount_ = 0;
    std::uint64_t dropped_ = 0;
};

/// \name Firmware loader handshake (bootloader at 9600 then 140000 baud)
///@{
inline constexpr std::array<std::uint8_t, 3> kLoaderHello = {0x0a, 0x43, 0x0d};
inline constexpr std::array<std::uint8_t, 4> kLoaderHelloReply = {0x0a, 0x44, 0x2c, 0x0d};
inline constexpr std::array<std::uint8_t, 1> kLoaderStart = {0x41};
inline constexpr std::array<std::uint8_t, 2> kLoaderStartReply = {0x13, 0x41};
inline constexpr std::size_t kFirmwareChunk = 128; ///< Bytes per write; the loader echoes each.
/// Sizes a firmware image can have: the Falcon's firmware is a few kilobytes.
inline constexpr std::size_t kFirmwareMinBytes = 1024;
inline constexpr std::size_t kFirmwareMaxBytes = 64 * 1024;
///@}

/// \brief FTDI setup for the running firmware: latency timer 1 ms, 1456312 baud, 8N1, purge.
/// \return Errors of UsbTransport::control().
[[nodiscard]] Result<void> setNormalMode(UsbTransport &usb);

/// \brief Uploads \a image to the Falcon's bootloader: purge, latency 16 ms, 9600 baud 8N1 without
/// flow control, serial mode, RTS low, a DTR low-high pulse, the hello handshake, DTR low, 140000
/// baud, the start handshake, then the image in kFirmwareChunk-byte writes each echoed back and
/// checked; then setNormalMode(). Not real-time safe (takes about a second on a device).
/// \return Errors: InvalidArgument (image size outside [kFirmwareMinBytes, kFirmwareMaxBytes]),
/// Io (a handshake or an echo did not match), NoDevice, Timeout.
[[nodiscard]] Result<void> uploadFirmware(UsbTransport &usb, std::span<const std::uint8_t> image);

} // namespace falcon
} // namespace depthtouch::drivers
