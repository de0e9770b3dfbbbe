/// \file
/// \brief The player's command table and its handlers (state_machine.h): one row per command
/// (its name, arguments, the states it runs in, its parser and its handler, in CommandId order),
/// mpv's names of its commands, and what each command does to the machine. The machine's own
/// transitions (end of stream, open results, failures) are in state_machine.cpp, the files and
/// playlist in state_machine_files.cpp.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "command_parsers.h"
#include "depthtouch/options/option_range.h"
#include "depthtouch/player/state_machine.h"

namespace depthtouch::player {

template <class F>
CommandOutcome StateMachine::apply(const char *what, Result<void> r, F &&onSuccess)
{
    if (r) {
        onSuccess();
        return CommandOutcome::accept();
    }
    return refuseOrFail(what, r);
}

namespace {

constexpr StateMask kActive = stateBit(PlayerState::Playing) | stateBit(PlayerState::Paused);
constexpr StateMask kNotError = kAnyState & static_cast<StateMask>(~stateBit(PlayerState::Error));
constexpr StateMask kCanStart =
    stateBit(PlayerState::Idle) | stateBit(PlayerState::Stopped) | stateBit(PlayerState::Error);

/// \return the refusal of \a v outside \a range: "stiffness 3001 N/m is outside 100 N/m .. 3000
/// N/m".
std::string outsideRange(const options::OptionRange &range, double v)
{
    return std::string(range.name) + " " + range.text(v) + " is outside " + range.text(range.min) +
           " .. " + range.text(range.max);
}

} // namespace

/// The handlers of the command table: each runs only in a state of its row's validIn.
struct CommandHandlers {
    static CommandOutcome startOrResume(StateMachine &m, const std::string &url)
    {
        if (m.state_ == PlayerState::Paused) {
            if (!url.empty() && url != m.url_)
                return CommandOutcome::refuse("stop before opening another file");
            return m.apply("resume", m.actions_.resume(),
                           [&] { m.setState(PlayerState::Playing); });
        }
        const std::string target = url.empty() ? m.url_ : url;
        if (target.empty())
            return CommandOutcome::refuse("no file or URL to play");
        // A file named is the whole playlist (mpv's loadfile replace); the current entry again.
        if (!url.empty() || m.current_ < 0)
            m.replacePlaylist(target);
        return m.openEntry(m.current_ < 0 ? 0 : static_cast<std::size_t>(m.current_));
    }

    /// An mpv alias's command: the handler of the row of the id its parser set.
    static CommandOutcome byId(StateMachine &m, const Command &c)
    {
        return commandSpec(c.id).handle(m, c);
    }

    static CommandOutcome play(StateMachine &m, const Command &c)
    {
        return startOrResume(m, c.url);
    }

    static CommandOutcome pause(StateMachine &m, const Command &)
    {
        return m.apply("pause", m.actions_.pause(), [&] { m.setState(PlayerState::Paused); });
    }

    static CommandOutcome togglePause(StateMachine &m, const Command &c)
    {
        return m.state_ == PlayerState::Playing ? pause(m, c) : startOrResume(m, {});
    }

    /// mpv's stop: the file ends (reason stop) and the playlist is cleared.
    static CommandOutcome stop(StateMachine &m, const Command &)
    {
        // With nothing open, mpv's stop succeeds and forgets the playlist: a UI's stop button is
        // never an error (node-mpv's stop() on an idle player).
        if (m.state_ == PlayerState::Idle || m.state_ == PlayerState::Stopped) {
            m.playlist_.clear();
            return CommandOutcome::accept();
        }
        return m.apply("stop", m.actions_.stop(), [&] {
            m.playlist_.clear();
            m.setState(PlayerState::Stopped);
        });
    }

    static CommandOutcome seek(StateMachine &m, const Command &c)
    {
        return m.apply("seek", m.actions_.seek(c.seconds, c.seekMode), [&] {
            m.emit(PlayerEventKind::Seeked);
            m.emit(PlayerEventKind::PlaybackRestart);
        });
    }

    static CommandOutcome loadFile(StateMachine &m, const Command &c) { return m.loadFile(c); }

    static CommandOutcome playlistStep(StateMachine &m, const Command &c)
    {
        return m.playlistStep(c);
    }

    static CommandOutcome setStereo(StateMachine &m, StereoMode mode)
    {
        if (mode == m.stereoMode_)
            return CommandOutcome::accept();
        return m.apply("stereo mode", m.actions_.setStereoMode(mode), [&] {
            m.stereoMode_ = mode;
            m.emit(PlayerEventKind::StereoModeChanged);
        });
    }

    static CommandOutcome nextStereoMode(StateMachine &m, const Command &)
    {
        return setStereo(m, player::nextStereoMode(m.stereoMode_));
    }

    static CommandOutcome setStereoMode(StateMachine &m, const Command &c)
    {
        return setStereo(m, c.stereoMode);
    }

    static CommandOutcome haptics(StateMachine &m, const Command &c)
    {
        const bool target = c.toggle == Switch::Toggle ? !m.haptics_ : c.toggle == Switch::On;
        if (target == m.haptics_)
            return CommandOutcome::accept();
        return m.apply("haptics", m.actions_.setHapticsEnabled(target), [&] {
            m.haptics_ = target;
            m.emit(PlayerEventKind::HapticsChanged);
        });
    }

    /// `stiffness +|-` steps and clamps at the ends (refused once there), `add stiffness N` clamps
    /// (mpv's add), `stiffness N` and set_property refuse N outside options::kStiffness.
    static CommandOutcome stiffness(StateMachine &m, const Command &c)
    {
        constexpr options::OptionRange kRange = options::kStiffness;
        double target = m.stiffness_;
        switch (c.stiffnessChange) {
        case StiffnessChange::Up:
        case StiffnessChange::Down: {
            const bool up = c.stiffnessChange == StiffnessChange::Up;
            target = kRange.clamp(m.stiffness_ + (up ? kRange.step : -kRange.step));
            if (target == m.stiffness_)
                return CommandOutcome::refuse(std::string("stiffness already at its ") +
                                              (up ? "maximum, " : "minimum, ") +
                                              kRange.text(target));
            break;
        }
        case StiffnessChange::By:
            target = kRange.clamp(m.stiffness_ + c.stiffness);
            break;
        case StiffnessChange::Set:
            if (!kRange.contains(c.stiffness))
                return CommandOutcome::refuse(outsideRange(kRange, c.stiffness));
            target = c.stiffness;
            break;
        }
        if (target == m.stiffness_)
            return CommandOutcome::accept();
        return m.apply("stiffness", m.actions_.setStiffness(target), [&] {
            m.stiffness_ = target;
            m.emit(PlayerEventKind::StiffnessChanged);
        });
    }

    /// One step of mpv's volume keys (`add volume ±2`) or `add volume N`, clamped at the ends of
    /// options::kVolume (mpv's add); a value outside it is refused. Kept when no sound plays.
    static CommandOutcome volume(StateMachine &m, const Command &c)
    {
        constexpr options::OptionRange kRange = options::kVolume;
        double target = c.volume;
        if (c.volumeChange == StiffnessChange::By)
            target = kRange.clamp(m.volume_ + c.volume);
        else if (c.volumeChange != StiffnessChange::Set)
            target = kRange.clamp(
                m.volume_ + (c.volumeChange == StiffnessChange::Up ? kRange.step : -kRange.step));
        else if (!kRange.contains(target)) // parseVolumeArgs() refuses it first from text
            return CommandOutcome::refuse(outsideRange(kRange, target));
        if (target == m.volume_)
            return CommandOutcome::accept();
        return m.apply("volume", m.actions_.setVolume(target), [&] { m.volume_ = target; });
    }

    static CommandOutcome mute(StateMachine &m, const Command &c)
    {
        const bool target = c.toggle == Switch::Toggle ? !m.mute_ : c.toggle == Switch::On;
        if (target == m.mute_)
            return CommandOutcome::accept();
        return m.apply("mute", m.actions_.setMute(target), [&] { m.mute_ = target; });
    }

    static CommandOutcome recenter(StateMachine &m, const Command &)
    {
        return m.apply("recenter", m.actions_.recenter(), [] {});
    }

    static CommandOutcome snapshot(StateMachine &m, const Command &)
    {
        return m.apply("snapshot", m.actions_.snapshot(), [] {});
    }

    static CommandOutcome showProgress(StateMachine &m, const Command &)
    {
        return m.apply("show-progress", m.actions_.showProgress(), [] {});
    }

    static CommandOutcome loop(StateMachine &m, const Command &c)
    {
        const bool target = c.toggle == Switch::Toggle ? !m.loop_ : c.toggle == Switch::On;
        if (target != m.loop_) {
            m.loop_ = target;
            m.emit(PlayerEventKind::LoopChanged);
        }
        return CommandOutcome::accept();
    }

    static CommandOutcome quit(StateMachine &m, const Command &)
    {
        const PlayerState s = m.state_;
        if (s == PlayerState::Opening || s == PlayerState::Playing || s == PlayerState::Paused) {
            // Quitting cannot be refused: a failing stop is reported, and the player quits anyway.
            m.endReason_ = "quit";
            m.enterOrFail(PlayerState::Stopped, "stop", m.actions_.stop());
        }
        m.quit_ = true;
        m.emit(PlayerEventKind::Quit);
        return CommandOutcome::accept();
    }

    static CommandOutcome get(StateMachine &m, const Command &c)
    {
        switch (c.property) {
        case Property::State:
            return CommandOutcome::accept(std::string(playerStateName(m.state_)));
        case Property::StereoMode:
            return CommandOutcome::accept(std::string(stereoModeName(m.stereoMode_)));
        case Property::Haptics:
            return CommandOutcome::accept(m.haptics_);
        case Property::Stiffness:
            return CommandOutcome::accept(m.stiffness_);
        case Property::Loop:
            return CommandOutcome::accept(m.loop_);
        case Property::Url:
            return CommandOutcome::accept(m.url_);
        case Property::Error:
            return CommandOutcome::accept(m.errorReason_);
        default:
            return media(m, c.property);
        }
    }

    /// The properties of the media, the session and the haptic device (mpv's names): a value, or
    /// "property unavailable" where there is none now (nothing open, a live stream's length).
    static CommandOutcome media(StateMachine &m, Property p)
    {
        const PlayerState s = m.state_;
        const bool open = s == PlayerState::Playing || s == PlayerState::Paused;
        const PlayerActions::MediaPosition at = m.actions_.mediaPosition();
        constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
        const auto number = [](double v) {
            return std::isfinite(v) ? CommandOutcome::accept(v)
                                    : CommandOutcome::refuse("property unavailable");
        };
        switch (p) {
        case Property::TimePos:
        case Property::PlaybackTime:
            return number(open ? at.timePos : kNone);
        case Property::Duration:
            return number(open ? at.duration : kNone);
        case Property::PercentPos:
            return number(open && at.duration > 0.0 ? 100.0 * at.timePos / at.duration : kNone);
        case Property::TimeRemaining: // mpv: duration - time-pos, s
            return number(open ? at.duration - at.timePos : kNone);
        case Property::PlaylistCount:
            return CommandOutcome::accept(static_cast<double>(m.playlist_.size()));
        case Property::PlaylistPos:
        case Property::PlaylistPos1:
            return CommandOutcome::accept(static_cast<double>(m.current_) +
                                          (p == Property::PlaylistPos1 ? 1.0 : 0.0));
        case Property::Pause:
            return CommandOutcome::accept(s == PlayerState::Paused);
        case Property::Path:
        case Property::Filename:
        case Property::MediaTitle:
            if (m.url_.empty() || !(open || s == PlayerState::Opening))
                return CommandOutcome::refuse("property unavailable");
            return CommandOutcome::accept(p == Property::Path ? m.url_
                                                              : detail::mediaFilename(m.url_));
        case Property::IdleActive: // mpv: no file loaded
            return CommandOutcome::accept(!open && s != PlayerState::Opening);
        case Property::EofReached:
            return CommandOutcome::accept(m.eofReached_);
        case Property::Volume:
            return CommandOutcome::accept(m.volume_);
        case Property::Mute:
            return CommandOutcome::accept(m.mute_);
        case Property::HapticForce:
            return number(open ? m.actions_.hapticForce() : kNone);
        case Property::Contact: {
            const double f = open ? m.actions_.hapticForce() : kNone;
            return std::isfinite(f) ? CommandOutcome::accept(f > 0.0)
                                    : CommandOutcome::refuse("property unavailable");
        }
        case Property::RemoteConnected:
            return m.remoteConnected_ ? CommandOutcome::accept(*m.remoteConnected_)
                                      : CommandOutcome::refuse("property unavailable");
        case Property::HapticDeviceConnected: {
            const std::optional<bool> connected =
                open ? m.actions_.hapticDeviceConnected() : std::nullopt;
            return connected ? CommandOutcome::accept(*connected)
                             : CommandOutcome::refuse("property unavailable");
        }
        default:
            return CommandOutcome::refuse("unknown property");
        }
    }
};

namespace {

using H = CommandHandlers;
using namespace detail;

// The one command table: every input sends these names. Rows in CommandId order.
constexpr CommandSpec kCommands[] = {
    {"play", CommandId::Play, "[FILE|URL]", "Open and play, or resume when paused",
     kCanStart | stateBit(PlayerState::Paused), false, &parsePlayArgs, &H::play},
    {"pause", CommandId::Pause, "", "Pause playback", stateBit(PlayerState::Playing), false,
     &parseNoArgs, &H::pause},
    {"toggle-pause", CommandId::TogglePause, "", "Pause when playing, otherwise play",
     kCanStart | kActive, false, &parseNoArgs, &H::togglePause},
    {"stop", CommandId::Stop, "", "Stop playback, close the stream and clear the playlist",
     kAnyState, false, &parseNoArgs, &H::stop},
    {"seek", CommandId::Seek, "SECONDS [relative|absolute]",
     "Seek by SECONDS (negative: back) or to a position; keeps paused or playing", kActive, true,
     &parseSeekArgs, &H::seek},
    {"next-stereo-mode", CommandId::NextStereoMode, "",
     "Cycle sbs, tab, anaglyph, mono, interleaved", kNotError, false, &parseNoArgs,
     &H::nextStereoMode},
    {"stereo-mode", CommandId::SetStereoMode, "sbs|tab|anaglyph|mono|interleaved",
     "Set the stereo packing", kNotError, false, &parseStereoModeArgs, &H::setStereoMode},
    {"haptics", CommandId::Haptics, "on|off|toggle", "Turn force output on or off", kNotError,
     false, &parseSwitchArgs, &H::haptics},
    {"stiffness", CommandId::Stiffness, "+|-|N", "Step the stiffness up or down, or set N N/m",
     kNotError, true, &parseStiffnessArgs, &H::stiffness},
    {"recenter", CommandId::Recenter, "", "Re-seat the haptic workspace on the surface", kActive,
     false, &parseNoArgs, &H::recenter},
    {"loop", CommandId::Loop, "on|off|toggle", "Loop at the end of the stream", kAnyState, false,
     &parseSwitchArgs, &H::loop},
    {"quit", CommandId::Quit, "", "Stop and leave the player", kAnyState, false, &parseNoArgs,
     &H::quit},
    {"get", CommandId::Get, "PROPERTY",
     "Read state, stereo-mode, haptics, stiffness, loop, url or error", kAnyState, false,
     &parseGetArgs, &H::get},
    {"snapshot", CommandId::Snapshot, "", "Save the presented frame as PNG (play --snapshot-dir)",
     kActive, false, &parseNoArgs, &H::snapshot},
    {"show-progress", CommandId::ShowProgress, "",
     "Show the on-screen display (state, haptics, stiffness, force) for --osd-seconds", kAnyState,
     false, &parseNoArgs, &H::showProgress},
    {"volume", CommandId::Volume, "+|-|N", "Step the volume up or down 2 %, or set N % (0..130)",
     kAnyState, true, &parseVolumeArgs, &H::volume},
    {"mute", CommandId::Mute, "on|off|toggle", "Mute or unmute the sound", kAnyState, false,
     &parseSwitchArgs, &H::mute},
    {"loadfile", CommandId::LoadFile, "URL [replace|append|append-play]",
     "mpv's loadfile: play URL now (replace), or add it to the playlist (append; append-play "
     "plays it when nothing plays)",
     kAnyState, false, &parseLoadFileArgs, &H::loadFile},
    {"playlist-next", CommandId::PlaylistNext, "[weak|force]",
     "Play the playlist's next entry (force: stop at its end)",
     kActive | stateBit(PlayerState::Opening), false, &parsePlaylistStepArgs, &H::playlistStep},
};

// mpv's names of the table's commands (mpvCommandAliases()): the parser sets the id of the command
// meant, whose row then decides the states and whose handler runs. validIn: the widest.
constexpr CommandSpec kMpvAliases[] = {
    {"playlist-prev", CommandId::PlaylistNext, "[weak|force]",
     "mpv's playlist-prev: play the playlist's previous entry",
     kActive | stateBit(PlayerState::Opening), false, &parsePlaylistPrevArgs, &H::byId},
    {"cycle", CommandId::TogglePause, "PROPERTY [up|down]",
     "mpv's cycle: pause, haptics, loop, mute, stereo-mode", kAnyState, false, &parseCycleArgs,
     &H::byId},
    {"add", CommandId::Seek, "PROPERTY [N]", "mpv's add: time-pos (seek), stiffness, volume",
     kAnyState, true, &parseAddArgs, &H::byId},
};

constexpr bool tableInIdOrder()
{
    for (std::size_t i = 0; i < std::size(kCommands); ++i)
        if (static_cast<std::size_t>(kCommands[i].id) != i)
            return false;
    return true;
}
static_assert(tableInIdOrder(), "kCommands rows must be in CommandId order");

} // namespace

std::span<const CommandSpec> commandTable() noexcept
{
    return kCommands;
}

std::span<const CommandSpec> mpvCommandAliases() noexcept
{
    return kMpvAliases;
}

} // namespace depthtouch::player
