#pragma once
/// \file
/// \brief EglHeadlessDisplay: an OpenGL ES 3 context on Mesa's surfaceless EGL platform
/// (EGL_MESA_platform_surfaceless, e.g. llvmpipe or a render node) drawing into offscreen
/// framebuffers. Backend name `headless`: the host default when there is no screen.
///
/// open() creates the context and two framebuffer objects of the configured size (color RGBA8,
/// depth 24 + stencil 8 renderbuffers). The renderer draws into framebuffer() (bound by
/// makeCurrent() and present()); present() waits for the GPU (glFinish), swaps the two buffers
/// and sleeps until the next simulated vertical blank on the backend clock (VsyncPacer: blanks at
/// open time + k / refreshHz; deterministic on a platform::ManualClock). readPixels() reads the
/// last presented buffer, which stays untouched until the next present().
///
/// Options (BackendConfig::options): width, height (pixels, default 1280×720), refresh (Hz,
/// default 60). DisplayConfig::mode "WIDTHxHEIGHT[@HZ]" is honoured too.
/// Errors: the factory and open() return NoDevice when the surfaceless platform is missing.
/// Thread-safety: thread-bound, as hal::Display. Several headless displays may exist in one
/// process (they share the EGL display; each has its own context).

#include <memory>

#include "depthtouch/drivers/egl/display_settings.h"
#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/display_base.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {

class EglHeadlessDisplay final : public hal::DisplayBase {
public:
    /// Backend factory: settings from cfg.options, time from cfg.clock; checks that the
    /// surfaceless EGL platform initialises (NoDevice otherwise).
    static Result<std::unique_ptr<hal::Display>> create(const hal::BackendConfig &cfg);

    EglHeadlessDisplay(platform::Clock &clock, const EglDisplaySettings &settings);
    ~EglHeadlessDisplay() override;

protected:
    [[nodiscard]] Result<void> openDevice(const hal::DisplayConfig &cfg) override;
    void closeDevice() noexcept override;
    [[nodiscard]] Result<void> makeCurrentDevice() override;
    [[nodiscard]] Result<hal::PresentInfo> presentDevice() override;
    [[nodiscard]] std::uint32_t framebufferDevice() const noexcept override;
    [[nodiscard]] Result<void> readPixelsDevice(const hal::ImageView &out) override;

private:
    struct Gl; ///< EGL and GL handles (keeps EGL headers out of this header).

    [[nodiscard]] Result<void> ensureCurrent();

    platform::Clock &clock_;
    const EglDisplaySettings settings_;
    VsyncPacer pacer_;
    std::unique_ptr<Gl> gl_;
};

} // namespace depthtouch::drivers
