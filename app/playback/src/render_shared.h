#pragma once
/// \file
/// \brief RenderShared: what the main thread (Playback) and the render thread (RenderLoop) share:
/// the commands one way, the counters and reports the other.
///
/// Thread-safety: every plain member is guarded by `mutex`; the atomics are not.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "depthtouch/playback/playback.h"

#include "session.h"

namespace depthtouch::playback {

/// See the file comment.
struct RenderShared {
    mutable std::mutex mutex;
    std::condition_variable cv;

    // --- Main thread -> render thread ---
    Session *session = nullptr;   ///< Current session (owned by the main thread), or null.
    std::uint64_t sessionGen = 0; ///< Bumped when session changes.
    std::uint64_t sessionAck = 0; ///< The render thread dropped everything of older sessions.
    bool playing = false;         ///< startPlayback() was called for this session.
    bool paused = false;
    std::uint64_t seekGen = 0; ///< Bumped by seek().
    double seekTarget = 0.0;   ///< s, stream timeline (absolute).
    player::StereoMode stereoMode = player::StereoMode::SideBySide;
    bool quit = false;

    // --- Render thread -> main thread ---
    double position = 0.0;          ///< s from the first frame.
    PlaybackStats stats;            ///< Render-thread counters (copied out by stats()).
    std::string failure;            ///< Pipeline failure not yet reported.
    std::string displayError;       ///< The render thread could not open the display.
    std::vector<double> renderMs;   ///< Draw time per frame, ms (first 2^16 frames).
    std::vector<double> avOffsetMs; ///< Audio minus picture per presented frame, ms (2^16).
    std::vector<double> avOffsetAt; ///< When each was presented, s from the first; its PTS, s.
    std::vector<double> avOffsetPts;
    std::vector<double> meshTriangles; ///< Triangles drawn per frame under the LOD (first 2^16).
    bool endOfStream = false;          ///< Not yet reported.

    // --- Lock-free ---
    std::atomic<bool> snapshotRequest{false};
    std::atomic<std::uint64_t> osdEvents{0}; ///< Commands that bring the on-screen display up.
};

} // namespace depthtouch::playback
