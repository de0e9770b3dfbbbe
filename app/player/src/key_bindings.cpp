#include "depthtouch/player/key_bindings.h"

namespace depthtouch::player {

namespace {

using hal::Key;

// Remote keys and the terminal keyboard (drivers/tty maps h → KEY_RED, r → KEY_GREEN, c →
// KEY_YELLOW, 3 →
// KEY_3D_MODE, q → KEY_EXIT, space → KEY_PLAYPAUSE, s → KEY_STOP, arrows → arrows).
constexpr KeyBinding kBindings[] = {
    {Key::PlayPause, "toggle-pause"},
    {Key::Ok, "toggle-pause"},
    {Key::Enter, "toggle-pause"},
    {Key::Play, "play"},
    {Key::Pause, "pause"},
    {Key::Stop, "stop"},
    {Key::FastForward, "seek 10"},
    {Key::Right, "seek 10"},
    {Key::Rewind, "seek -10"},
    {Key::Left, "seek -10"},
    {Key::Up, "stiffness +"},
    {Key::Down, "stiffness -"},
    {Key::Mode3d, "next-stereo-mode"},
    {Key::Digit3, "next-stereo-mode"},
    {Key::Red, "haptics toggle"},
    {Key::Green, "recenter"},
    {Key::Yellow, "snapshot"},
    {Key::Exit, "quit"},
    {Key::Power, "quit"},
};

} // namespace

std::span<const KeyBinding> defaultKeyBindings() noexcept
{
    return kBindings;
}

const char *commandTextForKey(hal::Key key) noexcept
{
    for (const KeyBinding &b : kBindings)
        if (b.key == key)
            return b.command;
    return nullptr;
}

std::optional<Command> commandForKey(const hal::KeyEvent &event)
{
    if (event.action == hal::KeyAction::Release)
        return std::nullopt;
    const char *text = commandTextForKey(event.key);
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
