/// \file
/// \brief openDeviceInput(): see device_input.h.

#include "device_input.h"

#include <algorithm>
#include <cerrno>
#include <chrono>

#include <fcntl.h>
#include <poll.h>

namespace depthtouch::drivers::ffmpeg {

namespace {
/// The longest single wait for a FIFO's writer: how soon an interrupt is seen.
constexpr auto kWaitStep = std::chrono::milliseconds(50);
} // namespace

bool isDeviceInput(platform::PathKind kind, bool formatOpensItself) noexcept
{
    return kind == platform::PathKind::Fifo ||
           (kind == platform::PathKind::CharDevice && !formatOpensItself);
}

Result<platform::UniqueFd> openDeviceInput(const char *path, platform::PathKind kind,
                                           platform::Clock &clock, platform::TimePoint deadline,
                                           const std::atomic<bool> &interrupted)
{
    // O_NONBLOCK: open(2) returns at once (a FIFO without a writer, a tty waiting for its
    // carrier), and so do the reads.
    platform::UniqueFd fd(::open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC));
    if (!fd)
        return unexpected(Errc::Io, "Failed to open the media input", errno);
    if (kind != platform::PathKind::Fifo)
        return fd;
    // A FIFO that never had a writer polls as not readable (no POLLHUP) until one writes.
    for (;;) {
        if (interrupted.load(std::memory_order_relaxed))
            return unexpected(Errc::Timeout, "Interrupted by a stop request");
        const platform::TimePoint now = clock.now();
        if (now >= deadline)
            return unexpected(Errc::Timeout, "The input is a FIFO with no writer");
        const auto step = std::min<platform::Duration>(kWaitStep, deadline - now);
        const auto ms = std::chrono::ceil<std::chrono::milliseconds>(step).count();
        pollfd p{fd.get(), POLLIN, 0};
        const int n = ::poll(&p, 1, static_cast<int>(ms));
        if (n > 0)
            return fd;
        if (n < 0 && errno != EINTR)
            return unexpected(Errc::Io, "Failed to wait for the FIFO's writer", errno);
    }
}

} // namespace depthtouch::drivers::ffmpeg
