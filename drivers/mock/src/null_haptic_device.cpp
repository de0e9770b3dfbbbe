#include "depthtouch/drivers/mock/null_haptic_device.h"

namespace depthtouch::drivers {

Result<std::unique_ptr<hal::HapticDevice>> NullHapticDevice::create(const hal::BackendConfig &)
{
    return std::unique_ptr<hal::HapticDevice>(std::make_unique<NullHapticDevice>());
}

NullHapticDevice::NullHapticDevice()
{
    caps_.name = "none";
    caps_.maxForce = 0.0;
    caps_.servoRateHz = 1000.0;
    caps_.buttonCount = 0;
}

Result<void> NullHapticDevice::open()
{
    if (state() != State::Closed)
        return unexpected(Errc::InvalidState, "open() requires state Closed");
    state_.store(State::Disconnected, std::memory_order_release);
    return ok();
}

Result<void> NullHapticDevice::noDevice() const noexcept
{
    if (state() == State::Closed)
        return unexpected(Errc::InvalidState, "Haptic device not open");
    return unexpected(Errc::NoDevice, "No haptic device (backend none)");
}

Result<void> NullHapticDevice::read(hal::HapticState &) noexcept
{
    return noDevice();
}

Result<void> NullHapticDevice::commandForce(const hal::Vec3 &) noexcept
{
    return noDevice();
}

} // namespace depthtouch::drivers
