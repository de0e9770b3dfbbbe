#pragma once
/// \file
/// \brief Playback::Impl: the player's state shared by the main thread's files (playback.cpp, the
/// open and the commands; playback_audio.cpp, the sound) and handed to the render thread as its
/// RenderShared. Private to dt_playback.
///
/// Thread-safety: as playback.h; the RenderShared part through its methods (render_shared.h).

#include <memory>
#include <optional>
#include <string>

#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/platform/thread_config.h"
#include "depthtouch/playback/playback.h"

#include "async_opener.h"
#include "render_loop.h"
#include "render_shared.h"
#include "session.h"

namespace depthtouch::playback {

/// \return \a before's counters with \a later's added (a later session's queue and end win).
AudioStats addedAudioStats(AudioStats before, const AudioStats &later);

struct Playback::Impl : RenderShared {
    PlaybackConfig config;
    PlaybackHal hal;
    platform::Clock &clock;

    // --- Main thread only ---
    std::unique_ptr<Session> owned;
    AsyncOpener opener;                ///< The source's open and probe, off the main thread.
    std::string openingUrl;            ///< What the opener opens.
    platform::TimePoint openStarted{}; ///< When the opener was started (tune-in time).
    bool openDone = false;             ///< open() finished: report onOpened().
    std::string openError;             ///< open() failed: report onOpenFailed().
    Errc openErrorKind = Errc::InvalidArgument; ///< Whose: onOpenFailed().
    bool hapticsEnabled;
    double stiffness;
    double volume; ///< Of the sound, percent (kept for the next inputs).
    bool mute;
    AudioStats audioBefore;    ///< The sound's counters of the sessions before the current one.
    bool avLogWritten = false; ///< close() wrote PlaybackConfig::avLogPath (once).
    std::optional<haptic_task::HapticStats> lastHapticStats;
    /// The decode thread's DecoderThread::readProgress() when it was last seen to change, and
    /// when: the same odd value for PlaybackConfig::liveSilenceSeconds is a silent live stream.
    std::uint64_t silentProgress = 0;
    platform::TimePoint silentSince{};

    RenderLoop loop;                                        ///< The render thread's body.
    std::unique_ptr<platform::RealtimeThread> renderThread; ///< kRenderThread, from the first open.

    Impl(const PlaybackConfig &c, const PlaybackHal &h)
        : RenderShared(c.stereoMode), config(c), hal(h), clock(*h.clock),
          hapticsEnabled(c.hapticsEnabled), stiffness(c.haptics.renderer.stiffness),
          volume(c.audio.volume), mute(c.audio.mute), loop(*this, config, *h.display, *h.clock)
    {
    }

    /// Hands \a next (may be null) to the render thread and waits until it dropped every frame of
    /// the previous session.
    void switchSession(Session *next)
    {
        RenderShared::switchSession(next, static_cast<bool>(renderThread));
    }

    void tearDown()
    {
        opener.abandon();
        switchSession(nullptr);
        if (!owned)
            return;
        if (owned->task) {
            owned->task->stop();
            lastHapticStats = owned->task->stats();
        }
        if (owned->decoder)
            owned->decoder->stop();
        if (owned->receiver)
            setReceiverStats(owned->receiver->stats());
        if (owned->audio)
            audioBefore = addedAudioStats(audioBefore, owned->audio->stats());
        owned.reset();
    }

    /// Starts the render thread once. \return an error text, or empty.
    std::string startRenderThread()
    {
        if (renderThread)
            return {};
        auto t = std::make_unique<platform::RealtimeThread>(
            platform::kRenderThread, platform::kPlainThreadOptions,
            [this](platform::StopToken) { loop.run(); });
        if (auto r = t->start(); !r)
            return std::string("cannot start the render thread: ") + r.error().what;
        renderThread = std::move(t);
        return {};
    }
};

/// Writes PlaybackConfig::avLogPath from \a m's A/V offsets (after the render thread ended).
/// \return why it could not be written, or empty.
std::string writeAvLog(const Playback::Impl &m);

/// The sound of \a s, when the input has some, the player has an audio output and the source can
/// be read twice (a note in \a info says why not otherwise). Never fails the open: the input then
/// plays without sound. Main thread.
void attachAudio(Playback::Impl &m, Session &s, PlaybackInfo &info);

} // namespace depthtouch::playback
