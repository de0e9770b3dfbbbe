#pragma once
/// \file
/// \brief Playback::Impl: the player's state shared by the main thread's files (playback.cpp, the
/// open and the commands; playback_audio.cpp, the sound) and handed to the render thread as its
/// RenderShared. Private to dt_playback.
///
/// Thread-safety: as playback.h; the RenderShared part under its mutex.

#include <memory>
#include <optional>
#include <string>

#include "depthtouch/platform/realtime_thread.h"
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
        : config(c), hal(h), clock(*h.clock), hapticsEnabled(c.hapticsEnabled),
          stiffness(c.haptics.renderer.stiffness), volume(c.audio.volume), mute(c.audio.mute),
          loop(*this, config, *h.display, *h.clock)
    {
        stereoMode = c.stereoMode;
        renderMs.reserve(std::size_t{1} << 16);
        meshTriangles.reserve(std::size_t{1} << 16);
        avOffsetMs.reserve(std::size_t{1} << 16);
        avOffsetAt.reserve(std::size_t{1} << 16);
        avOffsetPts.reserve(std::size_t{1} << 16);
    }

    /// Hands \a next (may be null) to the render thread and waits until it dropped every frame of
    /// the previous session.
    void switchSession(Session *next)
    {
        std::unique_lock<std::mutex> lock(mutex);
        session = next;
        playing = false;
        paused = false;
        endOfStream = false;
        const std::uint64_t gen = ++sessionGen;
        cv.notify_all();
        if (renderThread)
            cv.wait(lock, [&] { return sessionAck >= gen || quit; });
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
        {
            std::lock_guard<std::mutex> lock(mutex);
            stats.receiver = owned->receiver ? owned->receiver->stats() : stats.receiver;
        }
        if (owned->audio)
            audioBefore = addedAudioStats(audioBefore, owned->audio->stats());
        owned.reset();
    }

    /// Notes a command for the OSD, then runs \a change under the lock when a session is open.
    /// \return nothing, or InvalidState with \a nothingOpen (a static string) when none is.
    template <class F> Result<void> changeSession(const char *nothingOpen, F &&change)
    {
        osdEvents.fetch_add(1, std::memory_order_relaxed);
        std::lock_guard<std::mutex> lock(mutex);
        if (session == nullptr)
            return Error(Errc::InvalidState, nothingOpen);
        change();
        return {};
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
