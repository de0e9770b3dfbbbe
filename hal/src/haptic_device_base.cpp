#include "depthtouch/hal/haptic_device_base.h"

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(HapticDevice)

namespace depthtouch::hal {

ForceCommand clampForce(const Vec3 &force, double maxForce) noexcept
{
    ForceCommand c{force, norm(force), false};
    if (c.magnitude > maxForce) {
        c.force *= maxForce / c.magnitude;
        c.magnitude = maxForce;
        c.clamped = true;
    }
    return c;
}

Result<void> HapticDeviceBase::open()
{
    if (state() != State::Closed) {
        DT_LOG(HapticDevice, Error, "%s: in state %s trying open() requiring Closed",
               caps_.name.c_str(), toString(state()));
        return unexpected(Errc::InvalidState, "open() requires state Closed");
    }
    auto opened = openDevice();
    if (!opened)
        return unexpected(opened.error());
    state_.store(*opened, std::memory_order_release);
    return ok();
}

void HapticDeviceBase::close() noexcept
{
    closeDevice();
    state_.store(State::Closed, std::memory_order_release);
}

bool HapticDeviceBase::isConnected() const noexcept
{
    return state() == State::Open && devicePresent();
}

void HapticDeviceBase::markDisconnected() noexcept
{
    zeroForceDevice();
    state_.store(State::Disconnected, std::memory_order_release);
}

Result<void> HapticDeviceBase::checkUsable() noexcept
{
    const State s = state();
    if (s == State::Closed)
        return unexpected(Errc::InvalidState, "Haptic device not open");
    if (s == State::Disconnected)
        return unexpected(Errc::NoDevice, "Haptic device disconnected");
    if (!devicePresent()) {
        markDisconnected();
        return unexpected(Errc::NoDevice, "Haptic device unplugged");
    }
    return ok();
}

Result<void> HapticDeviceBase::noteLoss(Result<void> r) noexcept
{
    if (!r && r.error().code == Errc::NoDevice)
        markDisconnected();
    return r;
}

Result<void> HapticDeviceBase::read(HapticState &out) noexcept
{
    DT_TRY(checkUsable());
    return noteLoss(readDevice(out));
}

Result<void> HapticDeviceBase::commandForce(const Vec3 &force) noexcept
{
    DT_TRY(checkUsable());
    if (!isFinite(force)) {
        DT_TRY(noteLoss(commandForceDevice(ForceCommand{})));
        return unexpected(Errc::InvalidArgument, "Non-finite force");
    }
    return noteLoss(commandForceDevice(clampForce(force, caps_.maxForce)));
}

} // namespace depthtouch::hal
