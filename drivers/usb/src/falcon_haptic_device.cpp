#include "depthtouch/drivers/usb/falcon_haptic_device.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string_view>
#include <vector>

#include "depthtouch/drivers/usb/fake_falcon.h"
#include "depthtouch/drivers/usb/libusb_transport.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Falcon)

namespace depthtouch::drivers {

namespace {

constexpr const char *kOptionKeys[] = {"firmware", "max_force", "emulate", "homing_packets"};

/// Generous wait for an answer outside the servo loop (open(), close()).
constexpr platform::Duration kSetupTimeout = std::chrono::milliseconds(20);
constexpr int kProbeTries = 5;

double clampTo(double v, double lo, double hi) noexcept
{
    return std::min(std::max(v, lo), hi);
}

/// Reads the firmware image at \a path. Errors: InvalidArgument (missing, unreadable, wrong size).
Result<std::vector<std::uint8_t>> readFirmware(const std::string &path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        DT_LOG(Falcon, Error, "Failed to open Falcon firmware file '%s': %s", path.c_str(),
               std::strerror(errno));
        return unexpected(Errc::InvalidArgument, "Cannot open the Falcon firmware file");
    }
    std::vector<std::uint8_t> image;
    image.reserve(falcon::kFirmwareMaxBytes + 1);
    char c = 0;
    while (image.size() <= falcon::kFirmwareMaxBytes && in.get(c))
        image.push_back(static_cast<std::uint8_t>(c));
    if (in.bad()) {
        DT_LOG(Falcon, Error, "Failed to read Falcon firmware file '%s'", path.c_str());
        return unexpected(Errc::InvalidArgument, "Cannot read the Falcon firmware file");
    }
    if (image.size() < falcon::kFirmwareMinBytes || image.size() > falcon::kFirmwareMaxBytes) {
        DT_LOG(Falcon, Error,
               "Falcon firmware file '%s' has %s%zu bytes; a firmware image has %zu to %zu",
               path.c_str(), image.size() > falcon::kFirmwareMaxBytes ? "more than " : "",
               std::min(image.size(), falcon::kFirmwareMaxBytes), falcon::kFirmwareMinBytes,
               falcon::kFirmwareMaxBytes);
        return unexpected(Errc::InvalidArgument, "Falcon firmware file has a wrong size");
    }
    return image;
}

} // namespace

Result<FalconSettings> FalconSettings::parse(hal::OptionList options)
{
    const std::string_view unknown = options.firstUnknownKey(kOptionKeys, std::size(kOptionKeys));
    if (!unknown.empty()) {
        DT_LOG(Falcon, Error, "Unknown falcon option '%.*s' (known: firmware, max_force, emulate, "
                              "homing_packets)",
               static_cast<int>(unknown.size()), unknown.data());
        return unexpected(Errc::InvalidArgument, "Unknown falcon haptic device option");
    }
    FalconSettings s;
    if (auto fw = options.find("firmware"))
        s.firmwarePath.assign(fw->data(), fw->size());
    auto maxForce = options.getDouble("max_force", s.maxForce);
    auto emulate = options.getBool("emulate", s.emulate);
    auto homing = options.getInt("homing_packets", s.homingPackets);
    if (!maxForce || !(*maxForce > 0.0) || *maxForce > kFalconMaxForce)
        return unexpected(Errc::InvalidArgument, "falcon option max_force must be in (0, 8.5] N");
    if (!emulate)
        return unexpected(emulate.error());
    if (!homing || *homing < 0 || *homing > 100'000)
        return unexpected(Errc::InvalidArgument, "falcon option homing_packets out of range");
    if (options.find("firmware") && s.firmwarePath.empty())
        return unexpected(Errc::InvalidArgument, "falcon option firmware needs a file path");
    s.maxForce = *maxForce;
    s.emulate = *emulate;
    s.homingPackets = *homing;
    return s;
}

Result<std::unique_ptr<hal::HapticDevice>> FalconHapticDevice::create(const hal::BackendConfig &cfg)
{
    auto settings = FalconSettings::parse(cfg.options);
    if (!settings)
        return unexpected(settings.error());
    std::unique_ptr<UsbTransport> transport;
    bool transportMissing = false;
    if (settings->emulate) {
        FakeFalconSettings fake;
        fake.firmwareAtPowerUp = settings->firmwarePath.empty();
        transport = std::make_unique<FakeFalcon>(fake);
    } else {
        auto found = LibusbTransport::probe(kFalconVendorId, kFalconProductId);
        if (!found)
            return unexpected(found.error());
        if (!*found && !cfg.awaitDevice)
            return unexpected(Errc::NoDevice, "No Novint Falcon (USB 0403:cb48) connected");
        transportMissing = !*found;
        if (!*found)
            DT_LOG(Falcon, Warning,
                   "No Novint Falcon (USB 0403:cb48) connected: waiting for one "
                   "(the haptic task opens it when it is plugged in)");
        transport = std::make_unique<LibusbTransport>();
    }
    auto device = std::make_unique<FalconHapticDevice>(cfg.clockRef(), std::move(transport),
                                                       std::move(*settings));
    device->awaiting_.store(transportMissing, std::memory_order_release);
    return std::unique_ptr<hal::HapticDevice>(std::move(device));
}

FalconHapticDevice::FalconHapticDevice(platform::Clock &clock,
                                       std::unique_ptr<UsbTransport> transport,
                                       FalconSettings settings)
    : clock_(clock), transport_(std::move(transport)), settings_(std::move(settings))
{
    caps_.name = settings_.emulate ? "Novint Falcon (emulated)" : "Novint Falcon";
    caps_.maxForce = settings_.maxForce;
    constexpr double e = falcon::kWorkspaceHalfExtent;
    caps_.workspaceMin = {-e, -e, -e};
    caps_.workspaceMax = {e, e, e};
    caps_.servoRateHz = 1000.0;
    caps_.buttonCount = 4;
}

FalconHapticDevice::~FalconHapticDevice()
{
    close();
}

Result<FalconHapticDevice::State> FalconHapticDevice::openDevice()
{
    DT_TRY(transport_->open(kFalconVendorId, kFalconProductId));
    command_ = {};
    frames_.clear();
    havePose_ = false;
    homed_ = false;
    output_ = {};
    if (auto r = startFirmware(); !r) {
        transport_->close();
        return unexpected(r.error());
    }
    home();
    awaiting_.store(false, std::memory_order_release);
    return State::Open;
}

Result<void> FalconHapticDevice::startFirmware()
{
    DT_TRY(falcon::setNormalMode(*transport_));
    const auto probe = [this]() -> Result<bool> {
        for (int i = 0; i < kProbeTries; ++i) {
            auto r = exchangeOnce(kSetupTimeout);
            if (r)
                return true;
            if (r.error().code == Errc::NoDevice)
                return unexpected(r.error());
        }
        return false;
    };
    auto running = probe();
    if (!running)
        return unexpected(running.error());
    if (*running)
        return ok();
    if (settings_.firmwarePath.empty()) {
        DT_LOG(Falcon, Error, "The Falcon's firmware is not running: give the firmware file with "
                              "the option firmware=PATH");
        return unexpected(Errc::InvalidArgument,
                          "Falcon firmware not loaded and no firmware option given");
    }
    auto image = readFirmware(settings_.firmwarePath);
    if (!image)
        return unexpected(image.error());
    DT_LOG(Falcon, Info, "Uploading Falcon firmware '%s' (%zu bytes)",
           settings_.firmwarePath.c_str(), image->size());
    DT_TRY(falcon::uploadFirmware(*transport_, *image));
    frames_.clear();
    running = probe();
    if (!running)
        return unexpected(running.error());
    if (!*running) {
        DT_LOG(Falcon, Error, "The Falcon's firmware did not start after uploading '%s'",
               settings_.firmwarePath.c_str());
        return unexpected(Errc::Io, "Falcon firmware did not start after the upload");
    }
    return ok();
}

void FalconHapticDevice::home()
{
    for (int i = 0; i < settings_.homingPackets && !homed_; ++i) {
        auto r = exchangeOnce(kSetupTimeout);
        if (!r && r.error().code == Errc::NoDevice)
            return;
    }
    if (!homed_)
        DT_LOG(Falcon, Warning,
               "Falcon not homed (red LED): move the grip all the way out, then push it straight "
               "in; forces stay off until it is homed");
}

void FalconHapticDevice::updateFlags() noexcept
{
    std::uint8_t flags = homed_ ? falcon::kLedGreen : (falcon::kLedRed | falcon::kFlagHoming);
    if (output_ != hal::Vec3{})
        flags |= falcon::kLedBlue;
    command_.flags = flags;
}

Result<void> FalconHapticDevice::exchangeOnce(platform::Duration timeout) noexcept
{
    updateFlags();
    falcon::encodeCommand(command_, outPacket_);
    auto n = transport_->exchange(outPacket_.data(), outPacket_.size(), inBuffer_.data(),
                                  inBuffer_.size(), timeout);
    if (!n) {
        if (n.error().code == Errc::NoDevice)
            return unexpected(n.error());
        ++stats_.timeouts;
        return unexpected(Errc::Timeout, "Falcon did not answer within a servo period");
    }
    frames_.push(inBuffer_.data(), *n);
    falcon::Packet packet{};
    falcon::StatusPacket status;
    if (!frames_.takeLatest(packet) || !falcon::decodeStatus(packet, status)) {
        ++stats_.framingErrors;
        ++stats_.timeouts;
        return unexpected(Errc::Timeout, "No well-formed Falcon status packet");
    }
    const bool wasHomed = homed_;
    homed_ = status.homedMask == 0x07;
    falcon::JointAngles angles{};
    for (std::size_t i = 0; i < 3; ++i)
        angles[i] = falcon::encoderToAngle(status.encoders[i]);
    hal::Vec3 p = havePose_ ? position_ : hal::Vec3{};
    const falcon::ForwardResult fk = falcon::forwardKinematics(angles, p);
    stats_.fkIterations += static_cast<std::uint64_t>(fk.iterations);
    stats_.fkMaxIterations = std::max(stats_.fkMaxIterations, fk.iterations);
    buttons_ = status.buttons;
    sampleTime_ = clock_.now();
    if (!fk.converged) {
        ++stats_.fkFailures;
        havePose_ = false;
        zeroOutput();
        return unexpected(Errc::Timeout, "Falcon encoder counts give no pose");
    }
    angles_ = angles;
    position_ = p;
    havePose_ = true;
    if (wasHomed != homed_)
        zeroOutput(); // the pose jumped: never keep torques computed at the old one
    ++stats_.exchanges;
    return ok();
}

void FalconHapticDevice::closeDevice() noexcept
{
    if (state() == State::Open && transport_->present()) {
        command_.motors = {};
        command_.flags = 0; // LEDs off: closed
        output_ = {};
        falcon::encodeCommand(command_, outPacket_);
        (void)transport_->exchange(outPacket_.data(), outPacket_.size(), inBuffer_.data(),
                                   inBuffer_.size(), kSetupTimeout);
    }
    transport_->close();
    zeroOutput();
    homed_ = false;
    havePose_ = false;
}

bool FalconHapticDevice::devicePresent() const noexcept
{
    return transport_->present();
}

void FalconHapticDevice::zeroOutput() noexcept
{
    command_.motors = {};
    output_ = {};
}

Result<void> FalconHapticDevice::readDevice(hal::HapticState &out) noexcept
{
    DT_TRY(exchangeOnce(settings_.exchangeTimeout));
    hal::HapticState s;
    const hal::Vec3 &lo = caps_.workspaceMin;
    const hal::Vec3 &hi = caps_.workspaceMax;
    s.position = {clampTo(position_.x, lo.x, hi.x), clampTo(position_.y, lo.y, hi.y),
                  clampTo(position_.z, lo.z, hi.z)};
    s.buttons = buttons_;
    s.time = sampleTime_;
    out = s;
    return ok();
}

Result<void> FalconHapticDevice::commandForceDevice(const hal::ForceCommand &command) noexcept
{
    hal::Vec3 f = command.force;
    hal::Vec3 tau;
    if (!homed_ || !havePose_ || !falcon::jointTorques(angles_, position_, f, tau)) {
        zeroOutput();
        return ok();
    }
    const double factor = falcon::torquesToCommands(tau, command_.motors);
    if (factor < 1.0) {
        ++stats_.rangeClamps;
        f *= factor;
    }
    output_ = f;
    return ok();
}

hal::Vec3 FalconHapticDevice::outputForce() const noexcept
{
    return isConnected() ? output_ : hal::Vec3{};
}

} // namespace depthtouch::drivers
