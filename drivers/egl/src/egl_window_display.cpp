/// \file
/// \brief makeCurrent() and readPixels() of the window-surface displays (egl_window_display.h).

#include "depthtouch/drivers/egl/egl_window_display.h"

#include "egl_common.h"

namespace depthtouch::drivers {

Result<void> EglWindowDisplay::makeCurrentDevice()
{
    DT_TRY(ensureCurrent());
    egl::bindDrawTarget(0, size_);
    return ok();
}

Result<void> EglWindowDisplay::readPixelsDevice(const hal::ImageView &out)
{
    DT_TRY(ensureCurrent());
    return frameCopy().read(out, size_);
}

} // namespace depthtouch::drivers
