#pragma once
/// \file
/// \brief MasterClock: where a clock the picture and the haptic time follow says the media is. The
/// sound is one (AudioPlayer::clock(): the media time the speaker plays), a GStreamer pipeline's
/// clock another (depthtouchsink: the running time its buffers are stamped with,
/// PlaybackHal::masterClock). The render thread moves the media origin onto it
/// (FrameClock::follow()), and with it the haptic task's time for Eq. 1.
/// Plain values.

#include "depthtouch/platform/clock.h"

namespace depthtouch::playback {

/// \brief The media time a master clock is at, at clock time `at` of the player's clock.
struct MasterClock {
    bool running = false;     ///< The clock runs (not paused, halted, ended or lost).
    platform::TimePoint at{}; ///< When it was read (the player's clock).
    double mediaTime = 0.0;   ///< Media time (the stream's PTS timeline) at `at`, s.
};

} // namespace depthtouch::playback
