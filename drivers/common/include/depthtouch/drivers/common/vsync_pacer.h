#pragma once
/// \file
/// \brief VsyncPacer: the simulated vertical blank that paces present() of the displays without a
/// real one (the mock display, the EGL headless and X11 displays).
///
/// Thread-safety: thread-bound, like the display that owns it.

#include <cstdint>

#include "depthtouch/hal/display.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {

/// \brief A simulated vertical blank on the backend clock.
///
/// Blanks fall at epoch + k / refreshHz (k = 1, 2, ...). next() sleeps until the first blank after
/// the previous frame's; when the caller is late it lands on the first blank at or after now and
/// reports the blanks it skipped. Deterministic on a
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
