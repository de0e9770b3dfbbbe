/// \file
/// \brief The StateMachine's notifications from the pipeline, its playlist and mpv's file events
/// (start-file, file-loaded, end-file with its reason, playback-restart, idle): see
/// state_machine.h. Reference: mpv's manual, "List of Input Commands" (loadfile, playlist-next,
/// playlist-prev, stop) and "List of events".

#include <cstring>
#include <string>
#include <utility>

#include "depthtouch/player/state_machine.h"

namespace depthtouch::player {

namespace {

bool active(PlayerState s) noexcept
{
    return s == PlayerState::Opening || s == PlayerState::Playing || s == PlayerState::Paused;
}

} // namespace

bool StateMachine::quitting() const noexcept
{
    return endReason_ != nullptr && std::strcmp(endReason_, "quit") == 0;
}

void StateMachine::replacePlaylist(const std::string &url)
{
    playlist_.clear();
    playlist_.push_back({url, nextEntryId_++});
    current_ = -1;
}

CommandOutcome StateMachine::openEntry(std::size_t index)
{
    const bool wasActive = active(state_);
    if (wasActive) {
        const Result<void> stopped = actions_.stop();
        if (!stopped)
            return refuseOrFail("stop", stopped);
    }
    const std::string url = playlist_[index].url;
    const Result<void> r = actions_.open(url);
    if (!r && isRefusal(r.error().code) && wasActive) {
        // The file that played was stopped for this one: it ended.
        setState(PlayerState::Stopped);
        return CommandOutcome::refuse(std::string("open refused: ") + r.error().what);
    }
    if (!r)
        return refuseOrFail("open", r);
    current_ = static_cast<std::ptrdiff_t>(index);
    url_ = url;
    beginFile();
    setState(PlayerState::Opening);
    return CommandOutcome::accept();
}

CommandOutcome StateMachine::refuseOrFail(const char *what, const Result<void> &r)
{
    if (isRefusal(r.error().code))
        return CommandOutcome::refuse(std::string(what) + " refused: " + r.error().what);
    fail(std::string(what) + " failed: " + r.error().what, r.error().code);
    return CommandOutcome::refuse(errorReason_);
}

void StateMachine::beginFile()
{
    if (fileActive_)
        endFile("stop");
    fileActive_ = true;
    fileLoaded_ = false;
    activeEntryId_ = current_ >= 0 ? playlist_[static_cast<std::size_t>(current_)].id : 0;
    emit(PlayerEventKind::StartFile);
}

void StateMachine::endFile(const char *reason, std::string detail)
{
    fileActive_ = false;
    fileLoaded_ = false;
    endDetail_ = std::move(detail);
    emit(PlayerEventKind::FileEnded, reason);
    endDetail_.clear();
}

void StateMachine::enterIdle()
{
    current_ = -1;
    emit(PlayerEventKind::Idle);
}

CommandOutcome StateMachine::loadFile(const Command &command)
{
    if (command.loadMode == LoadMode::Replace) {
        replacePlaylist(command.url);
        return openEntry(0);
    }
    playlist_.push_back({command.url, nextEntryId_++});
    // append-play starts the entry when nothing plays (mpv: "if nothing is currently playing").
    if (command.loadMode == LoadMode::AppendPlay && !active(state_))
        return openEntry(playlist_.size() - 1);
    return CommandOutcome::accept();
}

CommandOutcome StateMachine::playlistStep(const Command &command)
{
    const std::ptrdiff_t target = current_ + command.step;
    if (current_ < 0 || target < 0 || target >= static_cast<std::ptrdiff_t>(playlist_.size())) {
        // mpv: weak (the default) does nothing at the playlist's end, force stops there.
        if (command.force && active(state_)) {
            const Result<void> stopped = actions_.stop();
            if (!stopped)
                return refuseOrFail("stop", stopped);
            setState(PlayerState::Stopped);
            return CommandOutcome::accept();
        }
        return CommandOutcome::refuse(command.step > 0 ? "no next entry in the playlist"
                                                       : "no previous entry in the playlist");
    }
    return openEntry(static_cast<std::size_t>(target));
}

bool StateMachine::onOpened()
{
    if (state_ != PlayerState::Opening)
        return false;
    enterOrFail(PlayerState::Playing, "start", actions_.startPlayback());
    return true;
}

bool StateMachine::onOpenFailed(std::string_view reason, Errc kind)
{
    if (state_ != PlayerState::Opening)
        return false;
    fail("open failed: " + std::string(reason), kind);
    return true;
}

bool StateMachine::onFailure(std::string_view reason)
{
    if (state_ != PlayerState::Opening && state_ != PlayerState::Playing &&
        state_ != PlayerState::Paused)
        return false;
    fail(std::string(reason));
    return true;
}

bool StateMachine::onEndOfStream()
{
    if (state_ != PlayerState::Playing && state_ != PlayerState::Paused)
        return false;
    if (loop_) {
        // As mpv's --loop-file: the file has not ended for a client, it was seeked to its start.
        const Result<void> r = actions_.restartForLoop();
        if (r) {
            emit(PlayerEventKind::Seeked, "loop");
            emit(PlayerEventKind::PlaybackRestart);
        } else
            fail(std::string("loop seek failed: ") + r.error().what);
        return true;
    }
    const Result<void> r = actions_.stop();
    eofReached_ = true;
    emit(PlayerEventKind::EndOfFile, "eof");
    endOfStream(r);
    return true;
}

void StateMachine::endOfStream(const Result<void> &stopped)
{
    const std::ptrdiff_t next = current_ + 1;
    const bool more = current_ >= 0 && next < static_cast<std::ptrdiff_t>(playlist_.size());
    endReason_ = "eof";
    endDetail_ = "eof";
    advancing_ = more && stopped;
    enterOrFail(PlayerState::Stopped, "stop", stopped);
    endReason_ = nullptr;
    advancing_ = false;
    // mpv: at the end of a file the playlist's next entry plays.
    if (more && state_ == PlayerState::Stopped) {
        const CommandOutcome out = openEntry(static_cast<std::size_t>(next));
        if (!out.accepted && state_ == PlayerState::Stopped)
            enterIdle();
    }
}

} // namespace depthtouch::player
