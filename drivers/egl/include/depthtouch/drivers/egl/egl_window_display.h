#pragma once
/// \file
/// \brief EglWindowDisplay: what the EGL displays that draw into a window surface (`kms`, `x11`)
/// do alike once the backend has made its surface current: makeCurrent() binds the surface's back
/// buffer (framebuffer 0) at the display's size, and readPixels() reads the copy of the last
/// presented frame that present() keeps (option `readback=1`).
/// Thread-safety: thread-bound, as hal::Display.

#include "depthtouch/hal/display_base.h"

namespace depthtouch::drivers {

namespace egl {
class FrameCopy;
} // namespace egl

/// \brief The base of the window-surface displays: implements makeCurrentDevice() and
/// readPixelsDevice() on the backend's ensureCurrent() and frameCopy().
class EglWindowDisplay : public hal::DisplayBase {
public:
    ~EglWindowDisplay() override = default;

protected:
    EglWindowDisplay() = default;

    /// \brief Makes the backend's context and window surface current on the calling thread.
    /// \return nothing on success. Errors: NoDevice when the display is lost (the backend marks it
    /// Lost first), Io when EGL refuses otherwise.
    [[nodiscard]] virtual Result<void> ensureCurrent() = 0;
    /// \return the copy of the last presented frame that present() keeps (created with
    /// `readback=1`).
    [[nodiscard]] virtual egl::FrameCopy &frameCopy() noexcept = 0;

    /// \brief ensureCurrent(), then binds framebuffer 0 at size_ for drawing.
    [[nodiscard]] Result<void> makeCurrentDevice() final;
    /// \brief ensureCurrent(), then the kept frame into \a out.
    [[nodiscard]] Result<void> readPixelsDevice(const hal::ImageView &out) final;
};

} // namespace depthtouch::drivers
