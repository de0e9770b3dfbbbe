/// \file
/// \brief RenderShared: see render_shared.h. The only file that takes its mutex.

#include "render_shared.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <utility>

#include <glm/geometric.hpp>

#include "depthtouch/platform/percentile.h"

namespace depthtouch::playback {

using platform::percentile;

namespace {
/// Entries kept of each per-frame series (about 18 minutes at 60 fps).
constexpr std::size_t kSeriesLength = std::size_t{1} << 16;

/// Appends \a v to \a series while it has room (no allocation after the reserve).
void append(std::vector<double> &series, double v)
{
    if (series.size() < series.capacity())
        series.push_back(v);
}
} // namespace

RenderShared::RenderShared(player::StereoMode stereoMode) : stereoMode_(stereoMode)
{
    renderMs_.reserve(kSeriesLength);
    meshTriangles_.reserve(kSeriesLength);
    avOffsets_.ms.reserve(kSeriesLength);
    avOffsets_.at.reserve(kSeriesLength);
    avOffsets_.pts.reserve(kSeriesLength);
}

// --- Main thread ---------------------------------------------------------------------------------

void RenderShared::switchSession(Session *next, bool waitForRenderThread)
{
    std::unique_lock<std::mutex> lock(mutex_);
    session_ = next;
    playing_ = false;
    paused_ = false;
    endOfStream_ = false;
    const std::uint64_t gen = ++sessionGen_;
    cv_.notify_all();
    if (waitForRenderThread)
        cv_.wait(lock, [&] { return sessionAck_ >= gen || quit_; });
}

void RenderShared::quit()
{
    std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
    cv_.notify_all();
}

Result<void> RenderShared::startPlaying()
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (session_ == nullptr)
        return Error(Errc::InvalidState, "nothing is open");
    playing_ = true;
    paused_ = false;
    cv_.notify_all();
    return {};
}

Result<void> RenderShared::setPaused(bool paused, const char *nothingOpen)
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (session_ == nullptr)
        return Error(Errc::InvalidState, nothingOpen);
    paused_ = paused;
    return {};
}

Result<void> RenderShared::seek(double seconds, player::SeekMode mode)
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (session_ == nullptr)
        return Error(Errc::InvalidState, "nothing is open");
    const double start = session_->haveStart ? session_->startPts : 0.0;
    double target = mode == player::SeekMode::Absolute ? seconds : position_ + seconds;
    target = std::max(0.0, target);
    const double duration = ptsSeconds(session_->receiver->info().duration);
    if (duration > 0.0)
        target = std::min(target, std::max(0.0, duration - session_->period));
    seekTarget_ = start + target;
    position_ = target;
    ++seekGen_;
    ++stats_.seeks;
    endOfStream_ = false;
    return {};
}

void RenderShared::setStereoMode(player::StereoMode mode)
{
    std::lock_guard<std::mutex> lock(mutex_);
    stereoMode_ = mode;
}

void RenderShared::setRemoteConnected(bool connected)
{
    std::lock_guard<std::mutex> lock(mutex_);
    remoteConnected_ = connected;
}

player::PlayerActions::MediaPosition RenderShared::mediaPosition() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    player::PlayerActions::MediaPosition at;
    if (session_ == nullptr)
        return at;
    at.timePos = position_;
    const double duration = ptsSeconds(session_->receiver->info().duration);
    if (duration > 0.0)
        at.duration = duration;
    return at;
}

double RenderShared::hapticForce() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (session_ == nullptr || session_->task == nullptr)
        return std::numeric_limits<double>::quiet_NaN();
    return glm::length(session_->task->lastForce());
}

std::optional<bool> RenderShared::hapticDeviceConnected() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (session_ == nullptr || session_->task == nullptr)
        return std::nullopt;
    return session_->task->deviceConnected();
}

double RenderShared::position() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return position_;
}

void RenderShared::countOpen()
{
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.opens;
}

std::string RenderShared::takeDisplayError()
{
    std::lock_guard<std::mutex> lock(mutex_);
    return std::exchange(displayError_, std::string());
}

RenderShared::Report RenderShared::takeReport()
{
    std::lock_guard<std::mutex> lock(mutex_);
    Report r;
    r.failure = std::exchange(failure_, std::string());
    r.endOfStream = std::exchange(endOfStream_, false);
    return r;
}

void RenderShared::setReceiverStats(const receiver::ReceiverStats &stats)
{
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.receiver = stats;
}

void RenderShared::setAvLogLost(std::string why)
{
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.avLogLost = std::move(why);
}

bool RenderShared::snapshotLost() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return !stats_.snapshotLost.empty();
}

PlaybackStats RenderShared::stats() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    PlaybackStats s = stats_;
    s.renderMsP50 = percentile(renderMs_, 0.50);
    s.renderMsP99 = percentile(renderMs_, 0.99);
    s.meshTrianglesP50 = percentile(meshTriangles_, 0.50);
    if (!avOffsets_.ms.empty()) {
        s.avOffsetMsP50 = percentile(avOffsets_.ms, 0.50);
        std::vector<double> magnitude(avOffsets_.ms);
        for (double &v : magnitude)
            v = std::abs(v);
        s.avOffsetMsP99 = percentile(magnitude, 0.99);
    }
    return s;
}

RenderShared::AvOffsets RenderShared::avOffsets() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return avOffsets_;
}

// --- Render thread -------------------------------------------------------------------------------

RenderShared::Turn RenderShared::nextTurn(std::uint64_t adoptedGen)
{
    std::unique_lock<std::mutex> lock(mutex_);
    Turn t;
    if (quit_) {
        t.step = Turn::Step::Quit;
        return t;
    }
    if (adoptedGen != sessionGen_) {
        t.step = Turn::Step::Adopt;
        t.session = session_;
        t.gen = sessionGen_;
        t.seekGen = seekGen_;
        return t;
    }
    if (session_ == nullptr || !playing_) {
        cv_.wait_for(lock, std::chrono::milliseconds(20));
        t.step = Turn::Step::Idle;
        return t;
    }
    t.step = Turn::Step::Play;
    t.commands.paused = paused_;
    t.commands.seekGen = seekGen_;
    t.commands.seekTo = seekTarget_;
    t.commands.mode = stereoMode_;
    t.commands.remoteConnected = remoteConnected_;
    return t;
}

void RenderShared::acknowledgeSession(std::uint64_t gen, std::string displayError)
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (!displayError.empty())
        displayError_ = std::move(displayError);
    sessionAck_ = std::max(sessionAck_, gen);
    cv_.notify_all();
}

void RenderShared::acknowledgeAll()
{
    std::lock_guard<std::mutex> lock(mutex_);
    sessionAck_ = sessionGen_;
    cv_.notify_all();
}

void RenderShared::setStart(Session &s, double pts)
{
    std::lock_guard<std::mutex> lock(mutex_);
    s.startPts = pts;
    s.haveStart = true;
}

void RenderShared::addAvOffset(double offsetMs, platform::TimePoint shownAt, double pts)
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (avOffsets_.ms.size() >= avOffsets_.ms.capacity())
        return;
    if (avOffsets_.ms.empty())
        firstAvOffset_ = shownAt;
    avOffsets_.ms.push_back(offsetMs);
    avOffsets_.at.push_back(platform::toSeconds(shownAt - firstAvOffset_));
    avOffsets_.pts.push_back(pts);
}

void RenderShared::countFrameReceived()
{
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.framesReceived;
}

void RenderShared::reportFailure(std::string why)
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (failure_.empty())
        failure_ = std::move(why);
}

void RenderShared::reportEndOfStream()
{
    std::lock_guard<std::mutex> lock(mutex_);
    endOfStream_ = true;
    ++stats_.endsOfStream;
}

void RenderShared::countDropped()
{
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.framesDropped;
}

void RenderShared::countShown(double lateSeconds, double period)
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (lateSeconds > period)
        ++stats_.framesLate;
    stats_.lateMsMax = std::max(stats_.lateMsMax, 1e3 * lateSeconds);
}

void RenderShared::countDepthPairPublished()
{
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.depthPairsPublished;
}

void RenderShared::countPresented(const PresentedFrame &f)
{
    std::lock_guard<std::mutex> lock(mutex_);
    PlaybackStats &s = stats_;
    if (f.draw.preparedAhead)
        ++s.framesPreparedAhead;
    if (f.draw.recorded)
        ++s.framesRecorded;
    if (f.draw.snapshotWritten)
        ++s.snapshotsWritten;
    if (!f.draw.recordError.empty()) {
        failure_ = f.draw.recordError;
        s.recordingLost = f.draw.recordError;
    }
    if (!f.draw.snapshotError.empty() && s.snapshotLost.empty())
        s.snapshotLost = f.draw.snapshotError;
    if (f.lod) {
        s.lodBudget = f.lod->budget;
        if (f.lod->limited)
            ++s.framesLodLimited;
        append(meshTriangles_, f.lod->triangles);
    }
    if (!f.draw.drawn)
        ++s.renderErrors;
    if (f.presented) {
        ++s.framesPresented;
        if (f.tuneInSeconds)
            s.tuneInSeconds = *f.tuneInSeconds;
    } else {
        ++s.presentErrors;
        // The window was closed or the display went away: playback cannot go on.
        if (!f.displayLost.empty() && failure_.empty())
            failure_ = f.displayLost;
    }
    position_ = f.position;
    s.playingSeconds = f.playingSeconds;
    s.presentedFps =
        f.playingSeconds > 0 ? static_cast<double>(s.framesPresented) / f.playingSeconds : 0.0;
    append(renderMs_, f.drawMs);
    s.zeroCopy = f.zeroCopy;
    s.colorFramesImported = f.colorFramesImported;
    s.colorFramesDmaBufUploaded = f.colorFramesDmaBufUploaded;
}

void RenderShared::addLostOutputs(const OutputsLost &lost)
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (!lost.recording.empty() && stats_.recordingLost.empty())
        stats_.recordingLost = lost.recording;
    if (!lost.snapshot.empty() && stats_.snapshotLost.empty())
        stats_.snapshotLost = lost.snapshot;
}

} // namespace depthtouch::playback
