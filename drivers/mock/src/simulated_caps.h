#pragma once
/// \file
/// \brief The capabilities of the simulated haptic devices (mock, sim): private to drivers/mock.

#include "depthtouch/hal/haptic_device.h"

namespace depthtouch::drivers {

/// \return the capabilities of a simulated device called \a name whose \a settings give maxForce
/// (N), workspaceHalfExtent (m: the workspace is the cube ±half-extent on each axis), servoRateHz
/// and buttonCount. Reentrant.
template <class Settings>
hal::HapticCapabilities simulatedCapabilities(const char *name, const Settings &settings)
{
    hal::HapticCapabilities caps;
    caps.name = name;
    caps.maxForce = settings.maxForce;
    const double e = settings.workspaceHalfExtent;
    caps.workspaceMin = {-e, -e, -e};
    caps.workspaceMax = {e, e, e};
    caps.servoRateHz = settings.servoRateHz;
    caps.buttonCount = settings.buttonCount;
    return caps;
}

} // namespace depthtouch::drivers
