#include "depthtouch/drivers/usb/fake_falcon.h"

#include <algorithm>

namespace depthtouch::drivers {

using falcon::Packet;

FakeFalcon::FakeFalcon(const FakeFalconSettings &settings) : settings_(settings)
{
    controls_.reserve(64);
    (void)falcon::inverseKinematics(grip_, gripAngles_);
    powerUp();
}

void FakeFalcon::powerUp() noexcept
{
    mode_ = settings_.firmwareAtPowerUp ? Mode::Running : Mode::Off;
    dtr_ = false;
    baud_ = settings_.firmwareAtPowerUp ? kFtdiBaud1456312 : 0;
    latency_ = settings_.firmwareAtPowerUp ? 1 : 16;
    firmwareBytes_ = 0;
    homingSeen_ = 0;
    homed_ = settings_.homingPackets <= 0;
    last_ = {};
    corrupt_ = 0;
    commandFrames_.clear();
    rxSize_ = 0;
    rxHead_ = 0;
}

void FakeFalcon::replug() noexcept
{
    powerUp();
    open_ = false;
    plugged_.store(true, std::memory_order_release);
}

Result<void> FakeFalcon::open(std::uint16_t vendorId, std::uint16_t productId)
{
    if (!plugged_.load(std::memory_order_acquire) || vendorId != kFalconVendorId ||
        productId != kFalconProductId)
        return unexpected(Errc::NoDevice, "No Novint Falcon on the USB bus");
    if (open_)
        return unexpected(Errc::Busy, "Falcon already open");
    open_ = true;
    return ok();
}

void FakeFalcon::close() noexcept
{
    open_ = false;
}

bool FakeFalcon::present() const noexcept
{
    return open_ && plugged_.load(std::memory_order_acquire);
}

Result<void> FakeFalcon::control(FtdiRequest request, std::uint16_t value)
{
    if (!present())
        return unexpected(Errc::NoDevice, "Falcon unplugged");
    controls_.emplace_back(request, value);
    switch (request) {
    case FtdiRequest::Reset:
        if (value == kFtdiPurgeRx)
            rxSize_ = 0;
        break;
    case FtdiRequest::BaudRate:
        baud_ = value;
        break;
    case FtdiRequest::LatencyTimer:
        latency_ = value;
        break;
    case FtdiRequest::ModemControl:
        if ((value & 0x0100) != 0) {
            const bool dtr = (value & 0x01) != 0;
            // The DTR line resets the microcontroller: a rising edge at the loader's 9600 baud
            // starts the loader (the running firmware stops).
            if (dtr && !dtr_ && baud_ == kFtdiBaud9600) {
                mode_ = Mode::Off;
                homed_ = settings_.homingPackets <= 0;
                homingSeen_ = 0;
                firmwareBytes_ = 0;
            }
            dtr_ = dtr;
        }
        break;
    case FtdiRequest::FlowControl:
    case FtdiRequest::LineProperty:
    case FtdiRequest::BitMode:
        break;
    }
    if (mode_ == Mode::Loading && latency_ == 1 && baud_ == kFtdiBaud1456312) {
        const bool sizeOk = settings_.firmwareSize != 0
                                ? firmwareBytes_ == settings_.firmwareSize
                                : firmwareBytes_ >= falcon::kFirmwareMinBytes &&
                                      firmwareBytes_ <= falcon::kFirmwareMaxBytes;
        mode_ = sizeOk ? Mode::Running : Mode::Off;
        if (sizeOk)
            ++uploads_;
    }
    return ok();
}

void FakeFalcon::queue(const std::uint8_t *data, std::size_t size) noexcept
{
    for (std::size_t i = 0; i < size && rxSize_ < rx_.size(); ++i) {
        rx_[(rxHead_ + rxSize_) % rx_.size()] = data[i];
        ++rxSize_;
    }
}

void FakeFalcon::deviceReceives(const std::uint8_t *data, std::size_t size) noexcept
{
    switch (mode_) {
    case Mode::Off:
        if (baud_ == kFtdiBaud9600 && dtr_ && size == falcon::kLoaderHello.size() &&
            std::equal(data, data + size, falcon::kLoaderHello.begin())) {
            queue(falcon::kLoaderHelloReply.data(), falcon::kLoaderHelloReply.size());
            mode_ = Mode::Hello;
        }
        break;
    case Mode::Hello:
        if (baud_ == kFtdiBaud140000 && !dtr_ && size == 1 && data[0] == falcon::kLoaderStart[0]) {
            queue(falcon::kLoaderStartReply.data(), falcon::kLoaderStartReply.size());
            mode_ = Mode::Loading;
            firmwareBytes_ = 0;
        }
        break;
    case Mode::Loading:
        if (baud_ == kFtdiBaud140000) {
            queue(data, size);
            firmwareBytes_ += size;
        }
        break;
    case Mode::Running:
        if (baud_ != kFtdiBaud1456312)
            break; // wrong serial speed: the firmware sees noise
        commandFrames_.push(data, size);
        Packet p{};
        while (commandFrames_.takeOldest(p))
            answerCommand(p);
        break;
    }
}

void FakeFalcon::answerCommand(const Packet &packet) noexcept
{
    falcon::CommandPacket cmd;
    if (!falcon::decodeCommand(packet, cmd))
        return;
    last_ = cmd;
    ++commands_;
    if ((cmd.flags & falcon::kFlagHoming) != 0 && !homed_ &&
        ++homingSeen_ >= settings_.homingPackets)
        homed_ = true;
    falcon::StatusPacket st;
    for (std::size_t i = 0; i < 3; ++i) {
        const std::int16_t counts = falcon::angleToEncoder(gripAngles_[i]);
        st.encoders[i] = homed_ ? counts : static_cast<std::int16_t>(counts + kUnhomedOffset);
    }
    st.buttons = buttons_;
    st.homedMask = homed_ ? 0x07 : 0x00;
    Packet out{};
    falcon::encodeStatus(st, out);
    if (corrupt_ > 0) {
        --corrupt_;
        out[5] = 0x21; // not a nibble byte
        out[15] = 0x7c;
    }
    queue(out.data(), out.size());
}

Result<std::size_t> FakeFalcon::write(const std::uint8_t *data, std::size_t size,
                                      platform::Duration /*timeout*/)
{
    if (!present())
        return unexpected(Errc::NoDevice, "Falcon unplugged");
    if (!silent_.load(std::memory_order_acquire))
        deviceReceives(data, size);
    return size;
}

Result<std::size_t> FakeFalcon::read(std::uint8_t *data, std::size_t capacity,
                                     platform::Duration /*timeout*/)
{
    if (!present())
        return unexpected(Errc::NoDevice, "Falcon unplugged");
    const std::size_t n = std::min(capacity, rxSize_);
    for (std::size_t i = 0; i < n; ++i)
        data[i] = rx_[(rxHead_ + i) % rx_.size()];
    rxHead_ = (rxHead_ + n) % rx_.size();
    rxSize_ -= n;
    return n;
}

Result<std::size_t> FakeFalcon::exchange(const std::uint8_t *out, std::size_t outSize,
                                         std::uint8_t *in, std::size_t inCapacity,
                                         platform::Duration timeout) noexcept
{
    if (!present())
        return unexpected(Errc::NoDevice, "Falcon unplugged");
    if (silent_.load(std::memory_order_acquire))
        return unexpected(Errc::Timeout, "Falcon did not answer");
    deviceReceives(out, outSize);
    auto n = read(in, inCapacity, timeout);
    if (!n)
        return n;
    if (*n == 0)
        return unexpected(Errc::Timeout, "Falcon did not answer");
    return n;
}

bool FakeFalcon::setGripPosition(const hal::Vec3 &p) noexcept
{
    falcon::JointAngles th{};
    if (!falcon::inverseKinematics(p, th))
        return false;
    grip_ = p;
    gripAngles_ = th;
    return true;
}

hal::Vec3 FakeFalcon::outputForce() const noexcept
{
    // F = (∂theta/∂p)ᵀ·tau: column k of ∂theta/∂p by a central difference along axis k.
    const hal::Vec3 tau = falcon::commandsToTorques(last_.motors);
    constexpr double kStep = 1e-6;
    const hal::Vec3 axes[3] = {{kStep, 0.0, 0.0}, {0.0, kStep, 0.0}, {0.0, 0.0, kStep}};
    double f[3] = {0.0, 0.0, 0.0};
    for (std::size_t k = 0; k < 3; ++k) {
        falcon::JointAngles plus{};
        falcon::JointAngles minus{};
        if (!falcon::inverseKinematics(grip_ + axes[k], plus) ||
            !falcon::inverseKinematics(grip_ - axes[k], minus))
            return {};
        const hal::Vec3 dthetaDp{(plus[0] - minus[0]) / (2.0 * kStep),
                                 (plus[1] - minus[1]) / (2.0 * kStep),
                                 (plus[2] - minus[2]) / (2.0 * kStep)};
        f[k] = hal::dot(dthetaDp, tau);
    }
    return {f[0], f[1], f[2]};
}

} // namespace depthtouch::drivers
