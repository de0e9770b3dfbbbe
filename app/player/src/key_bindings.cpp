#include "depthtouch/player/key_bindings.h"

#include <algorithm>
#include <string>

namespace depthtouch::player {

namespace {

using hal::Key;

// Remote keys and the terminal keyboard (drivers/tty maps h → KEY_RED, r → KEY_GREEN, c →
// KEY_YELLOW, 3 → KEY_3D_MODE, q → KEY_EXIT, space → KEY_PLAYPAUSE, s → KEY_STOP, + / - →
// KEY_CHANNELUP / KEY_CHANNELDOWN, o → KEY_INFO, 0 / 9 → KEY_VOLUMEUP / KEY_VOLUMEDOWN and m →
// KEY_MUTE as mpv's, arrows → arrows). Where a key means the same in Kodi's full-screen video
// (system/keymaps/remote.xml: play PlayPause, pause, stop, forward and reverse, Left/Right
// StepBack/StepForward, Up/Down ChapterOrBigStep, select/menu/info OSD, back, power ShutDown) it
// does the same here; Up/Down's big step is mpv's (seek ±60 s). Stiffness, the one thing neither
// has, is on the other ± rocker of a TV remote, CH+/CH−; VOL+/VOL− and MUTE are the sound's, as
// everywhere (mpv's `add volume ±2`, `cycle mute`).
constexpr KeyBinding kBindings[] = {
    {Key::PlayPause, "toggle-pause"},
    {Key::Play, "toggle-pause"},
    {Key::Pause, "pause"},
    {Key::Stop, "stop"},
    {Key::FastForward, "seek 10"},
    {Key::Right, "seek 10"},
    {Key::Rewind, "seek -10"},
    {Key::Left, "seek -10"},
    {Key::Up, "seek 60"},
    {Key::Down, "seek -60"},
    {Key::Ok, "show-progress"},
    {Key::Enter, "show-progress"},
    {Key::Menu, "show-progress"},
    {Key::Info, "show-progress"},
    {Key::ChannelUp, "stiffness +"},
    {Key::ChannelDown, "stiffness -"},
    {Key::VolumeUp, "volume +"},
    {Key::VolumeDown, "volume -"},
    {Key::Mute, "mute toggle"},
    {Key::Mode3d, "next-stereo-mode"},
    {Key::Digit3, "next-stereo-mode"},
    {Key::Red, "haptics toggle"},
    {Key::Green, "recenter"},
    {Key::Yellow, "snapshot"},
    {Key::Back, "quit"},
    {Key::Exit, "quit"},
    {Key::Power, "quit"},
};

/// Another name of a key: the kernel's codes the evdev backend folds into a key
/// (drivers/evdev's kAliases) and mpv's names (mpv's input/keycodes.c), without "KEY_".
struct KeyAlias {
    const char *name;
    Key key;
};

constexpr KeyAlias kKeyAliases[] = {
    // evdev: KEY_ESC, KEY_SELECT, KEY_PAGEUP, KEY_PAGEDOWN, KEY_MODE, KEY_SPACE, KEY_*CD
    {"ESC", Key::Exit},
    {"SELECT", Key::Ok},
    {"PAGEUP", Key::ChannelUp},
    {"PAGEDOWN", Key::ChannelDown},
    {"MODE", Key::Mode3d},
    {"SPACE", Key::PlayPause},
    {"PLAYCD", Key::Play},
    {"PAUSECD", Key::Pause},
    {"STOPCD", Key::Stop},
    // mpv's names of the same keys
    {"PGUP", Key::ChannelUp},
    {"PGDWN", Key::ChannelDown},
    {"KPENTER", Key::Enter},
    {"FORWARD", Key::FastForward},
    {"PLAYONLY", Key::Play},
    {"PAUSEONLY", Key::Pause},
    {"GOBACK", Key::Back},
};

/// The terminal's keys (drivers/tty: both cases of a letter), for mpv's one-character names.
constexpr KeyAlias kCharKeys[] = {
    {" pP", Key::PlayPause}, {"sS", Key::Stop},   {"3", Key::Mode3d},    {"hH", Key::Red},
    {"rR", Key::Green},      {"cC", Key::Yellow}, {"qQ", Key::Exit},     {"+=", Key::ChannelUp},
    {"-", Key::ChannelDown}, {"oO", Key::Info},   {"0*", Key::VolumeUp}, {"9/", Key::VolumeDown},
    {"mM", Key::Mute},
};

/// \return \a name upper-cased, without a leading "KEY_" and without '_'.
std::string folded(std::string_view name)
{
    if (name.size() > 4 && (name.substr(0, 4) == "KEY_" || name.substr(0, 4) == "key_"))
        name.remove_prefix(4);
    std::string out;
    for (const char c : name)
        if (c != '_')
            out += (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c;
    return out;
}

/// \return \a text without the spaces and tabs at its ends.
std::string_view trimmed(std::string_view text)
{
    const std::size_t begin = text.find_first_not_of(" \t\r");
    if (begin == std::string_view::npos)
        return {};
    return text.substr(begin, text.find_last_not_of(" \t\r") - begin + 1);
}

} // namespace

std::span<const KeyBinding> defaultKeyBindings() noexcept
{
    return kBindings;
}

hal::Key keyFromInputName(std::string_view name)
{
    if (name.empty() || name.size() > 64)
        return Key::Unknown;
    const std::string text(name);
    if (const Key key = hal::keyFromName(text.c_str()); key != Key::Unknown)
        return key;
    const std::string upper = folded(name);
    for (const KeyAlias &a : kKeyAliases)
        if (upper == a.name)
            return a.key;
    if (name.size() == 1)
        for (const KeyAlias &a : kCharKeys)
            if (std::string_view(a.name).find(name.front()) != std::string_view::npos)
                return a.key;
    return Key::Unknown;
}

KeyMap::KeyMap()
{
    for (const KeyBinding &b : kBindings)
        bindings_.emplace_back(b.key, b.command);
}

std::string KeyMap::apply(std::string_view text)
{
    constexpr std::size_t kMaxLine = 256;
    constexpr int kMaxLines = 1000;
    std::vector<std::pair<hal::Key, std::string>> out = bindings_;
    int lineNo = 0;
    for (std::size_t at = 0; at <= text.size(); ++lineNo) {
        const std::size_t end = std::min(text.find('\n', at), text.size());
        std::string_view line = text.substr(at, end - at);
        at = end + 1;
        const std::string where = "line " + std::to_string(lineNo + 1) + ": ";
        if (lineNo >= kMaxLines)
            return where + "more than 1000 lines";
        if (line.size() > kMaxLine)
            return where + "longer than 256 bytes";
        line = trimmed(line.substr(0, line.find('#')));
        if (line.empty())
            continue;
        const std::size_t space = std::min(line.find_first_of(" \t"), line.size());
        const std::string name(line.substr(0, space));
        const std::string command(trimmed(line.substr(space)));
        const hal::Key key = keyFromInputName(name);
        if (key == hal::Key::Unknown)
            return where + "unknown key '" + name + "'";
        const auto bound =
            std::find_if(out.begin(), out.end(), [key](const auto &b) { return b.first == key; });
        if (command == "ignore") {
            if (bound != out.end())
                out.erase(bound);
            continue;
        }
        const ParsedCommand parsed = parseCommandText(command);
        if (!parsed)
            return where + (command.empty() ? std::string("no command for ") + name : parsed.error);
        if (bound != out.end())
            bound->second = command;
        else
            out.emplace_back(key, command);
    }
    bindings_ = std::move(out);
    return {};
}

const char *KeyMap::commandText(hal::Key key) const noexcept
{
    for (const auto &[k, command] : bindings_)
        if (k == key)
            return command.c_str();
    return nullptr;
}

std::optional<Command> KeyMap::commandFor(const hal::KeyEvent &event) const
{
    if (event.action == hal::KeyAction::Release)
        return std::nullopt;
    const char *text = commandText(event.key);
    if (text == nullptr)
        return std::nullopt;
    ParsedCommand parsed = parseCommandText(text);
    if (!parsed)
        return std::nullopt;
    if (event.action == hal::KeyAction::Repeat && !commandSpec(parsed.command->id).autoRepeat)
        return std::nullopt;
    return std::move(parsed.command);
}

} // namespace depthtouch::player
