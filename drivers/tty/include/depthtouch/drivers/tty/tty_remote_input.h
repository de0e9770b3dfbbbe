#pragma once
/// \file
/// \brief TtyRemoteInput: single keys typed on a terminal as remote-control keys (backend `tty`),
/// for developers at a shell.
///
/// Keys: space or p → KEY_PLAYPAUSE, s → KEY_STOP, ← / → → KEY_LEFT / KEY_RIGHT, ↑ / ↓ → KEY_UP /
/// KEY_DOWN, + (or =) / - → KEY_CHANNELUP / KEY_CHANNELDOWN (stiffness), o → KEY_INFO (the
/// on-screen display, as mpv's show-progress key), 3 → KEY_3D_MODE, h → KEY_RED (haptics), r →
/// KEY_GREEN (recenter), c → KEY_YELLOW (snapshot), q → KEY_EXIT (letters in either case; arrows
/// as "ESC [ A" or "ESC O A"). Each key is
/// reported as a press followed by a release at the same time (a terminal has no key-up). Other
/// bytes are skipped.
///
/// The terminal is put in non-canonical mode without echo while the backend exists (signal keys
/// such as Ctrl-C keep working) and restored when it is destroyed, and also when SIGINT, SIGTERM,
/// SIGHUP or SIGQUIT arrives (the handler restores the terminal, then runs the signal's previous
/// disposition). One TtyRemoteInput may exist at a time.
///
/// Options: `device=PATH` (or BackendConfig::device): the terminal to read; default standard
/// input. Errors: NoDevice when it is not a terminal (or when the terminal hangs up, from poll()),
/// Busy when another TtyRemoteInput exists.
/// Thread-safety: thread-bound, as hal::RemoteInput.

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <termios.h>

#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/remote_input.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/platform/unique_fd.h"

namespace depthtouch::drivers {

/// \brief Decodes terminal bytes into keys, appending them to \a keys.
/// \return the number of bytes consumed; an incomplete escape sequence at the end is left
/// unconsumed (so the caller can complete it with the next read).
std::size_t decodeTerminalKeys(std::string_view bytes, std::vector<hal::Key> &keys);

class TtyRemoteInput final : public hal::RemoteInput {
public:
    /// Backend factory (see the file comment).
    static Result<std::unique_ptr<hal::RemoteInput>> create(const hal::BackendConfig &cfg);

    /// Restores the terminal and the previous signal handlers.
    ~TtyRemoteInput() override;

    [[nodiscard]] Result<hal::KeyEvent> poll(hal::Deadline until) override;

private:
    TtyRemoteInput(platform::UniqueFd owned, int fd, platform::Clock &clock) noexcept;
    /// Reads what is available and queues its keys. \return NoDevice on hang-up.
    Result<void> readKeys();

    platform::UniqueFd owned_; ///< The opened device, or empty for standard input.
    int fd_;
    platform::Clock &clock_;
    std::string partial_;               ///< Incomplete escape sequence.
    std::vector<hal::KeyEvent> queue_;  ///< Decoded events not yet returned (FIFO).
    std::size_t queueHead_ = 0;
    bool gone_ = false;
};

} // namespace depthtouch::drivers
