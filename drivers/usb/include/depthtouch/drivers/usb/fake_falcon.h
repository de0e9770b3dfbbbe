#pragma once
/// \file
/// \brief FakeFalcon: a device-side emulator of a Novint Falcon behind the UsbTransport interface,
/// so the whole Falcon driver (FTDI setup, firmware upload, homing, packets, kinematics) runs
/// without the device: in tests, and with the backend option `emulate`.
///
/// It answers as the device does: the FTDI requests set its serial state; a DTR low-high pulse at
/// 9600 baud resets it into the firmware loader, which answers the hello and start handshakes and
/// echoes the firmware image; switching to the firmware's serial setup (latency 1 ms, 1456312 baud)
/// after a complete image starts the firmware. The firmware answers every 16-byte command packet
/// with a status packet holding encoder counts computed from a simulated grip position through
/// inverse kinematics, the buttons and the homing status. While not homed, the encoders read off by
/// kUnhomedOffset counts; the motors home after a number of packets in homing mode.
///
/// Faults: unplug (every call fails with NoDevice; replug powers it up again, firmware lost unless
/// FakeFalconSettings::firmwareAtPowerUp), silence (no answers: exchange() times out) and corrupt
/// answers.
///
/// Thread-safety: thread-bound, except unplug(), replug(), setSilent() and the observers of
/// present(), which are thread-safe. Real-time: exchange() does not allocate, lock or log.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "depthtouch/drivers/usb/falcon_protocol.h"
#include "depthtouch/drivers/usb/usb_transport.h"
#include "depthtouch/hal/types.h"

namespace depthtouch::drivers {

struct FakeFalconSettings {
    /// The firmware runs from power-up (no upload needed), as on a device another program set up.
    bool firmwareAtPowerUp = false;
    /// Firmware images of another size are refused (the firmware does not start); 0 accepts any
    /// size the protocol allows.
    std::size_t firmwareSize = 0;
    /// Command packets with the homing flag before the motors report homed; 0 = homed at start.
    int homingPackets = 3;
};

class FakeFalcon final : public UsbTransport {
public:
    /// Encoder offset while not homed, counts.
    static constexpr std::int16_t kUnhomedOffset = 300;

    enum class Mode : std::uint8_t {
        Off,     ///< Powered, waiting for the loader reset (no firmware).
        Hello,   ///< Loader answered the hello.
        Loading, ///< Loader receiving the image.
        Running, ///< Firmware running.
    };

    explicit FakeFalcon(const FakeFalconSettings &settings = {});

    [[nodiscard]] Result<void> open(std::uint16_t vendorId, std::uint16_t productId) override;
    void close() noexcept override;
    [[nodiscard]] bool present() const noexcept override;
    [[nodiscard]] Result<void> control(FtdiRequest request, std::uint16_t value) override;
    [[nodiscard]] Result<std::size_t> write(const std::uint8_t *data, std::size_t size,
                                            platform::Duration timeout) override;
    [[nodiscard]] Result<std::size_t> read(std::uint8_t *data, std::size_t capacity,
                                           platform::Duration timeout) override;
    [[nodiscard]] Result<std::size_t> exchange(const std::uint8_t *out, std::size_t outSize,
                                               std::uint8_t *in, std::size_t inCapacity,
                                               platform::Duration timeout) noexcept override;

    /// \name The simulated hand
    ///@{
    /// Moves the grip to \a p (device frame, metres). \return false when out of reach (unchanged).
    bool setGripPosition(const hal::Vec3 &p) noexcept;
    [[nodiscard]] hal::Vec3 gripPosition() const noexcept { return grip_; }
    void setButtons(std::uint8_t buttons) noexcept { buttons_ = buttons & 0x0f; }
    ///@}

    /// \name Fault injection (unplug, replug and setSilent are thread-safe)
    ///@{
    void unplug() noexcept { plugged_.store(false, std::memory_order_release); }
    /// Plugs it back in: it powers up again (firmware lost unless firmwareAtPowerUp).
    void replug() noexcept;
    void setSilent(bool silent) noexcept { silent_.store(silent, std::memory_order_release); }
    /// Garbles the next \a count status packets.
    void corruptNext(int count) noexcept { corrupt_ = count; }
    ///@}

    /// \name Observers
    ///@{
    [[nodiscard]] Mode mode() const noexcept { return mode_; }
    [[nodiscard]] bool homed() const noexcept { return homed_; }
    /// The last well-formed command packet received.
    [[nodiscard]] const falcon::CommandPacket &lastCommand() const noexcept { return last_; }
    /// Command packets received (well-formed ones).
    [[nodiscard]] std::uint64_t commandCount() const noexcept { return commands_; }
    /// The force at the grip that the last motor commands output, newtons, device frame, computed
    /// with the emulator's own Jacobian: F = (∂theta/∂p)ᵀ·tau, ∂theta/∂p by central differences of
    /// the inverse kinematics at the grip position.
    [[nodiscard]] hal::Vec3 outputForce() const noexcept;
    /// Firmware bytes the loader received.
    [[nodiscard]] std::size_t firmwareBytes() const noexcept { return firmwareBytes_; }
    /// Times the firmware was started by an upload.
    [[nodiscard]] int uploads() const noexcept { return uploads_; }
    /// Every FTDI control request received since construction, in order.
    [[nodiscard]] const std::vector<std::pair<FtdiRequest, std::uint16_t>> &
    controls() const noexcept
    {
        return controls_;
    }
    [[nodiscard]] std::uint16_t baudDivisor() const noexcept { return baud_; }
    [[nodiscard]] std::uint16_t latencyMs() const noexcept { return latency_; }
    ///@}

private:
    void powerUp() noexcept;
    void queue(const std::uint8_t *data, std::size_t size) noexcept;
    void deviceReceives(const std::uint8_t *data, std::size_t size) noexcept;
    void answerCommand(const falcon::Packet &packet) noexcept;

    FakeFalconSettings settings_;
    std::atomic<bool> plugged_{true};
    std::atomic<bool> silent_{false};
    bool open_ = false;

    Mode mode_ = Mode::Off;
    bool dtr_ = false;
    std::uint16_t baud_ = 0;
    std::uint16_t latency_ = 16;
    std::size_t firmwareBytes_ = 0;
    int uploads_ = 0;
    std::vector<std::pair<FtdiRequest, std::uint16_t>> controls_;

    falcon::FrameAssembler commandFrames_;
    falcon::CommandPacket last_{};
    std::uint64_t commands_ = 0;
    int homingSeen_ = 0;
    bool homed_ = false;
    int corrupt_ = 0;

    hal::Vec3 grip_{};
    falcon::JointAngles gripAngles_{};
    std::uint8_t buttons_ = 0;

    // Bytes the device has sent and the host not read yet (fixed capacity; overflow is dropped as
    // an FTDI chip's buffer does).
    std::array<std::uint8_t, 1024> rx_{};
    std::size_t rxHead_ = 0;
    std::size_t rxSize_ = 0;
};

} // namespace depthtouch::drivers
