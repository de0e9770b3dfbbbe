#pragma once
/// \file
/// \brief Pieces shared by the EGL display backends that need no EGL: backend options, the mode
/// string of DisplayConfig, and (from drivers/common) the simulated vertical blank that paces
/// present().
///
/// Thread-safety: value types and pure functions (reentrant); a VsyncPacer is thread-bound like
/// the display that owns it.

#include <cstdint>
#include <string>
#include <string_view>

#include "depthtouch/drivers/common/display_mode.h"
#include "depthtouch/drivers/common/vsync_pacer.h"
#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/display.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers {

/// \brief Backend options of the headless and X11 displays, used for the zero fields of
/// DisplayConfig.
struct EglDisplaySettings : DisplayModeSettings {
    int swapInterval = 1;    ///< X11 only: eglSwapInterval (option `swap_interval`, 0..4).
    bool fullscreen = false; ///< X11 only: a window covering the screen (option `fullscreen`).
    bool readback = false;   ///< X11 only: keep a copy of each presented frame for readPixels()
                             ///< (option `readback`; costs one framebuffer blit per frame).

    /// \return the settings from \a options over the defaults. Errors: InvalidArgument for an
    /// unknown key or a value out of range (1..16384 pixels, 1..1000 Hz).
    /// \param[in] window Also accept the window-only keys `fullscreen` and `readback`.
    static Result<EglDisplaySettings> parse(hal::OptionList options, bool window = false);
};

/// \brief A parsed DisplayConfig::mode: "[CONNECTOR][:]WIDTHxHEIGHT[@HZ]", e.g. "HDMI-A-1",
/// "1920x1080", "1920x1080@50", "HDMI-A-1:1280x720@60". Zero fields were not given.
struct ModeSpec {
    std::string connector; ///< DRM connector name ("HDMI-A-1", "DP-2"); empty = any.
    int width = 0;         ///< Pixels.
    int height = 0;        ///< Pixels.
    double refreshHz = 0;  ///< Hertz.
};

/// \brief Parses a mode string (see ModeSpec). A text that does not start with a digit and has no
/// ':' is a connector name, which must look like a DRM one (TYPE-INDEX: "HDMI-A-1", "eDP-1").
/// \return the spec; an empty text gives an empty spec. Errors: NotSupported (malformed size, rate
/// or connector, e.g. "1920x", "640x480@", "0x0", "x1080").
Result<ModeSpec> parseModeSpec(std::string_view text);

/// \brief The size and refresh a window or offscreen display opens with: \a cfg fields, then
/// cfg.mode, then \a settings for what is still zero. A connector in the mode is ignored.
/// \return the resolved values. Errors: NotSupported (malformed mode), InvalidArgument (negative
/// or out-of-range values).
Result<EglDisplaySettings> resolveWindowConfig(const hal::DisplayConfig &cfg,
                                               const EglDisplaySettings &settings);
} // namespace depthtouch::drivers
