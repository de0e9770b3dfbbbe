#pragma once
/// \file
/// \brief Presenter: what the render thread draws into the display's frame buffer before each
/// present: the stereo renderer with its level of detail, the prep worker, the on-screen display,
/// the avatar, the recording and the snapshots (gl_presenter.cpp, in builds with EGL/GLES), or
/// nothing (null_presenter.cpp): CMake compiles one of the two.
///
/// Thread-safety: thread-bound (the render thread, which owns the display's GL context).

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "depthtouch/hal/display.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/playback/playback.h"

#include "session.h"

namespace depthtouch::playback {

/// \brief The frame to draw and what goes over it.
struct DrawInput {
    const receiver::PairedFrame &frame; ///< On screen now (color and/or depth).
    double pts = 0.0;                   ///< Its PTS, s.
    player::StereoMode mode;            ///< Stereo packing.
    bool paused = false;                ///< The on-screen display says PAUSED (and stays up).
    bool remoteConnected = true;        ///< False: the on-screen display says REMOTE: NO DEVICE.
    const Session &session;             ///< Frame period; its haptic task for avatar and OSD.
};

/// \brief What draw() did, for the counters (applied by the render thread under its lock).
struct DrawOutcome {
    bool drawn = true;            ///< The frame buffer holds the frame (false: a render error).
    bool preparedAhead = false;   ///< Drawn with a mesh made ahead by the prep worker.
    bool recorded = false;        ///< Added to the recording.
    bool snapshotWritten = false; ///< A snapshot was written.
    std::string recordError;      ///< The recording stopped with this error.
    std::string snapshotError;    ///< A snapshot was not written (this one or an earlier one).
};

/// \brief The outputs of a run lost when it ended (empty: written, or none).
struct OutputsLost {
    std::string recording; ///< Why the recording could not be finished.
    std::string snapshot;  ///< Why a snapshot still being written was lost.
};

/// \brief The level of detail after a presented frame.
struct LodSample {
    std::size_t budget = 0; ///< Leaf-block budget.
    bool limited = false;   ///< The budget made this frame's mesh coarser.
    double triangles = 0.0; ///< Triangles drawn.
};

/// See the file comment.
class Presenter {
public:
    virtual ~Presenter() = default;

    /// \brief The display's GL context is current on this thread: frames are drawn from now on.
    virtual void contextReady() = 0;
    /// \brief A new session: drops the renderer (re-created for the new sizes), its target, the
    /// level of detail and every frame made ahead.
    virtual void newSession() = 0;
    /// \brief A seek: drops the frames made ahead (they reference frames of the old position).
    virtual void dropPrepared() = 0;
    /// \brief Has \a next (a queued frame) made ahead while this thread draws; \a queued are the
    /// \a queuedCount frames queued (their preps are kept).
    virtual void prepareAhead(const receiver::PairedFrame &next,
                              const receiver::PairedFrame *queued, int queuedCount) = 0;
    /// \brief Draws \a in into the display's frame buffer (records it, takes a snapshot).
    virtual DrawOutcome draw(const DrawInput &in) = 0;
    /// \brief Before the draw time is taken: waits for a software rasterizer's work (under the
    /// level of detail), so the time covers the draw and not the present's wait for the vblank.
    virtual void finishDrawing(bool drawn) = 0;
    /// \brief After present(): feeds the draw time to the level of detail.
    /// \return the level of detail's state, or nullopt when it did not run (no LOD, not drawn,
    /// not presented, or the preroll frame).
    virtual std::optional<LodSample> afterPresent(double drawSeconds, bool drawn, bool presented,
                                                  bool prerolling) = 0;
    /// \brief Copies the renderer's own counters (zero-copy colour frames) into \a stats.
    virtual void addStats(PlaybackStats &stats) const = 0;
    /// \brief Ends the recording, writes the snapshots still queued and drops the GL objects
    /// (while the context is current).
    /// \return what could not be written.
    virtual OutputsLost shutdown() = 0;

protected:
    Presenter() = default;
};

/// \return the presenter of this build: the GL one (EGL/GLES built) or the null one.
/// \param snapshotRequest set by Playback::requestSnapshot(), taken by the presenter.
/// \param osdEvents commands that bring the on-screen display up (counted by Playback).
std::unique_ptr<Presenter> makePresenter(const PlaybackConfig &config, hal::Display &display,
                                         platform::Clock &clock, std::atomic<bool> &snapshotRequest,
                                         const std::atomic<std::uint64_t> &osdEvents);

/// \return whether this build draws the frames on \a display (it has a GL context and the GL
/// presenter is built).
bool presenterDraws(const hal::Display &display) noexcept;

} // namespace depthtouch::playback
