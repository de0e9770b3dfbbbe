#pragma once
/// \file
/// \brief RenderShared: what the main thread (Playback) and the render thread (RenderLoop) share:
/// the commands and session changes one way, the counters, the position and the reports the other.
///
/// Thread-safety: any method from either thread (each group below says which thread calls it);
/// the plain state is private, guarded by one mutex that only render_shared.cpp takes
/// (docs/style.md §6: each lock private to one .cpp). The two atomics are public and lock-free.
/// The session handshake: switchSession() waits until the render thread has acknowledged the new
/// generation (acknowledgeSession()), by which time it holds no frame of an older session, so the
/// main thread may then destroy the old Session.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "depthtouch/platform/clock.h"
#include "depthtouch/playback/playback.h"

#include "presenter.h"
#include "session.h"

namespace depthtouch::playback {

/// See the file comment.
class RenderShared {
public:
    /// What the main thread asked, read by the render thread once per turn.
    struct Commands {
        bool paused = false;
        std::uint64_t seekGen = 0; ///< Bumped by every seek.
        double seekTo = 0.0;       ///< s, stream timeline (absolute).
        player::StereoMode mode = player::StereoMode::SideBySide;
        bool remoteConnected = true; ///< False: the on-screen display says the remote is missing.
    };
    /// The start of one render-thread turn (nextTurn()).
    struct Turn {
        enum class Step : std::uint8_t {
            Quit,  ///< Leave the loop.
            Adopt, ///< Drop every frame held, take `session`, then acknowledgeSession(gen).
            Idle,  ///< Nothing to play (waited up to 20 ms).
            Play   ///< Play a turn of the adopted session with `commands`.
        };
        Step step = Step::Idle;
        Session *session = nullptr; ///< Adopt: the new session (null: none).
        std::uint64_t gen = 0;      ///< Adopt: its generation.
        std::uint64_t seekGen = 0;  ///< Adopt: the seeks asked for before it (already done).
        Commands commands;          ///< Play.
    };
    /// The counters of one frame drawn and handed to present() (countPresented()).
    struct PresentedFrame {
        DrawOutcome draw;
        std::optional<LodSample> lod;
        bool presented = false;
        std::string displayLost;             ///< present() failed for good (NoDevice): why.
        std::optional<double> tuneInSeconds; ///< The session's first frame presented: since open.
        double drawMs = 0.0;                 ///< Time of the draw, ms.
        double position = 0.0;               ///< s from the session's first frame.
        double playingSeconds = 0.0;         ///< Time played so far (FrameClock), s.
        /// The presenter's own counters (Presenter::addStats()): zero-copy colour frames.
        bool zeroCopy = false;
        std::uint64_t colorFramesImported = 0;
        std::uint64_t colorFramesDmaBufUploaded = 0;
    };
    /// A report for the state machine (takeReport()).
    struct Report {
        std::string failure;      ///< A pipeline failure, or empty.
        bool endOfStream = false; ///< The last frame had its time on screen.
    };
    /// The A/V offsets of a run, one entry per presented frame with sound (first 2^16).
    struct AvOffsets {
        std::vector<double> ms;  ///< Audio minus picture, ms.
        std::vector<double> at;  ///< When presented, s from the first.
        std::vector<double> pts; ///< The frame's PTS, s.
    };

    /// \param stereoMode the first stereo mode. Reserves the per-frame series (2^16 entries each).
    explicit RenderShared(player::StereoMode stereoMode);

    // --- Main thread ---

    /// \brief Hands \a next (null: none) to the render thread; when \a waitForRenderThread, waits
    /// until it dropped every frame of the older sessions (or quits).
    void switchSession(Session *next, bool waitForRenderThread);
    /// \brief Tells the render thread to leave its loop.
    void quit();
    /// \brief Plays the session from its start. \return InvalidState "nothing is open" without one.
    Result<void> startPlaying();
    /// \brief Pauses or resumes. \return InvalidState \a nothingOpen (static) without a session.
    Result<void> setPaused(bool paused, const char *nothingOpen);
    /// \brief Seeks to \a seconds (absolute from the first frame, or relative to the position),
    /// clamped to [0, duration − one frame]. \return InvalidState "nothing is open" without a
    /// session.
    Result<void> seek(double seconds, player::SeekMode mode);
    void setStereoMode(player::StereoMode mode);
    /// \brief The remote's input device is there, or there is no remote (false: waited for, lost).
    void setRemoteConnected(bool connected);
    /// \return the position and the duration (when known) of the session, s; none without one.
    [[nodiscard]] player::PlayerActions::MediaPosition mediaPosition() const;
    /// \return |F| of the session's haptic task, N; NaN without a session or a task.
    [[nodiscard]] double hapticForce() const;
    /// \return whether the session's haptic task has its device connected; none without a
    /// session or a task.
    [[nodiscard]] std::optional<bool> hapticDeviceConnected() const;
    /// \return s from the first frame.
    [[nodiscard]] double position() const;
    void countOpen();
    /// \return why the render thread could not open the display, once; else empty.
    std::string takeDisplayError();
    /// \return the failure and end of stream not yet reported, once.
    Report takeReport();
    void setReceiverStats(const receiver::ReceiverStats &stats);
    void setAvLogLost(std::string why);
    /// \return a snapshot could not be written.
    [[nodiscard]] bool snapshotLost() const;
    /// \return the counters, with the draw time's, triangles' and A/V offset's percentiles.
    [[nodiscard]] PlaybackStats stats() const;
    /// \return a copy of the A/V offsets (for the A/V log, after the render thread ended).
    [[nodiscard]] AvOffsets avOffsets() const;

    // --- Render thread ---

    /// \return what this turn does; \a adoptedGen is the generation of the session it holds.
    Turn nextTurn(std::uint64_t adoptedGen);
    /// \brief The session of \a gen is adopted (every older frame dropped); \a displayError (may be
    /// empty) is why the display could not be opened for it.
    void acknowledgeSession(std::uint64_t gen, std::string displayError);
    /// \brief Every session so far is let go (the loop is leaving).
    void acknowledgeAll();
    /// \brief The first frame's PTS of \a s, s (positions and seeks count from it).
    void setStart(Session &s, double pts);
    /// \brief An A/V offset (\a offsetMs) of the frame of PTS \a pts (s) presented at \a shownAt.
    void addAvOffset(double offsetMs, platform::TimePoint shownAt, double pts);
    void countFrameReceived();
    /// \brief A pipeline failure, kept when none is waiting to be reported.
    void reportFailure(std::string why);
    void reportEndOfStream();
    void countDropped();
    /// \brief A frame shown \a lateSeconds after its time (late when more than \a period, s).
    void countShown(double lateSeconds, double period);
    void countDepthPairPublished();
    void countPresented(const PresentedFrame &frame);
    /// \brief The outputs the presenter could not finish when the loop ended.
    void addLostOutputs(const OutputsLost &lost);

    // --- Lock-free ---
    std::atomic<bool> snapshotRequest{false};
    std::atomic<std::uint64_t> osdEvents{0}; ///< Commands that bring the on-screen display up.

private:
    mutable std::mutex mutex_;
    std::condition_variable cv_;

    // Main thread -> render thread.
    Session *session_ = nullptr;   ///< Current session (owned by the main thread), or null.
    std::uint64_t sessionGen_ = 0; ///< Bumped when the session changes.
    std::uint64_t sessionAck_ = 0; ///< The render thread dropped everything of older sessions.
    bool playing_ = false;         ///< startPlaying() was called for this session.
    bool paused_ = false;
    std::uint64_t seekGen_ = 0; ///< Bumped by seek().
    double seekTarget_ = 0.0;   ///< s, stream timeline (absolute).
    player::StereoMode stereoMode_;
    bool remoteConnected_ = true; ///< setRemoteConnected().
    bool quit_ = false;

    // Render thread -> main thread.
    double position_ = 0.0;               ///< s from the first frame.
    PlaybackStats stats_;                 ///< Render-thread counters (copied out by stats()).
    std::string failure_;                 ///< Pipeline failure not yet reported.
    std::string displayError_;            ///< The render thread could not open the display.
    std::vector<double> renderMs_;        ///< Draw time per frame, ms (first 2^16 frames).
    AvOffsets avOffsets_;                 ///< First 2^16.
    platform::TimePoint firstAvOffset_{}; ///< When the first A/V offset was measured.
    std::vector<double> meshTriangles_;   ///< Triangles drawn per frame under the LOD (first 2^16).
    bool endOfStream_ = false;            ///< Not yet reported.
};

} // namespace depthtouch::playback
