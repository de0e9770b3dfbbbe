/// \file
/// \brief FrameClock: see frame_clock.h.

#include "depthtouch/playback/frame_clock.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace depthtouch::playback {

using platform::fromSeconds;
using platform::TimePoint;
using platform::toSeconds;

void FrameClock::trackPlaying(TimePoint now, bool paused) noexcept
{
    if (!paused && !playClockRunning_) {
        playStart_ = now;
        playClockRunning_ = true;
    } else if (paused && playClockRunning_) {
        playingSeconds_ += toSeconds(now - playStart_);
        playClockRunning_ = false;
    }
}

double FrameClock::playingSeconds(TimePoint now) const noexcept
{
    double played = playingSeconds_;
    if (playClockRunning_)
        played += toSeconds(now - playStart_);
    return played;
}

bool FrameClock::holdForPause(TimePoint now, bool paused) noexcept
{
    bool moved = false;
    if (paused && started_) {
        if (!wasPaused_)
            pausedAt_ = toSeconds(now - origin_);
        origin_ = now - fromSeconds(pausedAt_);
        moved = true;
    }
    wasPaused_ = paused;
    return moved;
}

Pace FrameClock::pace(TimePoint now, double pts, const double *nextPts, double period,
                      bool hold) noexcept
{
    Pace p;
    if (!started_) {
        // First frame after open or seek: media time starts at its PTS now, and again when it is
        // on screen (endPreroll()), so the time its first draw takes (shader compilation, first
        // uploads, a seek's decode) does not make the frames after it late.
        origin_ = now - fromSeconds(pts);
        onTimeAt_ = now;
        started_ = true;
        prerolling_ = true;
        pausedAt_ = pts;
        p.starts = true;
        return p;
    }
    if (hold) {
        p.step = Pace::Step::Hold;
        return p;
    }
    const TimePoint due = origin_ + fromSeconds(pts);
    if (now < due) {
        p.step = Pace::Step::Wait;
        p.until = std::min(due, now + std::chrono::milliseconds(5));
        return p;
    }
    // Late: skip this frame when its successor is due too and it is too late to catch up; else
    // draw it, and the next frames catch up.
    if (skipsFront(now, pts, nextPts)) {
        p.step = Pace::Step::Drop;
        return p;
    }
    p.lateSeconds = toSeconds(now - due);
    if (p.lateSeconds <= period)
        onTimeAt_ = now;
    return p;
}

bool FrameClock::skipsFront(TimePoint now, double pts, const double *nextPts) const noexcept
{
    if (nextPts == nullptr || now < origin_ + fromSeconds(*nextPts))
        return false;
    const double late = toSeconds(now - origin_) - pts;
    return late > maxLateness_ || toSeconds(now - onTimeAt_) > 3.0 * maxLateness_;
}

bool FrameClock::endPreroll(TimePoint now, double pts) noexcept
{
    if (!prerolling_)
        return false;
    // The haptic time never runs backwards (it holds until the new origin catches up).
    prerolling_ = false;
    origin_ = now - fromSeconds(pts);
    return true;
}

bool FrameClock::follow(TimePoint at, double mediaTime, double tolerance) noexcept
{
    if (!started_ || prerolling_ || wasPaused_)
        return false;
    const TimePoint heard = at - fromSeconds(mediaTime);
    if (std::abs(toSeconds(heard - origin_)) <= tolerance)
        return false;
    origin_ = heard;
    return true;
}

bool FrameClock::lastFrameDone(TimePoint now, double shownPts, double period) const noexcept
{
    return !started_ || toSeconds(now - origin_) >= shownPts + period;
}

} // namespace depthtouch::playback
