#pragma once
/// \file
/// \brief RenderLoop: the body of the render thread (kRenderThread). Per turn: the main thread's
/// commands and session changes (RenderShared), pause and seek, frames taken from the decode
/// thread without blocking, the pacing decision (FrameClock), the depth pair published to the
/// haptic task's hand-off when a frame goes on screen (DepthHandoff::publishPair(): each new depth
/// frame copied once), the draw (Presenter), present() and the counters.
///
/// The display belongs to this thread: it is opened here (sized for the first stream), so that its
/// GL context is current here and nowhere else, and closed when the loop ends.
///
/// Thread-safety: run() on the render thread only; the object is built and destroyed by the main
/// thread while the render thread does not run. Everything shared goes through RenderShared.

#include <cstdint>
#include <memory>
#include <string>

#include "depthtouch/hal/display.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/playback/frame_clock.h"
#include "depthtouch/playback/playback.h"

#include "presenter.h"
#include "render_shared.h"
#include "session.h"

namespace depthtouch::playback {

/// See the file comment.
class RenderLoop {
public:
    /// \param shared the state shared with the main thread (outlives the loop)
    /// \param config the player's settings (outlive the loop)
    RenderLoop(RenderShared &shared, const PlaybackConfig &config, hal::Display &display,
               platform::Clock &clock);
    RenderLoop(const RenderLoop &) = delete;
    RenderLoop &operator=(const RenderLoop &) = delete;

    /// \brief Runs until RenderShared::quit(): plays the current session, then drops its frames,
    /// ends the recording, drops the GL objects and closes the display.
    void run();

private:
    using Commands = RenderShared::Commands;
    /// The frames this thread holds for the session.
    struct Frames {
        Session *session = nullptr;
        std::uint64_t gen = 0;
        receiver::PairedFrame shown;      ///< On screen.
        receiver::PairedFrame pending[2]; ///< Taken from the decoder, not yet shown.
        int pendingCount = 0;
        std::uint64_t seekSeen = 0;
        bool reseat = false;   ///< Next shown frame comes after a seek: restart the haptic clock.
        bool rebasing = false; ///< The clock restarts at a discontinuity, not at open or seek.
        bool eosSent = false;  ///< End of stream (or a cut input) reported.
        bool anyFrame = false; ///< The decoder has given a frame in this session.

        [[nodiscard]] bool haveShown() const noexcept
        {
            return static_cast<bool>(shown.color) || static_cast<bool>(shown.depth);
        }
        void dropFrames() noexcept;
        void popFront() noexcept;
        /// \return the PTS of pending[1], s, or null when only one frame is queued.
        [[nodiscard]] const double *nextPts(double &storage) const noexcept;
    };
    std::string adoptSession(const RenderShared::Turn &turn);
    std::string openDisplay();
    void play(Session &s, const Commands &cmd);
    void rebaseAtDiscontinuity(bool paused);
    void followMaster(Session &s, bool paused);
    void measureAvOffset(Session &s, platform::TimePoint shownAt, double pts);
    void seek(Session &s, double seekTo);
    void takeFrames(Session &s, platform::TimePoint now);
    void checkDecoder(Session &s, platform::TimePoint now);
    bool pace(Session &s, platform::TimePoint now, double pts, bool paused);
    void publishDepth(Session &s);
    void drawAndPresent(Session &s, const Commands &cmd, double pts);
    void count(Session &s, const DrawOutcome &d, const Result<hal::PresentInfo> &presented,
               double ms, const std::optional<LodSample> &lod, double pts);
    void leave();

    RenderShared &shared_;
    const PlaybackConfig &config_;
    hal::Display &display_;
    platform::Clock &clock_;
    std::unique_ptr<Presenter> presenter_;
    Frames frames_;
    FrameClock frameClock_;
    double avLead_ = 0.0; ///< s: how much earlier than its time a frame's turn comes with sound.
    /// The presenter's own counters (Presenter::addStats()), kept between frames.
    PlaybackStats presenterStats_;
};

} // namespace depthtouch::playback
