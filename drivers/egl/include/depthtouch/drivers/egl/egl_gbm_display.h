#pragma once
/// \file
/// \brief EglGbmDisplay: the `kms` display backend of the set-top box: OpenGL ES 3 rendered into
/// a GBM surface and scanned out full screen by DRM/KMS, with page flips on the vertical blank.
/// Autoprobed first (before `x11` and `headless`).
///
/// open() chooses card, connector and mode (selectKmsScreenMode(): the option `mode` or
/// DisplayConfig::mode — "HDMI-A-1", "1920x1080@60", "HDMI-A-1:1280x720@50" — else the sink's
/// preferred mode; DisplayConfig's size picks a mode only when the sink has one of that size, as
/// the player asks for the size of its content). It opens the card, becomes DRM master, picks a
/// CRTC for the connector (chooseCrtc(): its encoder's current CRTC, else the first one it can
/// drive), saves that CRTC's state, creates a GBM device and a GBM surface of the mode's size
/// (GBM_FORMAT_XRGB8888, scan-out + rendering), an EGL display on the GBM platform
/// (EGL_PLATFORM_GBM_KHR), an XRGB8888 window surface on the GBM surface and a GLES 3 context,
/// and sets the mode with a black first frame. It leaves no context current: makeCurrent() binds
/// it on the render thread. The renderer draws into framebuffer() 0, the surface's back buffer,
/// of size() = the mode's size.
///
/// present() swaps (eglSwapBuffers), then KmsScanout shows the buffer: page flip, wait for its
/// event (poll with a 500 ms timeout, drmHandleEvent), release of the previous buffer; vsyncTime is
/// the flip event's timestamp moved to the backend clock, skippedVsyncs comes from the events'
/// vertical blank sequence numbers (kms_scanout.h).
///
/// readPixels() needs the option `readback=1`: present() then copies the back buffer into an
/// offscreen framebuffer before the swap (a GBM buffer's content is undefined once it is back in
/// the surface), as the x11 backend does; capabilities().readback says whether it was asked for.
///
/// Lost: a flip event that does not come in time, or DRM calls failing because the connector was
/// unplugged or DRM master was taken (EACCES, ENODEV, EINVAL, ...), or a lost EGL context make the
/// state Lost: present() and makeCurrent() return NoDevice at once, never hanging.
///
/// close() (also after Lost, after an open() that failed midway, and from the destructor) puts
/// back the CRTC state saved by open() — its mode, framebuffer (the console or the previous
/// program's picture), position — on the connector, once; then releases the GBM buffers (their
/// DRM framebuffers are removed with them), destroys the EGL surface and context, the GBM surface
/// and device, drops DRM master and closes the card.
///
/// Needs: DRM master on the card, so no X server or Wayland compositor running on it (run from a
/// text console or a service), and read/write access to /dev/dri/card* (group `video`).
/// Options (BackendConfig::options): mode (as DisplayConfig::mode), card (a card path instead of
/// discovery, e.g. /dev/dri/card1; BackendConfig::device too), readback (0/1).
/// Errors: the factory returns InvalidArgument for an unknown option or a malformed mode, NoDevice
/// when there is no DRM card (/dev/dri/card*) or no connected display (so autoprobe moves on), and
/// Busy when another process is DRM master. open() returns NoDevice (display unplugged meanwhile,
/// no CRTC, EGL without the GBM platform), NotSupported (no mode as asked, the mode cannot be set,
/// no XRGB8888 config) or Busy (DRM master taken meanwhile).
/// Thread-safety: thread-bound, as hal::Display.

#include <cstdint>
#include <memory>
#include <string>

#include "depthtouch/drivers/egl/egl_window_display.h"
#include "depthtouch/hal/backends.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {

class EglGbmDisplay final : public EglWindowDisplay {
public:
    /// Options of the kms display (see the file comment).
    struct Settings {
        std::string mode; ///< Option `mode`: "[CONNECTOR][:]WxH[@HZ]"; empty = DisplayConfig's.
        std::string card; ///< Option `card` or BackendConfig::device; empty = discovery.
        bool readback = false; ///< Option `readback`.

        /// \return the settings of \a cfg. Errors: InvalidArgument (unknown key, malformed mode
        /// or readback value).
        static Result<Settings> parse(const hal::BackendConfig &cfg);
    };

    /// Backend factory (see the file comment): settings from cfg.options and cfg.device, time
    /// from cfg.clock; checks that a card with a connected display exists and that DRM master can
    /// be taken.
    static Result<std::unique_ptr<hal::Display>> create(const hal::BackendConfig &cfg);

    EglGbmDisplay(platform::Clock &clock, Settings settings);
    ~EglGbmDisplay() override;

protected:
    [[nodiscard]] Result<void> openDevice(const hal::DisplayConfig &cfg) override;
    void closeDevice() noexcept override;
    [[nodiscard]] Result<hal::PresentInfo> presentDevice() override;

private:
    struct Kms; ///< DRM, GBM, EGL and GL handles (keeps their headers out of this header).

    [[nodiscard]] Result<void> openOutput(const hal::DisplayConfig &cfg);
    [[nodiscard]] Result<void> ensureCurrent() override;
    [[nodiscard]] egl::FrameCopy &frameCopy() noexcept override;
    void lose(const char *why) noexcept;

    platform::Clock &clock_;
    const Settings settings_;
    std::uint64_t frames_ = 0;
    std::unique_ptr<Kms> kms_;
};

} // namespace depthtouch::drivers
