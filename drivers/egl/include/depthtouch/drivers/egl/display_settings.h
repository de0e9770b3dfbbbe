#pragma once
/// \file
/// \brief Pieces shared by the EGL display backends that need no EGL: backend options, the mode
/// string of DisplayConfig, and the simulated vertical blank that paces present().
///
/// Thread-safety: value types and pure functions (reentrant); a VsyncPacer is thread-bound like
/// the display that owns it.

#include <cstdint>
#include <string>
#include <string_view>

#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/display.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers {

/// \brief Backend options of the headless and X11 displays, used for the zero fields of
/// DisplayConfig.
struct EglDisplaySettings {
    int width = 1280;        ///< Pixels (option `width`).
    int height = 720;        ///< Pixels (option `height`).
    double refreshHz = 60.0; ///< Hertz (option `refresh`).
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

/// \brief A simulated vertical blank on the backend clock.
///
/// Blanks fall at epoch + k / refreshHz (k = 1, 2, ...). next() sleeps until the first blank after
/// the previous frame's; when the caller is late it lands on the first blank at or after now and
/// reports the blanks it skipped (the same timing as the mock display). Deterministic on a
/// platform::ManualClock.
class VsyncPacer {
public:
    /// Restarts the count: blanks from \a epoch at \a refreshHz (> 0).
    void start(platform::TimePoint epoch, double refreshHz) noexcept;
    /// \brief Waits on \a clock for the blank of the next frame.
    /// \return its time, the frame counter (1, 2, ...) and the blanks skipped.
    hal::PresentInfo next(platform::Clock &clock) noexcept;
    /// \brief Records a frame shown at \a shown, without waiting: the grid moves so that a blank
    /// falls at \a shown, and the blanks skipped since the previous frame are estimated from the
    /// time between them and the refresh rate (rounded to whole periods; at least one period per
    /// frame).
    /// \return \a shown, the frame counter and the estimated blanks skipped.
    hal::PresentInfo observe(platform::TimePoint shown) noexcept;
    /// \brief Paces a frame after a buffer swap that the window system may or may not have held
    /// until its vertical blank. Called less than \a interval periods after the previous frame's
    /// blank (a server that does not pace swaps, such as Xvfb), it sleeps on \a clock until then;
    /// otherwise the frame became visible now (the swap waited for the blank, or the caller is
    /// late). Then observe(). \a interval 0 never waits.
    /// \return the frame's time, the frame counter and the estimated blanks skipped.
    hal::PresentInfo follow(platform::Clock &clock, unsigned interval) noexcept;
    /// \return frames since start().
    [[nodiscard]] std::uint64_t frames() const noexcept { return frames_; }

private:
    [[nodiscard]] platform::TimePoint blank(std::uint64_t k) const noexcept;

    platform::TimePoint epoch_{};
    double refreshHz_ = 60.0;
    std::uint64_t lastBlank_ = 0;
    std::uint64_t frames_ = 0;
};

} // namespace depthtouch::drivers
