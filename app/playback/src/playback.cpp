/// \file
/// \brief Playback: see playback.h. The main thread's side: open (the async opener, then the
/// session: receiver, decode thread, depth hand-off, haptic task), the PlayerActions commands
/// handed to the render thread (RenderShared), reports and counters. The render thread's side is
/// render_loop.cpp.

#include "depthtouch/playback/playback.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <system_error>

#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/thread_config.h"
#include "depthtouch/options/option_range.h"

#include "depth_view.h"
#include "playback_impl.h"
#include "presenter.h"

namespace depthtouch::playback {

// ---------------------------------------------------------------------------------------------

Playback::Playback(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Result<std::unique_ptr<Playback>> Playback::create(const PlaybackConfig &config,
                                                   const PlaybackHal &hal)
{
    if (!hal.makeSource || !hal.makeDecoder || hal.display == nullptr || hal.clock == nullptr)
        return Error(Errc::InvalidArgument, "playback needs a media source, decoders, a display "
                                            "and a clock");
    if (auto r = config.haptics.validate(); !r)
        return r.error();
    if (config.outputWidth < 0 || config.outputHeight < 0 ||
        config.outputWidth > PlaybackConfig::kMaxOutputSize ||
        config.outputHeight > PlaybackConfig::kMaxOutputSize)
        return Error(Errc::InvalidArgument, "output size out of range");
    if (config.meshStep < 0 || config.meshStep > PlaybackConfig::kMaxMeshStep ||
        (config.meshStep & (config.meshStep - 1)) != 0)
        return Error(Errc::InvalidArgument, "mesh step must be 0 or a power of two up to 64");
    if (!(config.maxLateness >= 0.0 && config.maxLateness <= PlaybackConfig::kMaxLateness))
        return Error(Errc::InvalidArgument, "max lateness must be in [0, 10] s");
    auto impl = std::make_unique<Impl>(config, hal);
    return std::unique_ptr<Playback>(new Playback(std::move(impl)));
}

Playback::~Playback()
{
    close();
}

void Playback::close()
{
    impl_->tearDown();
    impl_->quit();
    if (impl_->renderThread && impl_->renderThread->joinable())
        impl_->renderThread->join();
    if (!impl_->config.avLogPath.empty() && !impl_->avLogWritten) {
        impl_->avLogWritten = true;
        impl_->setAvLogLost(writeAvLog(*impl_));
    }
}

Result<void> Playback::open(std::string_view url)
{
    return startOpening(url, false);
}

Result<void> Playback::awaitNextSender(std::string_view url)
{
    return startOpening(url, true);
}

Result<void> Playback::startOpening(std::string_view url, bool untilOpened)
{
    Impl &m = *impl_;
    m.tearDown();
    m.openDone = false;
    m.openError.clear();
    m.openErrorKind = Errc::InvalidArgument;
    // The source's open and probe may block (a FIFO without a writer, a silent stream): they run
    // on the opener's thread, and report() finishes the open when they are done.
    std::string why;
    if (!m.opener.start(m.hal.makeSource, std::string(url), m.hal.makeDecoder, m.config.receiver,
                        why, untilOpened))
        return Error(Errc::OutOfResources, "cannot start the thread that opens the input");
    m.openingUrl = std::string(url);
    m.openStarted = m.clock.now();
    return {};
}

namespace {

/// What the receiver found, for the summary (PlaybackInfo), and the frame period (s).
PlaybackInfo describe(const receiver::ReceiverInfo &ri, const std::string &url, double &period)
{
    PlaybackInfo info;
    info.url = url;
    info.mode = receiver::receiverModeName(ri.mode);
    info.notes = ri.notes;
    if (ri.hasDepth) {
        info.depthWidth = ri.depth.width;
        info.depthHeight = ri.depth.height;
    }
    if (ri.hasColor) {
        info.colorWidth = ri.color.width;
        info.colorHeight = ri.color.height;
    }
    const hal::Pts p = ri.hasColor ? ri.colorPeriod : ri.depthPeriod;
    period = p.count() > 0 ? ptsSeconds(p) : 1.0 / 30.0;
    info.fps = 1.0 / period;
    return info;
}

/// The display's size for the stream on the first open (opened by the render thread): --size, or
/// the natural size of the starting stereo layout for W×H depth: side by side 2W×H, top and bottom
/// W×2H, one picture (mono, anaglyph, row-interleaved) W×H; at most 3840×2160.
hal::DisplayConfig displayConfigFor(const receiver::ReceiverInfo &ri, const PlaybackConfig &config)
{
    const hal::StreamInfo &main = ri.hasColor ? ri.color : ri.depth;
    const int w = ri.hasDepth ? ri.depth.width : main.width;
    const int h = ri.hasDepth ? ri.depth.height : main.height;
    const int across = config.stereoMode == player::StereoMode::SideBySide ? 2 : 1;
    const int down = config.stereoMode == player::StereoMode::TopAndBottom ? 2 : 1;
    hal::DisplayConfig dc;
    dc.width = config.outputWidth > 0 ? config.outputWidth : std::min(across * w, 3840);
    dc.height = config.outputHeight > 0 ? config.outputHeight : std::min(down * h, 2160);
    dc.refreshHz = config.refreshHz;
    return dc;
}

/// The haptic task on the depth frames, when there are depth and a device (else a note says why
/// not). \return an error text, or empty.
std::string attachHaptics(Playback::Impl &m, Session &s, PlaybackInfo &info)
{
    const receiver::ReceiverInfo &ri = s.receiver->info();
    if (!ri.hasDepth) {
        info.notes.emplace_back("no depth stream: playing flat (2D) with haptics off");
        return {};
    }
    if (m.hal.device == nullptr) {
        info.notes.emplace_back("no haptic device: playing without haptics");
        return {};
    }
    auto handoff = haptic_task::DepthHandoff::create(
        ri.depth.width, ri.depth.height, sampleFormatOf(ri.depthFormat), ri.hasMaterial);
    if (!handoff)
        return std::string("cannot allocate the depth frames: ") + handoff.error().what;
    s.handoff = std::move(*handoff);
    haptic_task::HapticTaskConfig tc = m.config.haptics;
    tc.startEnabled = m.hapticsEnabled;
    auto task = haptic_task::HapticTask::create(tc, *m.hal.device, *s.handoff, m.clock);
    if (!task)
        return std::string("cannot create the haptic task: ") + task.error().what;
    s.task = std::move(*task);
    s.task->setStiffness(m.stiffness);
    info.haptics = true;
    if (ri.hasMaterial)
        info.notes.emplace_back(
            "material track: per-pixel stiffness and friction under the finger");
    return {};
}

} // namespace

void Playback::finishOpen(std::unique_ptr<receiver::Receiver> rec)
{
    Impl &m = *impl_;
    // A thread that cannot be started is the system's failure (exit 1), the rest the input's.
    auto fail = [&](std::string why, Errc kind = Errc::InvalidArgument) {
        m.openError = std::move(why);
        m.openErrorKind = kind;
    };

    auto s = std::make_unique<Session>();
    s->openStarted = m.openStarted;
    s->receiver = std::move(rec);
    const receiver::ReceiverInfo &ri = s->receiver->info();
    PlaybackInfo info = describe(ri, m.openingUrl, s->period);
    if (std::string why = attachHaptics(m, *s, info); !why.empty())
        return fail(std::move(why));
    s->displayConfig = displayConfigFor(ri, m.config);
    if (std::string why = m.startRenderThread(); !why.empty())
        return fail(std::move(why), Errc::OutOfResources);

    s->live = !s->receiver->source().info().seekable;
    s->adaptive = !s->receiver->source().info().renditions.empty();
    attachAudio(m, *s, info);
    if (!s->audio)
        s->masterClock = m.hal.masterClock;
    m.silentProgress = 0; // the new decode thread counts from 0
    s->decoder = std::make_unique<receiver::DecoderThread>(*s->receiver);
    if (auto r = s->decoder->start(); !r)
        return fail(std::string("cannot start the decode thread: ") + r.error().what,
                    Errc::OutOfResources);
    if (s->task) {
        if (auto r = s->task->start(); !r) {
            s->decoder->stop();
            return fail(std::string("cannot start the haptic task: ") + r.error().what,
                        r.error().code == Errc::OutOfResources ? Errc::OutOfResources
                                                               : Errc::InvalidArgument);
        }
    }
    m.owned = std::move(s);
    m.countOpen();
    m.switchSession(m.owned.get());
    if (std::string why = m.takeDisplayError(); !why.empty()) {
        m.tearDown();
        return fail(why);
    }
    const hal::Size size = m.hal.display->size();
    info.outputWidth = size.width;
    info.outputHeight = size.height;
    info.gl = presenterDraws(*m.hal.display);
    if (!m.config.recordPath.empty() && !info.gl)
        info.notes.emplace_back("not recording: the display has no OpenGL ES context to read "
                                "frames from");
    info_ = std::move(info);
    m.openDone = true;
}

Result<void> Playback::startPlayback()
{
    impl_->osdEvents.fetch_add(1, std::memory_order_relaxed);
    return impl_->startPlaying();
}

Result<void> Playback::pause()
{
    impl_->osdEvents.fetch_add(1, std::memory_order_relaxed);
    return impl_->setPaused(true, "nothing is playing");
}

Result<void> Playback::resume()
{
    impl_->osdEvents.fetch_add(1, std::memory_order_relaxed);
    return impl_->setPaused(false, "nothing is open");
}

Result<void> Playback::stop()
{
    impl_->tearDown();
    return {};
}

Result<void> Playback::seek(double seconds, player::SeekMode mode)
{
    impl_->osdEvents.fetch_add(1, std::memory_order_relaxed);
    return seekTo(seconds, mode);
}

player::PlayerActions::MediaPosition Playback::mediaPosition() const
{
    return impl_->mediaPosition();
}

double Playback::hapticForce() const
{
    return impl_->hapticForce();
}

std::optional<bool> Playback::hapticDeviceConnected() const
{
    return impl_->hapticDeviceConnected();
}

Result<void> Playback::restartForLoop()
{
    return seekTo(0.0, player::SeekMode::Absolute);
}

Result<void> Playback::seekTo(double seconds, player::SeekMode mode)
{
    if (!std::isfinite(seconds))
        return Error(Errc::InvalidArgument, "seek: not a number");
    return impl_->seek(seconds, mode);
}

Result<void> Playback::setStereoMode(player::StereoMode mode)
{
    impl_->osdEvents.fetch_add(1, std::memory_order_relaxed);
    impl_->setStereoMode(mode);
    return {};
}

Result<void> Playback::setHapticsEnabled(bool enabled)
{
    impl_->osdEvents.fetch_add(1, std::memory_order_relaxed);
    impl_->hapticsEnabled = enabled;
    if (impl_->owned && impl_->owned->task)
        impl_->owned->task->setEnabled(enabled);
    return {};
}

Result<void> Playback::setStiffness(double newtonsPerMetre)
{
    impl_->osdEvents.fetch_add(1, std::memory_order_relaxed);
    static_assert(options::kStiffness.min == 100.0 && options::kStiffness.max == 3000.0,
                  "the message below says the range");
    if (!options::kStiffness.contains(newtonsPerMetre))
        return Error(Errc::InvalidArgument, "stiffness must be in [100, 3000] N/m");
    impl_->stiffness = newtonsPerMetre;
    if (impl_->owned && impl_->owned->task)
        impl_->owned->task->setStiffness(newtonsPerMetre);
    return {};
}

Result<void> Playback::recenter()
{
    impl_->osdEvents.fetch_add(1, std::memory_order_relaxed);
    if (!impl_->owned || !impl_->owned->task)
        return Error(Errc::InvalidState, "no haptic task is running");
    impl_->owned->task->requestReseat();
    return {};
}

void Playback::showRemoteConnected(std::optional<bool> connected)
{
    impl_->osdEvents.fetch_add(1, std::memory_order_relaxed);
    impl_->setRemoteConnected(connected.value_or(true));
}

Result<void> Playback::showProgress()
{
    impl_->osdEvents.fetch_add(1, std::memory_order_relaxed);
    return {};
}

Result<void> Playback::snapshot()
{
    if (impl_->config.snapshotDir.empty())
        return Error(Errc::InvalidState, "no snapshot folder: play with --snapshot-dir");
    if (!presenterDraws(*impl_->hal.display))
        return Error(Errc::NotSupported, "this display draws no picture to save");
    // Refused now (playback goes on) rather than answered as a success for a PNG that cannot be
    // written: a folder that takes no file (made read-only while playing) or a snapshot already
    // lost (a full disk; that loss makes the exit code 1).
    std::error_code ec;
    std::filesystem::path folder(impl_->config.snapshotDir);
    while (!std::filesystem::exists(folder, ec) && folder.has_parent_path() &&
           folder.parent_path() != folder)
        folder = folder.parent_path(); // made with its parents at the first snapshot
    if (!std::filesystem::exists(folder, ec))
        folder = ".";
    if (auto w = platform::checkFolderWritable(folder.string()); !w)
        return Error(Errc::InvalidState, "the snapshot folder takes no file (read-only?)",
                     w.error().sysErrno);
    if (impl_->snapshotLost())
        return Error(Errc::InvalidState, "an earlier snapshot could not be written (disk full?)");
    requestSnapshot();
    return {};
}

void Playback::report(player::StateMachine &machine)
{
    Impl &m = *impl_;
    if (std::optional<AsyncOpener::Outcome> opened = m.opener.poll()) {
        if (opened->receiver)
            finishOpen(std::move(opened->receiver));
        else {
            m.openError = std::move(opened->error);
            m.openErrorKind = opened->kind;
        }
    }
    if (m.openDone) {
        m.openDone = false;
        machine.onOpened();
    }
    if (!m.openError.empty()) {
        const std::string why = std::move(m.openError);
        m.openError.clear();
        machine.onOpenFailed(why, m.openErrorKind);
        m.openErrorKind = Errc::InvalidArgument;
    }
    const RenderShared::Report r = m.takeReport();
    if (!r.failure.empty())
        machine.onFailure(r.failure);
    if (r.endOfStream)
        machine.onEndOfStream();
    else
        watchSilence(machine);
}

void Playback::watchSilence(player::StateMachine &machine)
{
    Impl &m = *impl_;
    if (!m.owned || !m.owned->live || m.owned->adaptive || !m.owned->decoder ||
        !(m.config.liveSilenceSeconds > 0.0))
        return;
    const std::uint64_t progress = m.owned->decoder->readProgress();
    const platform::TimePoint now = m.clock.now();
    // Even: the decode thread is not waiting on the source; a new odd value: a new wait.
    if (progress % 2 == 0 || progress != m.silentProgress) {
        m.silentProgress = progress;
        m.silentSince = now;
        return;
    }
    // A slow stream (a frame every few seconds) is not silent between its frames.
    const double limit = std::max(m.config.liveSilenceSeconds, 4.0 * m.owned->period);
    if (platform::toSeconds(now - m.silentSince) < limit)
        return;
    const player::PlayerState st = machine.state();
    if (st != player::PlayerState::Playing && st != player::PlayerState::Paused)
        return;
    m.silentProgress = 0;
    machine.onStreamSilent();
}

PlaybackStats Playback::stats() const
{
    PlaybackStats s = impl_->RenderShared::stats();
    if (impl_->owned && impl_->owned->decoder)
        s.receiver = impl_->owned->decoder->stats();
    AudioStats a = impl_->audioBefore;
    if (impl_->owned && impl_->owned->audio)
        a = addedAudioStats(a, impl_->owned->audio->stats());
    s.audioUnderruns = a.underruns;
    s.audioDelayMs = a.delaySeconds * 1e3;
    s.audioLost = a.lost;
    return s;
}

haptic_task::HapticTask *Playback::hapticTask() noexcept
{
    return impl_->owned ? impl_->owned->task.get() : nullptr;
}

std::optional<haptic_task::HapticStats> Playback::hapticStats()
{
    if (impl_->owned && impl_->owned->task)
        return impl_->owned->task->stats();
    return impl_->lastHapticStats;
}

double Playback::position() const noexcept
{
    return impl_->RenderShared::position();
}

void Playback::requestSnapshot() noexcept
{
    impl_->snapshotRequest.store(true);
}

} // namespace depthtouch::playback
