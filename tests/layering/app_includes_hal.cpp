// Layering control: the same app-layer setup including HAL and platform headers compiles.
#include "depthtouch/hal/haptic_device.h"
#include "depthtouch/platform/result.h"

int layeringControl() { return depthtouch::Result<int>(1).value(); }
