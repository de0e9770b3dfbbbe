#pragma once
/// \file
/// \brief FrameClock: the render thread's media clock and frame pacing, without GL or threads: when
/// a frame is due, how late it is, whether it is dropped, the preroll after open and seek, pause
/// freezing the media time, the end of the last frame's time on screen and the time spent playing.
///
/// Media time t (stream PTS, s) is at clock time origin() + t. The first frame after open() or a
/// seek starts the clock at its PTS (pace() → Pace::starts) and, once it is on screen,
/// endPreroll() anchors it again, so the time its first draw takes does not make the frames after
/// it late. Everything works on platform::TimePoint values given by the caller (a SteadyClock or a
/// ManualClock): the class never reads a clock and never sleeps.
///
/// Thread-safety: thread-bound (the render thread; tests). Real-time safe: no allocation, no lock.

#include <cstdint>

#include "depthtouch/platform/clock.h"

namespace depthtouch::playback {

/// \brief What FrameClock::pace() decides for the frame at the head of the queue.
struct Pace {
    enum class Step : std::uint8_t {
        Show, ///< Draw it now.
        Wait, ///< Not due yet: sleep until `until` (at most 5 ms ahead), then ask again.
        Hold, ///< Paused with a frame on screen: sleep 5 ms, then ask again.
        Drop, ///< Too late, and its successor is due too: skip it (FrameClock::skipsFront()).
    };
    Step step = Step::Show;
    platform::TimePoint until{}; ///< Wait: when to ask again.
    double lateSeconds = 0.0;    ///< Show: how late the frame is taken, s (0 when it starts).
    bool starts = false;         ///< Show: the clock started at this frame (open, seek): preroll.
};

/// See the file comment.
class FrameClock {
public:
    /// \param maxLateness PlaybackConfig::maxLateness, s (≥ 0): how late a frame may be drawn
    /// before it is skipped when its successor is due too.
    explicit FrameClock(double maxLateness) noexcept : maxLateness_(maxLateness) {}

    /// \name Time spent playing (for the presented frame rate)
    ///@{
    /// \brief Counts the time from \a now as playing (not \a paused) or not.
    void trackPlaying(platform::TimePoint now, bool paused) noexcept;
    /// \return seconds spent playing up to \a now.
    [[nodiscard]] double playingSeconds(platform::TimePoint now) const noexcept;
    ///@}

    /// \name The media clock
    ///@{
    /// \return whether the clock runs (a frame was shown since the last restart()).
    [[nodiscard]] bool started() const noexcept { return started_; }
    /// \return the clock time at which media time is 0 (meaningful when started()).
    [[nodiscard]] platform::TimePoint origin() const noexcept { return origin_; }
    /// \return whether the frame that started the clock is being drawn (before endPreroll()).
    [[nodiscard]] bool prerolling() const noexcept { return prerolling_; }
    /// \brief A seek: the next frame starts the clock again.
    void restart() noexcept { started_ = false; }
    /// \brief Freezes the media time while \a paused: the origin follows \a now so media time
    /// stands still. \return whether origin() moved (publish it to the haptic task).
    bool holdForPause(platform::TimePoint now, bool paused) noexcept;
    /// \brief Decides for the frame of PTS \a pts (s) at the head of the queue at \a now.
    /// \param nextPts PTS of the frame queued after it, s, or null when none is queued.
    /// \param period frame period, s: a frame taken within it counts as on time.
    /// \param hold paused with a frame on screen and no seek to show: Pace::Step::Hold.
    /// Starts the clock when it is not started (Pace::starts); on Show records whether the frame
    /// was on time (for skipsFront()).
    [[nodiscard]] Pace pace(platform::TimePoint now, double pts, const double *nextPts,
                            double period, bool hold) noexcept;
    /// \return whether the frame of PTS \a pts is skipped at \a now: its successor (\a nextPts,
    /// null when none is queued) is due too, and it is more than maxLateness late or the player
    /// has not been on time for 3 × maxLateness. A stall of L seconds is caught up within about
    /// 2L more (one refresh gained per frame at 30 fps on 60 Hz); frames late for longer mean the
    /// player cannot catch up (a slow machine, or 60 fps on 60 Hz), and are skipped as with no
    /// lateness allowed. \pre started().
    [[nodiscard]] bool skipsFront(platform::TimePoint now, double pts,
                                  const double *nextPts) const noexcept;
    /// \brief The frame of PTS \a pts that started the clock is on screen at \a now: media time is
    /// its PTS now. \return whether the origin moved (false when not prerolling).
    bool endPreroll(platform::TimePoint now, double pts) noexcept;
    /// \brief Audio as the master clock (audio_player.h): media time \a mediaTime (s) is heard at
    /// \a at, so the origin moves to at − mediaTime when it is more than \a tolerance (s) away.
    /// Ignored while the clock is not started, prerolling or paused.
    /// \return whether the origin moved (publish it to the haptic task).
    bool follow(platform::TimePoint at, double mediaTime, double tolerance) noexcept;
    /// \return whether the frame of PTS \a shownPts shown last has had its \a period on screen at
    /// \a now (true when the clock is not started).
    [[nodiscard]] bool lastFrameDone(platform::TimePoint now, double shownPts,
                                     double period) const noexcept;
    ///@}

private:
    double maxLateness_;
    bool started_ = false;
    bool prerolling_ = false;
    platform::TimePoint origin_{};   ///< Clock time at which media time is 0.
    platform::TimePoint onTimeAt_{}; ///< When a frame was last taken less than a period late.
    double pausedAt_ = 0.0;          ///< Media time frozen by pause, s.
    bool wasPaused_ = false;
    platform::TimePoint playStart_{};
    bool playClockRunning_ = false;
    double playingSeconds_ = 0.0;
};

} // namespace depthtouch::playback
