#pragma once
/// \file
/// \brief Remote-control keys to commands: the default bindings, one declarative table shared by
/// every RemoteInput backend (evdev remotes, the terminal keyboard, scripted mock keys), and a
/// KeyMap that a key map file in mpv's `input.conf` form rebinds (docs/playing.md, "Keys").
///
/// A press sends the key's command; an auto-repeat sends it again only when the command allows
/// it (CommandSpec::autoRepeat: seek, stiffness); a release sends nothing.
/// Thread-safety: the table is immutable; a KeyMap is built at setup and only read after (its
/// const members are reentrant).

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "depthtouch/hal/remote_input.h"
#include "depthtouch/player/command.h"

namespace depthtouch::player {

/// \brief One binding: a key and the command text it sends ("seek 10").
struct KeyBinding {
    hal::Key key;
    const char *command;
};

/// \return the default bindings (docs/playing.md, "Keys").
std::span<const KeyBinding> defaultKeyBindings() noexcept;

/// \brief The key that an `input.conf` line or mpv's `keypress` names.
///
/// First a name of hal::keyFromName() (the kernel's `KEY_VOLUMEUP`, or without `KEY_`, any case,
/// '_' ignored: `VOLUME_UP`, `UP`, `ENTER`, `PLAYPAUSE`, `3`); then the kernel's codes that the
/// evdev backend reads as one of those keys (`KEY_ESC` is KEY_EXIT, `KEY_SELECT` KEY_OK,
/// `KEY_PAGEUP`/`KEY_PAGEDOWN` KEY_CHANNELUP/DOWN, `KEY_MODE` KEY_3D_MODE, `KEY_SPACE`
/// KEY_PLAYPAUSE, `KEY_PLAYCD`, `KEY_PAUSECD`, `KEY_STOPCD`); then mpv's names (`SPACE`, `ESC`,
/// `PGUP`, `PGDWN`, `KP_ENTER`, `FORWARD`, `PLAYONLY`, `PAUSEONLY`, `GO_BACK`, `SELECT`); then a
/// single character, the key the terminal backend sends for it (`m` KEY_MUTE, `q` KEY_EXIT, `p`
/// and ` ` KEY_PLAYPAUSE, `+` KEY_CHANNELUP, ...; a digit is the remote's digit key).
/// \return the key, or hal::Key::Unknown.
hal::Key keyFromInputName(std::string_view name);

/// \brief The keys' commands in effect: the defaults, rebound line by line by key map files.
///
/// A key map file is mpv's `input.conf`: one binding a line, `KEY command [arguments]`, `#` starts
/// a comment, blank lines are skipped. KEY is a key name as keyFromInputName() reads it (the
/// kernel's KEY_VOLUMEUP or KEY_ESC, mpv's VOLUME_UP, SPACE, PGUP, a character: `m`); the command
/// is a control command (parseCommandText(): `seek -30`, `stiffness +`, mpv's `cycle pause`, `add
/// volume -2`); `ignore` unbinds the key, as in mpv.
class KeyMap {
public:
    /// The default bindings.
    KeyMap();

    /// \brief Applies the bindings of key map \a text, in order (a later line for the same key
    /// wins). Nothing is applied when a line is wrong.
    /// \return an empty string, or "line N: " and what is wrong (an unknown key, a command that
    /// does not parse, a line over 256 bytes, more than 1000 lines).
    std::string apply(std::string_view text);

    /// \return the command text bound to \a key, or nullptr when the key is not bound.
    [[nodiscard]] const char *commandText(hal::Key key) const noexcept;
    /// \return the command \a event sends, or std::nullopt (unbound key, release, or a repeat of a
    /// command that does not auto-repeat).
    [[nodiscard]] std::optional<Command> commandFor(const hal::KeyEvent &event) const;
    /// \return every binding in effect, in the defaults' order, then the keys bound later.
    [[nodiscard]] const std::vector<std::pair<hal::Key, std::string>> &bindings() const noexcept
    {
        return bindings_;
    }

private:
    std::vector<std::pair<hal::Key, std::string>> bindings_;
};

} // namespace depthtouch::player
