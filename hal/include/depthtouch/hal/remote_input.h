#pragma once
/// \file
/// \brief RemoteInput: key presses from a remote control (Linux evdev in real backends).
///
/// Keys follow the Linux input-event-codes names; Key values equal the Linux KEY_* codes so an
/// evdev backend can map codes with keyFromCode(). Key names for scripts and logs are the Linux
/// names
/// ("KEY_PLAYPAUSE"); keyFromName() also accepts them without the "KEY_" prefix and in any case.
///
/// Lifecycle: a RemoteInput is ready when its factory returns; there is no open/close. If the
/// device goes away, poll() returns Errc::NoDevice (the caller may create the backend again later).
/// Time: KeyEvent::time and poll() deadlines are on the backend clock (BackendConfig::clock).
/// Thread-safety: thread-bound (the main thread). Not real-time safe (poll() blocks).

#include <cstddef>
#include <cstdint>

#include "depthtouch/hal/types.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::hal {

/// \brief Remote-control keys; values are the Linux KEY_* codes (linux/input-event-codes.h).
enum class Key : std::uint16_t {
    Unknown = 0,         ///< KEY_RESERVED
    Digit1 = 2,          ///< KEY_1
    Digit2 = 3,          ///< KEY_2
    Digit3 = 4,          ///< KEY_3
    Digit4 = 5,          ///< KEY_4
    Digit5 = 6,          ///< KEY_5
    Digit6 = 7,          ///< KEY_6
    Digit7 = 8,          ///< KEY_7
    Digit8 = 9,          ///< KEY_8
    Digit9 = 10,         ///< KEY_9
    Digit0 = 11,         ///< KEY_0
    Enter = 28,          ///< KEY_ENTER
    Up = 103,            ///< KEY_UP
    Left = 105,          ///< KEY_LEFT
    Right = 106,         ///< KEY_RIGHT
    Down = 108,          ///< KEY_DOWN
    Mute = 113,          ///< KEY_MUTE
    VolumeDown = 114,    ///< KEY_VOLUMEDOWN
    VolumeUp = 115,      ///< KEY_VOLUMEUP
    Power = 116,         ///< KEY_POWER
    Pause = 119,         ///< KEY_PAUSE
    Stop = 128,          ///< KEY_STOP
    Menu = 139,          ///< KEY_MENU
    Back = 158,          ///< KEY_BACK
    PlayPause = 164,     ///< KEY_PLAYPAUSE
    Rewind = 168,        ///< KEY_REWIND
    Exit = 174,          ///< KEY_EXIT
    Play = 207,          ///< KEY_PLAY
    FastForward = 208,   ///< KEY_FASTFORWARD
    Ok = 0x160,          ///< KEY_OK
    Info = 0x166,        ///< KEY_INFO
    Red = 0x18e,         ///< KEY_RED
    Green = 0x18f,       ///< KEY_GREEN
    Yellow = 0x190,      ///< KEY_YELLOW
    Blue = 0x191,        ///< KEY_BLUE
    ChannelUp = 0x192,   ///< KEY_CHANNELUP (CH+; PgUp on a keyboard): stiffness up by default.
    ChannelDown = 0x193, ///< KEY_CHANNELDOWN (CH−; PgDn): stiffness down by default.
    Mode3d = 0x26f,      ///< KEY_3D_MODE: toggles 3D (stereo) rendering.
};

/// What happened to a key (evdev value 1, 0, 2).
enum class KeyAction : std::uint8_t {
    Press,   ///< Went down.
    Release, ///< Went up.
    Repeat,  ///< Auto-repeat while held.
};

/// \brief One key event.
struct KeyEvent {
    Key key = Key::Unknown;
    KeyAction action = KeyAction::Press;
    platform::TimePoint time{}; ///< When it happened, on the backend clock.
};

/// \return the Linux name of \a key, e.g. "KEY_PLAYPAUSE" (static string; "KEY_RESERVED" for
/// Unknown or a value that is not a listed key).
const char *keyName(Key key) noexcept;

/// \return the key called \a name ("KEY_PLAYPAUSE", "playpause", "PlayPause"), or Key::Unknown when
/// \a name is null or names no listed key.
Key keyFromName(const char *name) noexcept;

/// \return the key with Linux code \a code, or Key::Unknown when the code is not a listed key.
Key keyFromCode(int code) noexcept;

/// \return "press", "release" or "repeat" (static string).
const char *keyActionName(KeyAction action) noexcept;

/// \return every listed key (Unknown excluded), in code order; \a count receives the number.
const Key *allKeys(std::size_t &count) noexcept;

/// \brief A source of remote-control key events.
class RemoteInput {
public:
    virtual ~RemoteInput() = default;

    /// \brief Waits for the next key event until \a until (on the backend clock).
    /// \param[in] until Absolute deadline; a deadline in the past polls without waiting.
    /// \return the oldest pending event. Errors: Timeout (nothing arrived by the deadline),
    /// NoDevice (the input device went away), Io (read failure).
    [[nodiscard]] virtual Result<KeyEvent> poll(Deadline until) = 0;

    /// \return true while a backend created without its device (BackendConfig::awaitDevice) has
    /// none: poll() then returns Timeout until one is plugged in. False for backends that never
    /// wait. Thread-bound, as poll().
    [[nodiscard]] virtual bool awaitingDevice() const noexcept { return false; }

protected:
    RemoteInput() = default;
    DT_DISABLE_COPY_AND_MOVE(RemoteInput)
};

} // namespace depthtouch::hal
