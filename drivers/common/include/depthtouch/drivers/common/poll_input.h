#pragma once
/// \file
/// \brief pollInput(): one bounded poll(2) for input on a descriptor, the wait of the drivers'
/// event loops (tty and evdev remote inputs, KMS page flips).

#include <chrono>

#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {

/// Longest wait of one pollInput() call; a caller that must wait longer loops.
inline constexpr std::chrono::milliseconds kMaxPollWait{60'000};

/// \brief Waits with poll(2) for input (POLLIN) on \a fd for \a wait rounded up to whole
/// milliseconds, at most kMaxPollWait.
/// \return poll()'s result: 1 with the descriptor's events in \a revents (POLLIN, POLLHUP,
/// POLLERR, POLLNVAL), 0 on timeout, -1 with errno set (EINTR included). Blocks the calling
/// thread (not for the real-time thread); thread-safe.
int pollInput(int fd, platform::Duration wait, short &revents) noexcept;

} // namespace depthtouch::drivers
