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

Result<void> NullHapticDevice::readDevice(hal::HapticState &) noexcept
{
    return unexpected(Errc::NoDevice, "No haptic device (backend none)");
}

Result<void> NullHapticDevice::commandForceDevice(const hal::ForceCommand &) noexcept
{
    return unexpected(Errc::NoDevice, "No haptic device (backend none)");
}

} // namespace depthtouch::drivers
