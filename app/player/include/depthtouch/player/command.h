#pragma once
/// \file
/// \brief The player's commands: names, arguments, the states where each is valid, and parsing from
/// text ("seek -10") and from JSON arrays (["seek", -10]).
///
/// Every input (remote keys, the control socket, the terminal keyboard, tests) sends the same
/// command names through one table (commandTable(), after mpv's mp_cmds[]): one row per command
/// with its name, argument parser, the states where it is valid, whether key auto-repeat may send
/// it, and its handler in the StateMachine.
///
/// Units: seek offsets and positions in seconds; stiffness in N/m; volume in %. The ranges of
/// stiffness and volume are their rows of depthtouch/options/option_range.h.
/// Thread-safety: the table is immutable; the functions are reentrant.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "depthtouch/options/option_range.h"

namespace depthtouch::player {

/// \brief States of the player (see StateMachine for the diagram).
enum class PlayerState : std::uint8_t { Idle, Opening, Playing, Paused, Stopped, Error };

/// Number of PlayerState values.
inline constexpr std::size_t kPlayerStateCount = 6;

/// \return "idle", "opening", "playing", "paused", "stopped" or "error" (static string).
const char *playerStateName(PlayerState state) noexcept;

/// \brief How the two eye views are packed on the display.
enum class StereoMode : std::uint8_t {
    SideBySide,   ///< "sbs": left eye in the left half, right eye in the right half.
    TopAndBottom, ///< "tab": left eye on top.
    Anaglyph,     ///< "anaglyph": red/cyan.
    Mono,         ///< "mono": one eye only (2D).
    Interleaved,  ///< "interleaved": alternate rows (line-interleaved 3D panels).
};

/// \return "sbs", "tab", "anaglyph", "mono" or "interleaved" (static string).
const char *stereoModeName(StereoMode mode) noexcept;
/// \return the mode called \a name (the names of stereoModeName(), "side-by-side", "top-bottom", or
/// FFmpeg stereo3d's names of the same packings: sbsl, sbs2l, abl, ab2l, tbl, tb2l, arcc, irl),
/// or std::nullopt.
std::optional<StereoMode> stereoModeFromName(std::string_view name) noexcept;
/// \return the mode after \a mode in the cycle sbs → tab → anaglyph → mono → interleaved → sbs.
StereoMode nextStereoMode(StereoMode mode) noexcept;

/// The commands (one per row of commandTable()).
enum class CommandId : std::uint8_t {
    Play,           ///< "play [URL]": open and start, or resume when paused.
    Pause,          ///< "pause".
    TogglePause,    ///< "toggle-pause": pause when playing, otherwise play.
    Stop,           ///< "stop".
    Seek,           ///< "seek SECONDS [relative|absolute]".
    NextStereoMode, ///< "next-stereo-mode".
    SetStereoMode,  ///< "stereo-mode sbs|tab|anaglyph|mono|interleaved".
    Haptics,        ///< "haptics on|off|toggle".
    Stiffness,      ///< "stiffness +|-|N": one step up or down, or N N/m.
    Recenter,       ///< "recenter": re-seat the haptic workspace on the surface.
    Loop,           ///< "loop on|off|toggle": what the end of the stream does.
    Quit,           ///< "quit".
    Get,            ///< "get PROPERTY": a query, changes nothing.
    Snapshot,       ///< "snapshot": save the presented frame as PNG (play --snapshot-dir).
    ShowProgress,   ///< "show-progress": bring the on-screen display up (mpv's command).
    Volume,         ///< "volume +|-|N": one step (2 %) up or down, or N % (0..kMaxVolume).
    Mute,           ///< "mute on|off|toggle".
    LoadFile,       ///< mpv's "loadfile URL [replace|append|append-play]": the playlist.
    PlaylistNext,   ///< mpv's "playlist-next [weak|force]" (and playlist-prev: Command::step).
};

/// What loadfile does with the playlist (mpv's flags).
enum class LoadMode : std::uint8_t {
    Replace,    ///< Stop what plays, make URL the whole playlist and play it.
    Append,     ///< Add URL at the playlist's end; nothing starts.
    AppendPlay, ///< Add URL at the end, and play it when nothing plays (idle).
};

/// Largest volume, percent (mpv's --volume-max default; options::kVolume, the one range of every
/// volume setting); 100 is the sound as coded.
inline constexpr double kMaxVolume = options::kVolume.max;

/// On / off / toggle argument of haptics and loop.
enum class Switch : std::uint8_t { On, Off, Toggle };
/// How a seek's seconds are meant.
enum class SeekMode : std::uint8_t {
    Relative, ///< Offset from the current position (negative: back).
    Absolute, ///< Position from the start of the stream.
};
/// What a stiffness or a volume command does: one step up or down, set a value, or add a value to
/// the current one (By: mpv's `add stiffness 100`, `add volume -2`; negative: down).
enum class StiffnessChange : std::uint8_t { Up, Down, Set, By };
/// Properties readable with "get" (and mpv's get_property on the control socket), by name:
/// "state", "stereo-mode", "haptics", "stiffness" (N/m), "loop", "url", "error", and mpv's
/// "time-pos", "duration", "percent-pos" (s, s, %), "pause", "path", "idle-active", "eof-reached",
/// "volume" (%, 0..kMaxVolume), "mute", then "haptic-force" (|F| commanded, N) and "contact" (|F| >
/// 0), then mpv's "filename" (the path's last part, a URL's %-escapes undone), "media-title" (the
/// filename: the player reads no title tags) and "playback-time" (time-pos, s), then
/// "haptic-device-connected" (the haptic device is connected and answering; false while a player
/// that stays up waits for one to be plugged in; unavailable without a haptic task) and
/// "remote-connected" (the remote's input device is there; false while one is waited for;
/// unavailable without a remote), then mpv's "playlist-count" (entries), "playlist-pos" (the
/// current entry from 0; -1 for none), "playlist-pos-1" (from 1; 0 for none) and
/// "time-remaining" (duration - time-pos, s; unavailable without a duration).
enum class Property : std::uint8_t {
    State,
    StereoMode,
    Haptics,
    Stiffness,
    Loop,
    Url,
    Error,
    TimePos,
    Duration,
    PercentPos,
    Pause,
    Path,
    IdleActive,
    EofReached,
    Volume,
    Mute,
    HapticForce,
    Contact,
    Filename,
    MediaTitle,
    PlaybackTime,
    HapticDeviceConnected,
    RemoteConnected,
    PlaylistCount,
    PlaylistPos,
    PlaylistPos1,
    TimeRemaining,
};

/// Number of Property values.
inline constexpr std::size_t kPropertyCount = 27;

/// \return the property called \a name (propertyName()'s names, any case), or std::nullopt.
std::optional<Property> propertyFromName(std::string_view name) noexcept;

/// \brief A parsed command: its id and the arguments that apply to it.
struct Command {
    CommandId id = CommandId::Play;
    std::string url;                        ///< Play: URL or path; empty for the current one.
    double seconds = 0.0;                   ///< Seek: offset or position (s).
    SeekMode seekMode = SeekMode::Relative; ///< Seek.
    StereoMode stereoMode = StereoMode::SideBySide;        ///< SetStereoMode.
    Switch toggle = Switch::Toggle;                        ///< Haptics, Loop, Mute.
    StiffnessChange stiffnessChange = StiffnessChange::Up; ///< Stiffness.
    double stiffness = 0.0;                                ///< Stiffness with Set or By: N/m.
    StiffnessChange volumeChange = StiffnessChange::Up;    ///< Volume.
    double volume = 0.0;                                   ///< Volume with Set or By: %.
    Property property = Property::State;                   ///< Get.
    LoadMode loadMode = LoadMode::Replace;                 ///< LoadFile.
    int step = 1;       ///< PlaylistNext: +1 (playlist-next) or -1 (playlist-prev).
    bool force = false; ///< PlaylistNext: mpv's force (at the playlist's end: stop).
};

/// \brief A command or why the text could not be parsed.
struct ParsedCommand {
    std::optional<Command> command; ///< Set on success.
    std::string error;              ///< Set on failure, e.g. "seek: 'x' is not a number".

    explicit operator bool() const noexcept { return command.has_value(); }
};

/// A set of PlayerState values (bit 1 << state).
using StateMask = std::uint8_t;
/// \return the mask holding only \a state.
constexpr StateMask stateBit(PlayerState state) noexcept
{
    return static_cast<StateMask>(1u << static_cast<unsigned>(state));
}
/// Every state.
inline constexpr StateMask kAnyState = 0x3f;

class StateMachine;
struct CommandOutcome;

/// \brief One row of the command table.
struct CommandSpec {
    const char *name; ///< Command name used by every input, e.g. "toggle-pause".
    CommandId id;
    const char *usage; ///< Arguments, e.g. "SECONDS [relative|absolute]" ("" for none).
    const char *help;  ///< One line.
    StateMask validIn; ///< States where the command is accepted; elsewhere it is refused.
    bool autoRepeat;   ///< A held remote key may repeat it (seek, stiffness).
    /// Parses the arguments (the words after the name) into \a out. \return an error text, or
    /// an empty string on success.
    std::string (*parse)(std::span<const std::string_view> args, Command &out);
    /// Carries the command out; called only in a state of validIn.
    CommandOutcome (*handle)(StateMachine &machine, const Command &command);
};

/// \return the command table (one row per CommandId, in CommandId order).
std::span<const CommandSpec> commandTable() noexcept;
/// \return the row of \a id.
const CommandSpec &commandSpec(CommandId id) noexcept;
/// \return mpv's command names that are spellings of the table's commands (`playlist-prev`:
/// playlist-next with step -1; `cycle PROPERTY`: toggle-pause, haptics/loop/mute toggle,
/// next-stereo-mode; `add PROPERTY [N]`: seek relative, stiffness/volume by N): rows whose parser
/// sets Command::id to the command they mean, whose handler is that command's (the id's row decides
/// the states and runs it).
std::span<const CommandSpec> mpvCommandAliases() noexcept;
/// \return the row called \a name (the table's, then mpvCommandAliases()), or nullptr.
const CommandSpec *findCommand(std::string_view name) noexcept;

/// \brief Parses a command from its name and argument words.
ParsedCommand parseCommand(std::string_view name, std::span<const std::string_view> args);
/// \brief Parses a text command: words separated by spaces or tabs, e.g. "seek -10",
/// "haptics off", "play 'my file.mkv'" (single or double quotes group words).
ParsedCommand parseCommandText(std::string_view text);
/// \brief Parses a JSON command array, e.g. ["seek", -10] or ["haptics", false].
///
/// The first element is the name (a string). Arguments may be strings, numbers or booleans
/// (true/false become "on"/"off"); anything else is an error.
ParsedCommand parseCommandJson(const nlohmann::json &array);

/// \return the canonical text of \a command, e.g. "seek -10 relative" (for logs and tests).
std::string commandText(const Command &command);

/// \return the name of \a property as used by "get", e.g. "stereo-mode".
const char *propertyName(Property property) noexcept;

} // namespace depthtouch::player
