#include "depthtouch/player/state_machine.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <utility>

#include "command_parsers.h"
#include "depthtouch/platform/enum_names.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Player)

namespace depthtouch::player {

const char *playerEventName(PlayerEventKind kind) noexcept
{
    static constexpr std::array<const char *, 14> kNames = {"state",
                                                            "stereo-mode",
                                                            "haptics",
                                                            "stiffness",
                                                            "loop",
                                                            "seek",
                                                            "end-of-stream",
                                                            "error",
                                                            "shutdown",
                                                            "start-file",
                                                            "file-loaded",
                                                            "end-file",
                                                            "playback-restart",
                                                            "idle"};
    static_assert(kNames.size() == static_cast<std::size_t>(PlayerEventKind::Idle) + 1);
    return platform::enumName(kind, kNames, "unknown");
}

bool isRefusal(Errc code) noexcept
{
    return code == Errc::InvalidArgument || code == Errc::NotSupported ||
           code == Errc::InvalidState || code == Errc::Busy;
}

StateMachine::StateMachine(PlayerActions &actions, PlayerSettings settings)
    : actions_(actions), url_(std::move(settings.url)), loop_(settings.loop),
      reopenWhenSilent_(settings.reopenWhenSilent), stereoMode_(settings.stereoMode),
      haptics_(settings.haptics), mute_(settings.mute), keys_(std::move(settings.keys))
{
    // Checked by the caller (play's option table); clamped here as a last safety net.
    stiffness_ =
        options::kStiffness.clamp(std::isfinite(settings.stiffness) ? settings.stiffness : 800.0);
    volume_ = options::kVolume.clamp(std::isfinite(settings.volume) ? settings.volume : 100.0);
    mute_ = settings.mute;
}

bool StateMachine::isValid(CommandId id) const noexcept
{
    return !quit_ && (commandSpec(id).validIn & stateBit(state_)) != 0;
}

CommandOutcome StateMachine::execute(const Command &command)
{
    const CommandSpec &spec = commandSpec(command.id);
    if (notifying_)
        return CommandOutcome::refuse("a command cannot be sent from an event listener");
    if (quit_)
        return CommandOutcome::refuse("the player is quitting");
    if ((spec.validIn & stateBit(state_)) == 0) {
        std::string reason;
        if (command.id == CommandId::Pause && state_ == PlayerState::Paused)
            reason = "already paused";
        else if (command.id == CommandId::Play && state_ == PlayerState::Playing)
            reason = "already playing";
        else
            reason = std::string("cannot ") + spec.name + " while " + playerStateName(state_);
        DT_LOG(Player, Debug, "Refused %s: %s", spec.name, reason.c_str());
        return CommandOutcome::refuse(std::move(reason));
    }
    DT_LOG(Player, Debug, "Command %s in state %s", commandText(command).c_str(),
           playerStateName(state_));
    return spec.handle(*this, command);
}

CommandOutcome StateMachine::execute(std::string_view text)
{
    ParsedCommand parsed = parseCommandText(text);
    if (!parsed)
        return CommandOutcome::refuse(std::move(parsed.error));
    return execute(*parsed.command);
}

bool StateMachine::onStreamSilent()
{
    if (state_ != PlayerState::Playing && state_ != PlayerState::Paused)
        return false;
    const Result<void> r = actions_.stop();
    emit(PlayerEventKind::EndOfFile, "silent");
    endReason_ = "eof";
    endDetail_ = "silent";
    advancing_ = reopenWhenSilent_ && !url_.empty();
    enterOrFail(PlayerState::Stopped, "stop", r);
    endReason_ = nullptr;
    advancing_ = false;
    if (reopenWhenSilent_ && state_ == PlayerState::Stopped && !url_.empty()) {
        const Result<void> opened = actions_.awaitNextSender(url_);
        if (opened)
            beginFile();
        enterOrFail(PlayerState::Opening, "open", opened);
    }
    return true;
}

void StateMachine::addListener(PlayerListener *listener)
{
    if (listener != nullptr &&
        std::find(listeners_.begin(), listeners_.end(), listener) == listeners_.end())
        listeners_.push_back(listener);
}

void StateMachine::removeListener(PlayerListener *listener)
{
    listeners_.erase(std::remove(listeners_.begin(), listeners_.end(), listener), listeners_.end());
}

void StateMachine::setState(PlayerState state)
{
    if (state == state_)
        return;
    DT_LOG(Player, Info, "State %s -> %s", playerStateName(state_), playerStateName(state));
    const bool ended = state == PlayerState::Stopped && fileActive_;
    if (ended)
        endFile(endReason_ != nullptr ? endReason_ : "stop", std::move(endDetail_));
    state_ = state;
    if (state == PlayerState::Opening || state == PlayerState::Playing)
        eofReached_ = false;
    emit(PlayerEventKind::StateChanged);
    if (state == PlayerState::Playing && fileActive_ && !fileLoaded_) {
        fileLoaded_ = true;
        emit(PlayerEventKind::FileLoaded);
        emit(PlayerEventKind::PlaybackRestart);
    }
    if (ended && !advancing_ && !quitting())
        enterIdle();
}

void StateMachine::fail(std::string reason, Errc kind)
{
    DT_LOG(Player, Error, "%s", reason.c_str());
    errorReason_ = std::move(reason);
    errorKind_ = kind;
    const bool changed = state_ != PlayerState::Error;
    // mpv's file_error: the file did not open, or failed while it played.
    if (fileActive_)
        endFile("error", fileLoaded_ ? "something happened" : "loading failed");
    state_ = PlayerState::Error;
    emit(PlayerEventKind::Error, errorReason_);
    if (changed) {
        emit(PlayerEventKind::StateChanged);
        if (!advancing_ && !quitting())
            enterIdle();
    }
}

void StateMachine::enterOrFail(PlayerState next, const char *action, const Result<void> &r)
{
    if (r)
        setState(next);
    else
        fail(std::string(action) + " failed: " + r.error().what, r.error().code);
}

void StateMachine::emit(PlayerEventKind kind, std::string message)
{
    if (listeners_.empty())
        return;
    PlayerEvent event;
    event.kind = kind;
    event.state = state_;
    event.stereoMode = stereoMode_;
    event.haptics = haptics_;
    event.stiffness = stiffness_;
    event.loop = loop_;
    event.message = std::move(message);
    if (kind == PlayerEventKind::StartFile || kind == PlayerEventKind::FileEnded)
        event.playlistEntryId = activeEntryId_;
    if (kind == PlayerEventKind::FileEnded)
        event.detail = endDetail_;
    const bool wasNotifying = notifying_;
    notifying_ = true;
    // A copy: a listener may remove itself.
    const std::vector<PlayerListener *> listeners = listeners_;
    for (PlayerListener *l : listeners)
        l->onPlayerEvent(event);
    notifying_ = wasNotifying;
}

} // namespace depthtouch::player
