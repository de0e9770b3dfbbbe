#pragma once
/// \file
/// \brief Remote-control keys to commands: one declarative table shared by every RemoteInput
/// backend (evdev remotes, the terminal keyboard, scripted mock keys).
///
/// A press sends the key's command; an auto-repeat sends it again only when the command allows
/// it (CommandSpec::autoRepeat: seek, stiffness); a release sends nothing.
/// Thread-safety: the table is immutable; the functions are reentrant.

#include <optional>
#include <span>

#include "depthtouch/hal/remote_input.h"
#include "depthtouch/player/command.h"

namespace depthtouch::player {

/// \brief One binding: a key and the command text it sends ("seek 10").
struct KeyBinding {
    hal::Key key;
    const char *command;
};

/// \return the default bindings (see the README's "Remote control" section).
std::span<const KeyBinding> defaultKeyBindings() noexcept;

/// \return the command text bound to \a key, or nullptr when the key is not bound.
const char *commandTextForKey(hal::Key key) noexcept;

/// \return the command \a event sends, or std::nullopt (unbound key, release, or a repeat of a
/// command that does not auto-repeat).
std::optional<Command> commandForKey(const hal::KeyEvent &event);

} // namespace depthtouch::player
