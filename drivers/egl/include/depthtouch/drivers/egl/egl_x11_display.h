#pragma once
/// \file
/// \brief EglX11Display: an OpenGL ES 3 context drawing into an X11 window (EGL platform
/// EGL_PLATFORM_X11_KHR through eglGetPlatformDisplayEXT), for seeing the output live on a
/// developer desktop. Backend name `x11`, autoprobed after `kms` and before `headless`.
///
/// open() connects to the X server (BackendConfig::device, else $DISPLAY), creates a window of the
/// configured size titled "DepthTouch" (fixed size; or covering the screen with `fullscreen=1`),
/// an EGL window surface on it and a GLES 3 context, and leaves no context current: makeCurrent()
/// binds it on the calling thread (the render thread), so open() may run on another thread. The
/// renderer draws into framebuffer() 0, the window surface's back buffer.
///
/// present() swaps with eglSwapBuffers at swap interval `swap_interval` (default 1), then paces
/// the frame with VsyncPacer::follow() on the backend clock: a server that holds swaps until its
/// vertical blank (a desktop on a GPU) sets the rhythm, and the frame's blank is the time the swap
/// returned; where swaps return at once (Xvfb and Mesa's software path ignore the interval),
/// present() sleeps until one period after the previous frame's blank, as a simulated vertical
/// blank (deterministic on a platform::ManualClock). The blanks skipped are estimated from the time
/// since the previous frame and the refresh rate. `swap_interval=0` never waits. The refresh rate
/// is the option `refresh` (default 60 Hz) or DisplayConfig's, not the monitor's.
///
/// readPixels() needs the option `readback=1`: present() then copies the back buffer into an
/// offscreen framebuffer before the swap (the window's buffers are undefined after it), and
/// readPixels() reads that copy. capabilities().readback says whether it was asked for.
///
/// Lost: a window closed by the user (WM_DELETE_WINDOW) or destroyed, or a lost connection to the
/// X server, puts the display in state Lost: present() and makeCurrent() return NoDevice, and the
/// process goes on: the first open() installs process-wide Xlib error handlers that log and return
/// (XSetErrorHandler, XSetIOErrorHandler), and each display's connection gets an I/O error exit
/// handler (XSetIOErrorExitHandler) that marks it Lost; other connections keep Xlib's exit. After
/// close(), open() creates a new window, or fails with NoDevice while the server is gone.
///
/// Options (BackendConfig::options): width, height (pixels, default 1280×720), refresh (Hz,
/// default 60), swap_interval (0..4, default 1), fullscreen (0/1), readback (0/1).
/// DisplayConfig::mode "WIDTHxHEIGHT[@HZ]" is honoured too.
/// Errors: the factory returns NoDevice, without logging an error, when $DISPLAY is unset or the X
/// server cannot be reached (so autoprobe moves on to `headless` on machines without a screen), or
/// when EGL has no X11 platform.
/// Thread-safety: thread-bound, as hal::Display. Each display has its own X connection.

#include <memory>
#include <string>

#include "depthtouch/drivers/egl/display_settings.h"
#include "depthtouch/drivers/egl/egl_window_display.h"
#include "depthtouch/hal/backends.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {

class EglX11Display final : public EglWindowDisplay {
public:
    /// Backend factory: settings from cfg.options, X display name from cfg.device (empty:
    /// $DISPLAY), time from cfg.clock; checks that the X server answers and that EGL has the X11
    /// platform (NoDevice otherwise).
    static Result<std::unique_ptr<hal::Display>> create(const hal::BackendConfig &cfg);

    EglX11Display(platform::Clock &clock, const EglDisplaySettings &settings,
                  std::string xDisplayName);
    ~EglX11Display() override;

    /// \return the X window id (an XID) while Open or Lost, 0 when Closed.
    [[nodiscard]] unsigned long window() const noexcept;

protected:
    [[nodiscard]] Result<void> openDevice(const hal::DisplayConfig &cfg) override;
    void closeDevice() noexcept override;
    [[nodiscard]] Result<hal::PresentInfo> presentDevice() override;

private:
    struct X; ///< Xlib, EGL and GL handles (keeps X11 and EGL headers out of this header).

    /// \brief The steps of openDevice(): connects, creates the window, its EGL surface and
    /// context, and clears the first frame. What a failed step made is left in x_.
    /// \return the window's size.
    [[nodiscard]] Result<hal::Size> openWindow(const EglDisplaySettings &resolved);
    [[nodiscard]] Result<void> ensureCurrent() override;
    [[nodiscard]] egl::FrameCopy &frameCopy() noexcept override;
    /// Handles the pending X events; a closed window or a broken connection makes the state Lost.
    void pumpEvents() noexcept;
    void lose(const char *why) noexcept;

    platform::Clock &clock_;
    const EglDisplaySettings settings_;
    const std::string xDisplayName_;
    VsyncPacer pacer_;
    std::unique_ptr<X> x_;
};

} // namespace depthtouch::drivers
