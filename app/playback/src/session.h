#pragma once
/// \file
/// \brief Session: one open stream of the player (what Playback::open() builds and stop()
/// destroys), and the conversions between stream PTS and seconds.
///
/// Thread-safety: built and destroyed on the main thread; the render thread uses it between the
/// two (see RenderShared::switchSession()), and writes startPts/haveStart through
/// RenderShared::setStart() (the main thread reads them in RenderShared::seek()).

#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>

#include "depthtouch/hal/audio_source.h"
#include "depthtouch/hal/display.h"
#include "depthtouch/haptic_task/depth_handoff.h"
#include "depthtouch/haptic_task/haptic_task.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/playback/audio_player.h"
#include "depthtouch/receiver/decoder_thread.h"
#include "depthtouch/receiver/receiver.h"

namespace depthtouch::playback {

/// \return \a pts (stream timeline, ns) in seconds.
inline double ptsSeconds(hal::Pts pts) noexcept
{
    return static_cast<double>(pts.count()) * 1e-9;
}

/// \return \a s seconds as a stream PTS (ns, rounded to the nearest).
inline hal::Pts ptsFromSeconds(double s) noexcept
{
    return hal::Pts(static_cast<std::int64_t>(std::llround(s * 1e9)));
}

/// \brief One open stream: its receiver and decode thread, with depth and a device the depth
/// hand-off and the haptic task, with sound its audio player.
struct Session {
    std::unique_ptr<receiver::Receiver> receiver;
    std::unique_ptr<receiver::DecoderThread> decoder;
    std::unique_ptr<haptic_task::DepthHandoff> handoff; ///< Written by the render thread.
    std::unique_ptr<haptic_task::HapticTask> task;
    /// The sound, when the input has some and PlaybackHal has an audio output (the player before
    /// its source: destroyed first).
    std::unique_ptr<hal::AudioSource> audioSource;
    std::unique_ptr<AudioPlayer> audio;
    /// Without sound, the clock the media follows instead (PlaybackHal::masterClock), or null.
    std::function<MasterClock()> masterClock;
    double period = 1.0 / 30.0;       ///< Frame period, s.
    double startPts = 0.0;            ///< PTS of the first frame (s); positions count from it.
    hal::DisplayConfig displayConfig; ///< For the display's first open.
    bool haveStart = false;
    platform::TimePoint openStarted{}; ///< When open() was called (PlaybackStats::tuneInSeconds).
    bool presentedOnce = false;        ///< A frame of this session was presented.
    bool live = false; ///< The source cannot seek (a network stream, a FIFO): it may go silent.
    /// An adaptive input (an HLS ladder): it waits for whole segments over a slow link, so it is
    /// not watched for silence (the source's I/O time-out ends a server that stopped answering).
    bool adaptive = false;
};

} // namespace depthtouch::playback
