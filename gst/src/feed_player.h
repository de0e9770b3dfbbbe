#pragma once
/// \file
/// \brief FeedPlayer: `play`'s player fed by depthtouchsink's pads (issue 62), without GStreamer.
/// It is the player of `depthtouch play`, not a second one: `play`'s player core
/// (app/cli/player_core.h): the display and the haptic device from the backend table as
/// `play --display --haptic` opens them, playback::Playback with `play`'s option table's config
/// (cli::landPlayOptions()): its receiver (the raw-video decoder, the PTS pairing), stereo
/// renderer, on-screen display and 1 kHz haptic task; player::StateMachine with `play`'s control
/// loop (control::playUntilDone()) and control socket. Only the media source differs:
/// PadMediaSource over the element's PadFeed (pad_feed.h) instead of the FFmpeg demuxer, and, the
/// input being a stream without an end the player can know, no sound and no live-silence watch (a
/// paused pipeline sends nothing).
///
/// Lifetime: open() at the element's READY to PAUSED (backends, Playback and control socket: a bad
/// setting, a backend that does not open or a socket that cannot be made fails here), start() at
/// the first PAUSED to PLAYING (the loop's thread: the state machine plays the feed), setPaused()
/// at the later state changes, the destructor at PAUSED to READY (the feed shut down, the loop quit
/// and joined, zero force, the display closed). When the player stops by itself (both pads ended
/// and the frames shown, or a failure) the loop ends and \a onEnd is called on its thread.
///
/// Thread-safety: open(), start() and the destructor on one thread (the element's state
/// changes); setPaused(), setStiffness() and readout() from any thread. The state machine, the
/// control socket and the Playback's calls run on the loop's thread.

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "depthtouch/platform/macros.h"
#include "depthtouch/playback/master_clock.h"
#include "haptic_session.h"
#include "pad_feed.h"

namespace depthtouch::cli {
struct PlayOptions;
class PlayerCore;
} // namespace depthtouch::cli

namespace depthtouch::gst {

/// \brief depthtouchsink's settings: play's options of the same names (defaults are play's).
struct PlayerSettings {
    HapticSettings haptic;      ///< --haptic, --haptic-options, --stiffness, --method.
    std::string display;        ///< --display: backend(s); empty: autoprobe, as play.
    std::string displayOptions; ///< --display-options.
    std::string control;        ///< --control: the control socket's path; empty: none.
};

/// \brief What the player measured so far (its Playback's stats and haptic task), copied each
/// tenth of a second by the loop's thread.
struct PlayerReadout {
    std::string state;                 ///< The state machine's state ("playing", ...).
    std::uint64_t framesPaired = 0;    ///< Pairs the receiver made (ReceiverStats::framesOutput).
    std::uint64_t framesPresented = 0; ///< Pairs presented (PlaybackStats::framesPresented).
    std::uint64_t depthMissing = 0;    ///< Pairs without a depth frame.
    std::uint64_t depthUnpaired = 0;   ///< Depth frames no colour frame was paired with.
    std::uint64_t depthPairsPublished = 0; ///< Depth pairs handed to the haptic task.
    std::uint64_t hapticUpdates = 0;       ///< Cycles of the haptic loop.
    std::uint64_t safetyTrips = 0;         ///< Force-jump releases + watchdog trips.
    /// Of safetyTrips, the watchdog's (a missed deadline, a device time-out): the machine's load
    /// where the haptic thread is not SCHED_FIFO.
    std::uint64_t watchdogTrips = 0;
    std::uint64_t pageFaults = 0; ///< Page faults of the haptic thread after its warm-up.
    double servoRateHz = 0.0;     ///< Updates per second over the run.
    double forceZ = 0.0;          ///< z of the last force, N (toward the viewer).
    double force = 0.0;           ///< |F| of the last force, N.
    double maxForce = 0.0;        ///< Largest |F| commanded, N.
    double position = 0.0;        ///< Media position of the frame on screen, s.
    bool gl = false;              ///< Frames are drawn by the stereo renderer.
    bool haptics = false;         ///< A haptic task runs (depth and a device).
};

class FeedPlayer {
public:
    /// \brief Checks \a settings by play's option table, opens the display and the haptic device
    /// and makes the Playback reading \a feed, its media (the picture and the haptic task's time)
    /// following \a masterClock (the pipeline's running time; null: the player's own clock).
    /// \return the player, or null with \a why: the bad setting's, the failed backend's (the
    /// backend table's report) or the control socket's one line.
    static std::unique_ptr<FeedPlayer> open(const PlayerSettings &settings,
                                            std::shared_ptr<PadFeed> feed,
                                            std::function<playback::MasterClock()> masterClock,
                                            std::string &why);
    /// Shuts the feed, quits the loop and joins it, then closes the Playback and the backends.
    ~FeedPlayer();

    /// \brief Starts the loop's thread, which sends "play". \a onEnd(failure) is called on that
    /// thread when the player stopped by itself (failure empty at the end of the stream), not
    /// when the destructor ends it. \return an empty string, or why it could not start (a second
    /// call). Once.
    std::string start(std::function<void(const std::string &failure)> onEnd);
    /// \brief Pauses or resumes the player (the pipeline's PLAYING and PAUSED).
    void setPaused(bool paused) noexcept { wantPaused_.store(paused); }
    /// \brief A flushing seek began in the pipeline (PadFeed::flushStart()): on its next turn the
    /// loop seeks the player to the start of the new timeline, as `play`'s seek does (its queued
    /// frames dropped, its clock and the haptic task's surface restarted). Any thread.
    void seekForFlush() noexcept { flushSeeks_.fetch_add(1); }
    /// \brief The stiffness, N/m, sent to the player as the command `stiffness N`.
    void setStiffness(double newtonsPerMetre) noexcept { stiffness_.store(newtonsPerMetre); }
    /// \return the last readout.
    [[nodiscard]] PlayerReadout readout();
    /// \return the haptic backend chosen ("sim", "none"...) and the display's.
    [[nodiscard]] const std::string &deviceName() const noexcept { return deviceName_; }
    [[nodiscard]] const std::string &displayName() const noexcept { return displayName_; }

private:
    FeedPlayer(std::unique_ptr<cli::PlayOptions> options, std::unique_ptr<cli::PlayerCore> core);
    DT_DISABLE_COPY_AND_MOVE(FeedPlayer)
    /// The loop's thread: see start().
    void run(const std::function<void(const std::string &)> &onEnd);

    std::unique_ptr<cli::PlayOptions> options_;
    std::unique_ptr<cli::PlayerCore> core_; ///< The player: its loop runs on thread_.
    std::shared_ptr<PadFeed> feed_;
    std::string deviceName_;
    std::string displayName_;
    std::atomic<bool> stop_{false};
    std::atomic<bool> wantPaused_{false};
    std::atomic<std::uint64_t> flushSeeks_{0}; ///< seekForFlush() calls so far.
    std::atomic<double> stiffness_;
    std::mutex mutex_;
    PlayerReadout readout_; ///< Under mutex_.
    std::thread thread_;
};

} // namespace depthtouch::gst
