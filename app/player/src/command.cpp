#include "depthtouch/player/command.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "command_parsers.h"
#include "depthtouch/player/state_machine.h"

namespace depthtouch::player {

namespace {

/// Largest seek offset or position accepted (s): a day; beyond is a typo, not a request.
constexpr double kMaxSeekSeconds = 86400.0;

constexpr std::array<const char *, kPlayerStateCount> kStateNames = {"idle",   "opening", "playing",
                                                                     "paused", "stopped", "error"};
constexpr std::array<const char *, 5> kStereoNames = {"sbs", "tab", "anaglyph", "mono",
                                                      "interleaved"};
constexpr std::array<const char *, kPropertyCount> kPropertyNames = {"state",
                                                                     "stereo-mode",
                                                                     "haptics",
                                                                     "stiffness",
                                                                     "loop",
                                                                     "url",
                                                                     "error",
                                                                     "time-pos",
                                                                     "duration",
                                                                     "percent-pos",
                                                                     "pause",
                                                                     "path",
                                                                     "idle-active",
                                                                     "eof-reached",
                                                                     "volume",
                                                                     "mute",
                                                                     "haptic-force",
                                                                     "contact",
                                                                     "filename",
                                                                     "media-title",
                                                                     "playback-time",
                                                                     "haptic-device-connected",
                                                                     "remote-connected",
                                                                     "playlist-count",
                                                                     "playlist-pos",
                                                                     "playlist-pos-1",
                                                                     "time-remaining"};

static_assert(kPropertyCount == static_cast<std::size_t>(Property::TimeRemaining) + 1,
              "one name per Property");

/// The property names, comma-separated (for error texts).
std::string propertyList()
{
    std::string out;
    for (const char *name : kPropertyNames)
        out += std::string(out.empty() ? "" : ", ") + name;
    return out;
}

std::string quoted(std::string_view s)
{
    std::string out = "'";
    // Keep messages one printable line whatever the input held.
    for (char c : s.substr(0, 64)) {
        const auto u = static_cast<unsigned char>(c);
        out += (u >= 0x20 && u < 0x7f) ? c : '?';
    }
    if (s.size() > 64)
        out += "...";
    out += '\'';
    return out;
}

bool parseNumber(std::string_view text, double &out)
{
    if (!text.empty() && text.front() == '+')
        text.remove_prefix(1);
    if (text.empty())
        return false;
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
    return ec == std::errc() && ptr == text.data() + text.size() && std::isfinite(out);
}

bool lowerEquals(std::string_view a, std::string_view b) noexcept
{
    if (a.size() != b.size())
        return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        char c = a[i];
        if (c >= 'A' && c <= 'Z')
            c = static_cast<char>(c - 'A' + 'a');
        if (c != b[i])
            return false;
    }
    return true;
}

} // namespace

const char *playerStateName(PlayerState state) noexcept
{
    const auto i = static_cast<std::size_t>(state);
    return i < kStateNames.size() ? kStateNames[i] : "unknown";
}

const char *stereoModeName(StereoMode mode) noexcept
{
    const auto i = static_cast<std::size_t>(mode);
    return i < kStereoNames.size() ? kStereoNames[i] : "unknown";
}

std::optional<StereoMode> stereoModeFromName(std::string_view name) noexcept
{
    for (std::size_t i = 0; i < kStereoNames.size(); ++i)
        if (lowerEquals(name, kStereoNames[i]))
            return static_cast<StereoMode>(i);
    if (lowerEquals(name, "side-by-side"))
        return StereoMode::SideBySide;
    if (lowerEquals(name, "top-bottom"))
        return StereoMode::TopAndBottom;
    // FFmpeg's stereo3d filter's names of the same packings (docs/playing.md "Stereo layouts"):
    // left eye first (left half, top half, top row); arcc: red/cyan anaglyph of the eyes' colour.
    struct Alias {
        const char *name;
        StereoMode mode;
    };
    static constexpr Alias kStereo3d[] = {
        {"sbsl", StereoMode::SideBySide},  {"sbs2l", StereoMode::SideBySide},
        {"abl", StereoMode::TopAndBottom}, {"ab2l", StereoMode::TopAndBottom},
        {"tbl", StereoMode::TopAndBottom}, {"tb2l", StereoMode::TopAndBottom},
        {"arcc", StereoMode::Anaglyph},    {"irl", StereoMode::Interleaved},
    };
    for (const Alias &a : kStereo3d)
        if (lowerEquals(name, a.name))
            return a.mode;
    return std::nullopt;
}

StereoMode nextStereoMode(StereoMode mode) noexcept
{
    const auto i = (static_cast<std::size_t>(mode) + 1) % kStereoNames.size();
    return static_cast<StereoMode>(i);
}

std::optional<Property> propertyFromName(std::string_view name) noexcept
{
    for (std::size_t i = 0; i < kPropertyNames.size(); ++i)
        if (lowerEquals(name, kPropertyNames[i]))
            return static_cast<Property>(i);
    return std::nullopt;
}

const char *propertyName(Property property) noexcept
{
    const auto i = static_cast<std::size_t>(property);
    return i < kPropertyNames.size() ? kPropertyNames[i] : "unknown";
}

namespace detail {

std::string parseNoArgs(std::span<const std::string_view> args, Command &)
{
    return args.empty() ? std::string() : "takes no arguments";
}

std::string parsePlayArgs(std::span<const std::string_view> args, Command &out)
{
    if (args.size() > 1)
        return "takes at most one argument (a file or URL)";
    if (args.size() == 1) {
        if (args[0].empty())
            return "the file or URL is empty";
        out.url = std::string(args[0]);
    }
    return {};
}

std::string parseSeekArgs(std::span<const std::string_view> args, Command &out)
{
    // mpv's third word (exact, keyframes) is taken: every seek here is exact.
    if (args.size() == 3 && (lowerEquals(args[2], "exact") || lowerEquals(args[2], "keyframes")))
        args = args.first(2);
    if (args.empty() || args.size() > 2)
        return "needs SECONDS [relative|absolute]";
    if (!parseNumber(args[0], out.seconds))
        return quoted(args[0]) + " is not a number of seconds";
    out.seekMode = SeekMode::Relative;
    if (args.size() == 2) {
        if (lowerEquals(args[1], "relative") || lowerEquals(args[1], "rel"))
            out.seekMode = SeekMode::Relative;
        else if (lowerEquals(args[1], "absolute") || lowerEquals(args[1], "abs"))
            out.seekMode = SeekMode::Absolute;
        else
            return quoted(args[1]) + " is neither relative nor absolute";
    }
    if (std::fabs(out.seconds) > kMaxSeekSeconds)
        return "seconds out of range";
    if (out.seekMode == SeekMode::Absolute && out.seconds < 0.0)
        return "an absolute position cannot be negative";
    return {};
}

std::string parseStereoModeArgs(std::span<const std::string_view> args, Command &out)
{
    if (args.size() != 1)
        return "needs one of sbs, tab, anaglyph, mono, interleaved";
    const auto mode = stereoModeFromName(args[0]);
    if (!mode)
        return "unknown stereo mode " + quoted(args[0]) +
               " (sbs, tab, anaglyph, mono, interleaved)";
    out.stereoMode = *mode;
    return {};
}

std::string parseSwitchArgs(std::span<const std::string_view> args, Command &out)
{
    if (args.size() > 1)
        return "needs on, off or toggle";
    if (args.empty() || lowerEquals(args[0], "toggle")) {
        out.toggle = Switch::Toggle;
        return {};
    }
    for (const char *on : {"on", "yes", "true", "1"})
        if (lowerEquals(args[0], on)) {
            out.toggle = Switch::On;
            return {};
        }
    for (const char *off : {"off", "no", "false", "0"})
        if (lowerEquals(args[0], off)) {
            out.toggle = Switch::Off;
            return {};
        }
    return quoted(args[0]) + " is not on, off or toggle";
}

namespace {

/// Parses "+" / "up", "-" / "down" or a number into \a change and \a value. \return false when
/// \a a is none of them or the number is not finite.
bool parseStep(std::string_view a, StiffnessChange &change, double &value)
{
    if (a == "+" || lowerEquals(a, "up")) {
        change = StiffnessChange::Up;
        return true;
    }
    if (a == "-" || lowerEquals(a, "down")) {
        change = StiffnessChange::Down;
        return true;
    }
    change = StiffnessChange::Set;
    return parseNumber(a, value);
}

} // namespace

std::string parseStiffnessArgs(std::span<const std::string_view> args, Command &out)
{
    if (args.size() != 1)
        return "needs +, - or a value in N/m";
    double value = 0.0;
    // Any number parses: the state machine refuses one outside options::kStiffness.
    if (!parseStep(args[0], out.stiffnessChange, value))
        return quoted(args[0]) + " is not +, - or a stiffness in N/m";
    out.stiffness = value;
    return {};
}

std::string parseVolumeArgs(std::span<const std::string_view> args, Command &out)
{
    if (args.size() != 1)
        return "needs +, - or a volume in %";
    double value = 0.0;
    constexpr options::OptionRange kRange = options::kVolume;
    if (!parseStep(args[0], out.volumeChange, value) ||
        (out.volumeChange == StiffnessChange::Set && !kRange.contains(value)))
        return quoted(args[0]) + " is not +, - or a volume of " + kRange.number(kRange.min) +
               " to " + kRange.text(kRange.max);
    out.volume = value;
    return {};
}

std::string parseGetArgs(std::span<const std::string_view> args, Command &out)
{
    if (args.size() != 1)
        return "needs a property (" + propertyList() + ")";
    if (const std::optional<Property> p = propertyFromName(args[0])) {
        out.property = *p;
        return {};
    }
    return "unknown property " + quoted(args[0]) + " (" + propertyList() + ")";
}

namespace {

/// \return the property called \a name, mpv's "loop-file" being the loop; or std::nullopt.
std::optional<Property> mpvProperty(std::string_view name) noexcept
{
    return lowerEquals(name, "loop-file") ? std::optional<Property>(Property::Loop)
                                          : propertyFromName(name);
}

} // namespace

namespace {

/// \return the value of hex digit \a c, or -1.
int hexDigit(char c) noexcept
{
    if (c >= '0' && c <= '9')
        return c - '0';
    if (c >= 'a' && c <= 'f')
        return c - 'a' + 10;
    if (c >= 'A' && c <= 'F')
        return c - 'A' + 10;
    return -1;
}

} // namespace

std::string mediaFilename(std::string_view url)
{
    std::string text;
    const bool isUrl = url.find("://") != std::string_view::npos;
    for (std::size_t i = 0; i < url.size(); ++i) {
        const int high = isUrl && url[i] == '%' && i + 2 < url.size() ? hexDigit(url[i + 1]) : -1;
        const int low = high >= 0 ? hexDigit(url[i + 2]) : -1;
        if (low >= 0) {
            text += static_cast<char>(high * 16 + low);
            i += 2;
        } else {
            text += url[i];
        }
    }
    const std::size_t slash = text.find_last_of('/');
    std::string base = slash == std::string::npos ? text : text.substr(slash + 1);
    return base.empty() ? text : base;
}

std::string parseLoadFileArgs(std::span<const std::string_view> args, Command &out)
{
    // mpv's loadfile <url> [<flags> [<index> [<options>]]]: the flags only.
    if (args.empty() || args.size() > 2)
        return "needs a file or URL and at most one of replace, append, append-play";
    out.loadMode = LoadMode::Replace;
    if (args.size() == 2 && lowerEquals(args[1], "append"))
        out.loadMode = LoadMode::Append;
    else if (args.size() == 2 && lowerEquals(args[1], "append-play"))
        out.loadMode = LoadMode::AppendPlay;
    else if (args.size() == 2 && !lowerEquals(args[1], "replace"))
        return quoted(args[1]) + " is not replace, append or append-play";
    if (args[0].empty())
        return "the file or URL is empty";
    out.url = std::string(args[0]);
    return {};
}

std::string parsePlaylistStepArgs(std::span<const std::string_view> args, Command &out)
{
    if (args.size() > 1 ||
        (args.size() == 1 && !lowerEquals(args[0], "weak") && !lowerEquals(args[0], "force")))
        return "takes at most weak or force";
    out.force = args.size() == 1 && lowerEquals(args[0], "force");
    out.step = 1;
    return {};
}

std::string parsePlaylistPrevArgs(std::span<const std::string_view> args, Command &out)
{
    std::string error = parsePlaylistStepArgs(args, out);
    out.id = CommandId::PlaylistNext;
    out.step = -1;
    return error;
}

std::string parseCycleArgs(std::span<const std::string_view> args, Command &out)
{
    if (args.empty() || args.size() > 2)
        return "needs PROPERTY [up|down]";
    const bool down = args.size() == 2 && lowerEquals(args[1], "down");
    if (args.size() == 2 && !down && !lowerEquals(args[1], "up"))
        return quoted(args[1]) + " is neither up nor down";
    const std::optional<Property> p = mpvProperty(args[0]);
    if (!p)
        return "unknown property " + quoted(args[0]) + " (" + propertyList() + ")";
    out.toggle = Switch::Toggle;
    switch (*p) {
    case Property::Pause:
        out.id = CommandId::TogglePause;
        return {};
    case Property::Haptics:
        out.id = CommandId::Haptics;
        return {};
    case Property::Loop:
        out.id = CommandId::Loop;
        return {};
    case Property::Mute:
        out.id = CommandId::Mute;
        return {};
    case Property::StereoMode:
        out.id = CommandId::NextStereoMode;
        return down ? "stereo-mode cycles up only" : std::string();
    default:
        return quoted(args[0]) + " cannot be cycled (pause, haptics, loop, mute, stereo-mode)";
    }
}

std::string parseAddArgs(std::span<const std::string_view> args, Command &out)
{
    if (args.empty() || args.size() > 2)
        return "needs PROPERTY [VALUE]";
    double by = 1.0; // mpv's default
    if (args.size() == 2 && !parseNumber(args[1], by))
        return quoted(args[1]) + " is not a number";
    const std::optional<Property> p = mpvProperty(args[0]);
    if (!p)
        return "unknown property " + quoted(args[0]) + " (" + propertyList() + ")";
    switch (*p) {
    case Property::TimePos:
    case Property::PlaybackTime:
        if (std::fabs(by) > kMaxSeekSeconds)
            return "seconds out of range";
        out.id = CommandId::Seek;
        out.seconds = by;
        out.seekMode = SeekMode::Relative;
        return {};
    case Property::Stiffness:
        out.id = CommandId::Stiffness;
        out.stiffnessChange = StiffnessChange::By;
        out.stiffness = by;
        return {};
    case Property::Volume:
        out.id = CommandId::Volume;
        out.volumeChange = StiffnessChange::By;
        out.volume = by;
        return {};
    default:
        return quoted(args[0]) + " cannot be added to (time-pos, playback-time, stiffness, volume)";
    }
}

} // namespace detail

const CommandSpec &commandSpec(CommandId id) noexcept
{
    return commandTable()[static_cast<std::size_t>(id)];
}

const CommandSpec *findCommand(std::string_view name) noexcept
{
    for (const CommandSpec &spec : commandTable())
        if (name == spec.name)
            return &spec;
    for (const CommandSpec &spec : mpvCommandAliases())
        if (name == spec.name)
            return &spec;
    return nullptr;
}

ParsedCommand parseCommand(std::string_view name, std::span<const std::string_view> args)
{
    ParsedCommand result;
    const CommandSpec *spec = findCommand(name);
    if (spec == nullptr) {
        result.error = name.empty() ? "empty command" : "unknown command " + quoted(name);
        return result;
    }
    Command command;
    command.id = spec->id;
    std::string error = spec->parse(args, command);
    if (!error.empty()) {
        result.error = std::string(spec->name) + ": " + error;
        return result;
    }
    result.command = std::move(command);
    return result;
}

ParsedCommand parseCommandText(std::string_view text)
{
    std::vector<std::string> words;
    std::size_t i = 0;
    while (i < text.size()) {
        const char c = text[i];
        if (c == ' ' || c == '\t' || c == '\r' || c == '\n') {
            ++i;
            continue;
        }
        std::string word;
        if (c == '\'' || c == '"') {
            const std::size_t end = text.find(c, i + 1);
            if (end == std::string_view::npos)
                return {std::nullopt, "unterminated quote"};
            word = std::string(text.substr(i + 1, end - i - 1));
            i = end + 1;
        } else {
            while (i < text.size() && text[i] != ' ' && text[i] != '\t' && text[i] != '\r' &&
                   text[i] != '\n')
                word += text[i++];
        }
        words.push_back(std::move(word));
    }
    if (words.empty())
        return {std::nullopt, "empty command"};
    std::vector<std::string_view> args(words.begin() + 1, words.end());
    return parseCommand(words.front(), args);
}

ParsedCommand parseCommandJson(const nlohmann::json &array)
{
    if (!array.is_array() || array.empty())
        return {std::nullopt, "command must be a non-empty array, e.g. [\"seek\", 10]"};
    if (!array[0].is_string())
        return {std::nullopt, "the command name must be a string"};
    std::vector<std::string> words;
    words.reserve(array.size());
    for (std::size_t i = 1; i < array.size(); ++i) {
        const nlohmann::json &a = array[i];
        if (a.is_string())
            words.push_back(a.get<std::string>());
        else if (a.is_boolean())
            words.emplace_back(a.get<bool>() ? "on" : "off");
        else if (a.is_number_integer() || a.is_number_unsigned())
            words.push_back(a.dump());
        else if (a.is_number_float()) {
            char buf[64];
            std::snprintf(buf, sizeof buf, "%.17g", a.get<double>());
            words.emplace_back(buf);
        } else
            return {std::nullopt,
                    "argument " + std::to_string(i) + " must be a string, a number or a boolean"};
    }
    std::vector<std::string_view> args(words.begin(), words.end());
    return parseCommand(array[0].get_ref<const std::string &>(), args);
}

std::string commandText(const Command &command)
{
    std::string out = commandSpec(command.id).name;
    char buf[64];
    // A level's change: " <value>" when set, " +" or " -" when stepped.
    const auto appendChange = [&out, &buf](StiffnessChange change, double value) {
        if (change == StiffnessChange::Set || change == StiffnessChange::By) {
            std::snprintf(buf, sizeof buf, change == StiffnessChange::By ? " by %+g" : " %g",
                          value);
            out += buf;
        } else {
            out += change == StiffnessChange::Up ? " +" : " -";
        }
    };
    switch (command.id) {
    case CommandId::Play:
        if (!command.url.empty())
            out += " " + command.url;
        break;
    case CommandId::LoadFile:
        out += " " + command.url +
               (command.loadMode == LoadMode::Replace  ? " replace"
                : command.loadMode == LoadMode::Append ? " append"
                                                       : " append-play");
        break;
    case CommandId::PlaylistNext:
        if (command.step < 0)
            out = "playlist-prev";
        out += command.force ? " force" : " weak";
        break;
    case CommandId::Seek:
        std::snprintf(buf, sizeof buf, " %g %s", command.seconds,
                      command.seekMode == SeekMode::Absolute ? "absolute" : "relative");
        out += buf;
        break;
    case CommandId::SetStereoMode:
        out += std::string(" ") + stereoModeName(command.stereoMode);
        break;
    case CommandId::Haptics:
    case CommandId::Loop:
    case CommandId::Mute:
        out += command.toggle == Switch::On    ? " on"
               : command.toggle == Switch::Off ? " off"
                                               : " toggle";
        break;
    case CommandId::Stiffness:
        appendChange(command.stiffnessChange, command.stiffness);
        break;
    case CommandId::Volume:
        appendChange(command.volumeChange, command.volume);
        break;
    case CommandId::Get:
        out += std::string(" ") + propertyName(command.property);
        break;
    default:
        break;
    }
    return out;
}

} // namespace depthtouch::player
