#pragma once
/// \file
/// \brief FalconHapticDevice: hal::HapticDevice for the Novint Falcon over a UsbTransport (libusb,
/// or the FakeFalcon emulator). Backend name `falcon`.
///
/// open(): FTDI setup for the firmware; when the firmware does not answer, uploads the image given
/// by the option `firmware` (the user's file; never shipped); then homing: the homing flag is sent
/// and the red LED lit until the three motors report homed (the user moves the grip all the way
/// out and pushes it straight in), then the green LED. Until homed, every force output is zero.
///
/// read(): one packet exchange (the pending motor commands out, one status packet in) waiting at
/// most one servo period; encoder counts → arm angles → forward kinematics (Newton, warm-started
/// from the previous position) → position in the device frame, clamped to the capability box.
/// commandForce(): the force, clamped to maxForce (a non-finite one: zero) by
/// hal::HapticDeviceBase, which owns the state and presence checks too, is mapped to arm torques
/// through the Jacobian transpose at the last pose and to motor commands (falcon_kinematics.h),
/// sent on the next read(). The blue LED is lit while a non-zero force is output.
///
/// Options: `firmware=PATH` (firmware image to upload when the device needs one), `max_force=N`
/// (newtons, in (0, 8.5]; default 8.5), `emulate` (use the built-in FakeFalcon instead of USB:
/// firmware already running unless `firmware` is given), `homing_packets=N` (packets open() waits
/// for homing, default 200).
///
/// Real-time: read(), commandForce(), state() and isConnected() are noexcept and do not allocate,
/// lock or log; read() waits for at most one device transaction. Thread-safety: as
/// hal::HapticDevice; the observers are thread-bound (call them from the thread using the device).

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "depthtouch/drivers/usb/falcon_kinematics.h"
#include "depthtouch/drivers/usb/falcon_protocol.h"
#include "depthtouch/drivers/usb/usb_transport.h"
#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/haptic_device_base.h"

namespace depthtouch::drivers {

/// Largest force the Falcon outputs, newtons (Novint specifies "2 lbs+", about 8.9 N; the design
/// default is 8.5 N).
inline constexpr double kFalconMaxForce = 8.5;

struct FalconSettings {
    std::string firmwarePath;          ///< Option `firmware`; empty: no upload possible.
    double maxForce = kFalconMaxForce; ///< Option `max_force`.
    bool emulate = false;              ///< Option `emulate`.
    int homingPackets = 200;           ///< Option `homing_packets`.
    /// How long read() waits for the answer: one servo period.
    platform::Duration exchangeTimeout = std::chrono::milliseconds(1);

    /// \return the settings from \a options; InvalidArgument for an unknown key or a bad value.
    static Result<FalconSettings> parse(hal::OptionList options);
};

/// Counters of the servo exchange (observers).
struct FalconStats {
    std::uint64_t exchanges = 0;     ///< Successful reads.
    std::uint64_t timeouts = 0;      ///< Reads without a well-formed answer in time.
    std::uint64_t framingErrors = 0; ///< Answers without a complete well-formed packet.
    std::uint64_t fkIterations = 0;  ///< Newton iterations over all reads.
    int fkMaxIterations = 0;         ///< Most Newton iterations of one read.
    std::uint64_t fkFailures = 0;    ///< Reads whose forward kinematics did not converge.
    std::uint64_t rangeClamps = 0;   ///< Forces scaled down to fit the motor command range.
};

class FalconHapticDevice final : public hal::HapticDeviceBase {
public:
    /// Backend factory: settings from cfg.options. Without `emulate`, checks that a Falcon is on
    /// the USB bus (NoDevice otherwise), so autoprobing falls through to the next backend; with
    /// BackendConfig::awaitDevice it is created without one (open() fails with NoDevice until one
    /// is plugged in: the haptic task's supervisor retries it, DeviceSupervisor).
    static Result<std::unique_ptr<hal::HapticDevice>> create(const hal::BackendConfig &cfg);

    FalconHapticDevice(platform::Clock &clock, std::unique_ptr<UsbTransport> transport,
                       FalconSettings settings);
    ~FalconHapticDevice() override;

    /// \return true while created without a Falcon on the bus and none opened since.
    [[nodiscard]] bool awaitingDevice() const noexcept override
    {
        return awaiting_.load(std::memory_order_acquire);
    }

    /// \name Observers (thread-bound)
    ///@{
    /// The transport (a FakeFalcon under `emulate` or in tests).
    [[nodiscard]] UsbTransport &transport() noexcept { return *transport_; }
    /// The force the pending motor commands stand for, newtons: the last command after clamping,
    /// zero when not connected, not homed, after open(), close() or a non-finite command.
    [[nodiscard]] hal::Vec3 outputForce() const noexcept;
    [[nodiscard]] bool homed() const noexcept { return homed_; }
    /// The FalconFlag bits (homing, LEDs) sent with the motor commands.
    [[nodiscard]] std::uint8_t flags() const noexcept { return command_.flags; }
    [[nodiscard]] const falcon::MotorCommands &motorCommands() const noexcept
    {
        return command_.motors;
    }
    [[nodiscard]] const FalconStats &stats() const noexcept { return stats_; }
    ///@}

protected:
    [[nodiscard]] Result<State> openDevice() override;
    void closeDevice() noexcept override;
    [[nodiscard]] bool devicePresent() const noexcept override;
    [[nodiscard]] Result<void> readDevice(hal::HapticState &out) noexcept override;
    [[nodiscard]] Result<void>
    commandForceDevice(const hal::ForceCommand &command) noexcept override;
    void zeroForceDevice() noexcept override { zeroOutput(); }

private:
    void zeroOutput() noexcept;
    void updateFlags() noexcept;
    /// One exchange and decode; updates pose, buttons and homing. Real-time safe.
    Result<void> exchangeOnce(platform::Duration timeout) noexcept;
    Result<void> startFirmware();
    void home();

    platform::Clock &clock_;
    std::unique_ptr<UsbTransport> transport_;
    FalconSettings settings_;
    /// Created without a Falcon on the bus (awaitDevice) and none opened since.
    std::atomic<bool> awaiting_{false};

    falcon::CommandPacket command_{};
    falcon::Packet outPacket_{};
    std::array<std::uint8_t, 64> inBuffer_{};
    falcon::FrameAssembler frames_;

    falcon::JointAngles angles_{};
    hal::Vec3 position_{}; ///< Device frame, unclamped (the pose of the Jacobian).
    bool havePose_ = false;
    bool homed_ = false;
    std::uint32_t buttons_ = 0;
    platform::TimePoint sampleTime_{};
    hal::Vec3 output_{};
    FalconStats stats_;
};

} // namespace depthtouch::drivers
