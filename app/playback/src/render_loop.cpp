/// \file
/// \brief RenderLoop: see render_loop.h.

#include "render_loop.h"

#include <algorithm>
#include <chrono>
#include <string>

#include "depthtouch/platform/log.h"

#include "depth_view.h"

DT_LOG_CATEGORY(Playback)

namespace depthtouch::playback {

using platform::TimePoint;

namespace {
/// How far the picture's media origin may be from the master clock before it moves onto it, s:
/// well under a frame, above the jitter of a device's delay report.
constexpr double kMasterFollowSeconds = 0.002;
/// The picture's lead on the audio clock (the time from a frame's turn to its light on screen:
/// the draw and the wait for the refresh) is learnt from the measured A/V offsets: each adds this
/// share of itself to the lead, which stays within [0, kMaxLeadSeconds].
constexpr double kLeadGain = 0.1;
constexpr double kMaxLeadSeconds = 0.1;
} // namespace

void RenderLoop::Frames::dropFrames() noexcept
{
    shown = receiver::PairedFrame{};
    for (auto &p : pending)
        p = receiver::PairedFrame{};
    pendingCount = 0;
}

void RenderLoop::Frames::popFront() noexcept
{
    pending[0] = std::move(pending[1]);
    pending[1] = receiver::PairedFrame{};
    --pendingCount;
}

const double *RenderLoop::Frames::nextPts(double &storage) const noexcept
{
    if (pendingCount < 2)
        return nullptr;
    storage = ptsSeconds(pending[1].pts);
    return &storage;
}

RenderLoop::RenderLoop(RenderShared &shared, const PlaybackConfig &config, hal::Display &display,
                       platform::Clock &clock)
    : shared_(shared), config_(config), display_(display), clock_(clock),
      presenter_(makePresenter(config, display, clock, shared.snapshotRequest, shared.osdEvents)),
      frameClock_(config.maxLateness)
{
}

void RenderLoop::run()
{
    for (;;) {
        const RenderShared::Turn turn = shared_.nextTurn(frames_.gen);
        if (turn.step == RenderShared::Turn::Step::Quit)
            break;
        if (turn.step == RenderShared::Turn::Step::Adopt)
            shared_.acknowledgeSession(turn.gen, adoptSession(turn));
        else if (turn.step == RenderShared::Turn::Step::Play)
            play(*frames_.session, turn.commands);
    }
    leave();
}

/// A new session (\a turn's; the main thread waits for its acknowledgement): drops every frame
/// of the old one and restarts the clock. \return why the display could not be opened, or empty.
std::string RenderLoop::adoptSession(const RenderShared::Turn &turn)
{
    frames_.dropFrames();
    frames_ = Frames{};
    frames_.session = turn.session;
    frames_.gen = turn.gen;
    frames_.seekSeen = turn.seekGen;
    frameClock_ = FrameClock(config_.maxLateness);
    presenter_->newSession();
    if (frames_.session != nullptr && display_.state() != hal::Display::State::Open)
        return openDisplay();
    return {};
}

/// The display's first open, sized for the first stream, its GL context made current on this
/// thread. \return why it could not be opened, or empty.
std::string RenderLoop::openDisplay()
{
    if (auto r = display_.open(frames_.session->displayConfig); !r)
        return std::string("cannot open the display: ") + r.error().what;
    if (display_.capabilities().hasGlesContext) {
        if (auto c = display_.makeCurrent(); !c)
            DT_LOG(Playback, Warning, "No GL context (%s): frames are presented undrawn",
                   c.error().what);
        else
            presenter_->contextReady();
    }
    return {};
}

/// One turn of playing: at most one frame shown, or a short sleep.
void RenderLoop::play(Session &s, const Commands &cmd)
{
    const TimePoint now = clock_.now();
    frameClock_.trackPlaying(now, cmd.paused);
    if (cmd.seekGen != frames_.seekSeen) {
        frames_.seekSeen = cmd.seekGen;
        seek(s, cmd.seekTo);
    }
    // Pause: the media clock stands still (the haptic time with it).
    if (frameClock_.holdForPause(now, cmd.paused) && s.handoff)
        s.handoff->setMediaOrigin(frameClock_.origin());
    followMaster(s, cmd.paused);
    takeFrames(s, now);
    checkDecoder(s, now);
    if (frames_.pendingCount == 0) {
        clock_.sleepFor(std::chrono::milliseconds(2));
        return;
    }
    const double pts = ptsSeconds(frames_.pending[0].pts);
    if (!s.haveStart)
        shared_.setStart(s, pts);
    rebaseAtDiscontinuity(cmd.paused);
    if (!pace(s, now, pts, cmd.paused))
        return;
    // Frame i goes on screen: the haptic task gets (depth i, depth i+1).
    frames_.shown = std::move(frames_.pending[0]);
    frames_.popFront();
    publishDepth(s);
    frames_.reseat = false;
    drawAndPresent(s, cmd, pts);
}

/// A timestamp discontinuity at pending[0] (a splice, an encoder restart, a looped feed: the
/// receiver re-based its PTS, PairedFrame::discontinuity): the media clock restarts at that frame
/// as after a seek, so it is shown at once whatever the time the jump took on a live input, and
/// the haptic clock restarts with it (the reseat path: HapticTask::requestClockRestart()), so
/// the surface does not interpolate across the splice. Waits while \a paused.
void RenderLoop::rebaseAtDiscontinuity(bool paused)
{
    receiver::PairedFrame &f = frames_.pending[0];
    if (!f.discontinuity || paused)
        return;
    f.discontinuity = false;
    if (!frameClock_.started())
        return; // the clock starts at this frame anyway
    DT_LOG(Playback, Info, "Timestamp discontinuity at %.3f s: the media clock re-bases",
           ptsSeconds(f.pts));
    frameClock_.restart();
    frames_.reseat = true;
    frames_.rebasing = true;
}

/// The master clock: the media origin (the picture's and the haptic time's) follows the time the
/// speaker plays (audio_player.h) while the sound plays, a frame's turn coming avLead_ before its
/// time so that it is on screen at its time; without sound, the clock the player is given
/// (PlaybackHal::masterClock: a GStreamer pipeline's running time), with no lead.
void RenderLoop::followMaster(Session &s, bool paused)
{
    MasterClock c;
    double lead = 0.0;
    if (s.audio) {
        s.audio->setPaused(paused);
        c = s.audio->clock();
        lead = avLead_;
    } else if (s.masterClock && !paused) {
        c = s.masterClock();
    }
    if (c.running && frameClock_.follow(c.at, c.mediaTime + lead, kMasterFollowSeconds) &&
        s.handoff)
        s.handoff->setMediaOrigin(frameClock_.origin());
}

/// The A/V offset of the frame of PTS \a pts (s) presented at \a shownAt: the media time heard
/// then minus \a pts (positive: the sound is ahead of the picture); the lead learns from it.
void RenderLoop::measureAvOffset(Session &s, TimePoint shownAt, double pts)
{
    const MasterClock c = s.audio->clock();
    if (!c.running)
        return;
    const double offset = c.mediaTime + platform::toSeconds(shownAt - c.at) - pts;
    avLead_ = std::clamp(avLead_ + kLeadGain * offset, 0.0, kMaxLeadSeconds);
    shared_.addAvOffset(offset * 1e3, shownAt, pts);
}

/// Seek: drop what was queued; the decode thread restarts at \a seekTo (s, stream timeline).
void RenderLoop::seek(Session &s, double seekTo)
{
    for (auto &p : frames_.pending)
        p = receiver::PairedFrame{};
    frames_.pendingCount = 0;
    frameClock_.restart();
    frames_.rebasing = false;
    if (s.audio)
        s.audio->halt();
    frames_.reseat = true;
    frames_.eosSent = false;
    presenter_->dropPrepared();
    s.decoder->seek(ptsFromSeconds(seekTo));
}

/// Takes up to two frames from the decode thread (never blocks), and has the next one to show made
/// ahead while this thread draws (the first, or the second when it is due already and the first
/// will be dropped).
void RenderLoop::takeFrames(Session &s, TimePoint now)
{
    while (frames_.pendingCount < 2 &&
           s.decoder->poll(frames_.pending[static_cast<std::size_t>(frames_.pendingCount)])) {
        ++frames_.pendingCount;
        frames_.anyFrame = true;
        shared_.countFrameReceived();
    }
    if (frames_.pendingCount > 0 && frameClock_.started()) {
        double nextPts = 0.0;
        const bool skipFirst = frameClock_.skipsFront(now, ptsSeconds(frames_.pending[0].pts),
                                                      frames_.nextPts(nextPts));
        presenter_->prepareAhead(frames_.pending[skipFirst ? 1 : 0], frames_.pending,
                                 frames_.pendingCount);
    }
}

/// Decoder failures, an input cut before its first frame, and the end of the stream (the last
/// frame has had its time on screen).
void RenderLoop::checkDecoder(Session &s, TimePoint now)
{
    if (s.decoder->failed())
        shared_.reportFailure(std::string("decoding failed: ") + s.decoder->error().what);
    if (frames_.pendingCount == 0 && !frames_.anyFrame && s.decoder->finished() &&
        !frames_.eosSent) {
        // The input ended before its first complete frame (a file cut after its header): a
        // failure, not a player that shows nothing for ever.
        frames_.eosSent = true;
        shared_.reportFailure("the input ended before its first complete frame (truncated?)");
    }
    if (frames_.pendingCount == 0 && !frames_.eosSent && s.decoder->finished() &&
        frames_.haveShown() &&
        frameClock_.lastFrameDone(now, ptsSeconds(frames_.shown.pts), s.period)) {
        frames_.eosSent = true;
        shared_.reportEndOfStream();
    }
}

/// The pacing decision for pending[0] (PTS \a pts, s): sleeps or drops it and \return false, or
/// \return true to show it now.
bool RenderLoop::pace(Session &s, TimePoint now, double pts, bool paused)
{
    double nextPtsStorage = 0.0;
    const bool hold = paused && !frames_.reseat && frames_.haveShown();
    const Pace p = frameClock_.pace(now, pts, frames_.nextPts(nextPtsStorage), s.period, hold);
    switch (p.step) {
    case Pace::Step::Hold:
        clock_.sleepFor(std::chrono::milliseconds(5));
        return false;
    case Pace::Step::Wait:
        clock_.sleepUntil(p.until);
        return false;
    case Pace::Step::Drop: {
        frames_.popFront();
        shared_.countDropped();
        return false;
    }
    case Pace::Step::Show:
        break;
    }
    if (p.starts) {
        if (s.handoff)
            s.handoff->setMediaOrigin(frameClock_.origin());
        return true;
    }
    shared_.countShown(p.lateSeconds, s.period);
    return true;
}

/// The shown frame's depth pair into the hand-off: only the depth frame not yet there is copied
/// (the previous pair's next frame is this pair's current one). After a seek both are copied and
/// the haptic clock restarts.
void RenderLoop::publishDepth(Session &s)
{
    if (!s.handoff || !frames_.shown.depth)
        return;
    const receiver::StoredDepthPair dp = frames_.shown.depthPair();
    if (frames_.reseat)
        s.handoff->restart();
    scene::DepthFrameView current = depthView(*dp.current, ptsSeconds(dp.currentPts));
    current.material = materialView(dp.material, current.width, current.height);
    if (dp.next != nullptr) {
        scene::DepthFrameView next = depthView(*dp.next, ptsSeconds(dp.nextPts));
        next.material = materialView(dp.materialNext, next.width, next.height);
        s.handoff->publishPair(current, &next);
    } else {
        s.handoff->publishPair(current, nullptr);
    }
    if (frames_.reseat && s.task)
        s.task->requestClockRestart();
    shared_.countDepthPairPublished();
}

/// Draws the shown frame (PTS \a pts, s), presents it, ends the preroll and counts.
void RenderLoop::drawAndPresent(Session &s, const Commands &cmd, double pts)
{
    const TimePoint drawStart = clock_.now();
    const DrawOutcome d = presenter_->draw(
        DrawInput{frames_.shown, pts, cmd.mode, cmd.paused, cmd.remoteConnected, s});
    presenter_->finishDrawing(d.drawn);
    const double drawSeconds = platform::toSeconds(clock_.now() - drawStart);
    const auto presented = display_.present();
    const std::optional<LodSample> lod = presenter_->afterPresent(
        drawSeconds, d.drawn, static_cast<bool>(presented), frameClock_.prerolling());
    const bool first = frameClock_.prerolling();
    const TimePoint shownAt = clock_.now();
    if (frameClock_.endPreroll(shownAt, pts) && s.handoff)
        s.handoff->setMediaOrigin(frameClock_.origin());
    if (first && s.audio && !frames_.rebasing)
        s.audio->start(pts); // the sound starts with the first frame on screen
    else if (s.audio && presented && !first)
        measureAvOffset(s, shownAt, pts);
    if (first)
        frames_.rebasing = false;
    count(s, d, presented, drawSeconds * 1e3, lod, pts);
}

/// The counters of one presented frame (draw time \a ms).
void RenderLoop::count(Session &s, const DrawOutcome &d, const Result<hal::PresentInfo> &presented,
                       double ms, const std::optional<LodSample> &lod, double pts)
{
    RenderShared::PresentedFrame f;
    f.draw = d;
    f.lod = lod;
    f.presented = static_cast<bool>(presented);
    if (!presented && presented.error().code == Errc::NoDevice)
        f.displayLost = std::string("the display was lost: ") + presented.error().what;
    if (presented && !s.presentedOnce) {
        s.presentedOnce = true;
        f.tuneInSeconds = platform::toSeconds(clock_.now() - s.openStarted);
    }
    f.drawMs = ms;
    f.position = pts - s.startPts;
    f.playingSeconds = frameClock_.playingSeconds(clock_.now());
    presenter_->addStats(presenterStats_);
    f.zeroCopy = presenterStats_.zeroCopy;
    f.colorFramesImported = presenterStats_.colorFramesImported;
    f.colorFramesDmaBufUploaded = presenterStats_.colorFramesDmaBufUploaded;
    shared_.countPresented(f);
}

/// Leaving: drop frames; GL objects go while the context is current.
void RenderLoop::leave()
{
    frames_.dropFrames();
    shared_.acknowledgeAll();
    shared_.addLostOutputs(presenter_->shutdown());
    display_.close();
}

} // namespace depthtouch::playback
