#pragma once
/// \file
/// \brief pollInput(): one bounded poll(2) for input on a descriptor, the wait of the drivers'
/// event loops (tty and evdev remote inputs, KMS page flips).

#include <chrono>
#include <cstdint>

#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {

/// Longest wait of one pollInput() call; a caller that must wait longer loops.
inline constexpr std::chrono::milliseconds kMaxPollWait{60'000};

/// What one pollInput() call found.
enum class PollResult : std::uint8_t {
    Ready,       ///< The descriptor has events (in revents).
    Timeout,     ///< None within the wait.
    Interrupted, ///< A signal interrupted the wait (EINTR): wait again.
    Failed,      ///< poll(2) failed; errno says why.
};

/// \brief Waits with poll(2) for input (POLLIN) on \a fd for \a wait rounded up to whole
/// milliseconds, at most kMaxPollWait.
/// \return what it found; with Ready, the descriptor's events (POLLIN, POLLHUP, POLLERR,
/// POLLNVAL) are in \a revents. Blocks the calling thread (not for the real-time thread);
/// thread-safe.
PollResult pollInput(int fd, platform::Duration wait, short &revents) noexcept;

} // namespace depthtouch::drivers
