#pragma once
/// \file
/// \brief A FIFO or a character device named as the ffmpeg source's input, opened without ever
/// blocking the opening thread beyond a stop request (issue 60, class 6): open(2) of a FIFO
/// without a writer, and a read of a device nobody writes (/dev/ptmx, /dev/kmsg, a tty), would
/// block in the kernel where libavformat's interrupt callback is never asked. The descriptor is
/// opened with O_NONBLOCK and kept so: libavformat reads it as `pipe:FD`, and on EAGAIN it waits
/// in its own loop, which asks the interrupt callback (the stop request, the I/O deadline) every
/// millisecond or so.
///
/// Thread-safety: reentrant; \a interrupted may be set from any thread meanwhile.

#include <atomic>

#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/platform/unique_fd.h"

namespace depthtouch::drivers::ffmpeg {

/// \return whether an input path of kind \a kind is opened by openDeviceInput(): a FIFO, or a
/// character device unless the forced container format opens its device itself
/// (\a formatOpensItself: AVFMT_NOFILE, e.g. video4linux2).
[[nodiscard]] bool isDeviceInput(platform::PathKind kind, bool formatOpensItself) noexcept;

/// \brief Opens \a path (of kind \a kind, see isDeviceInput()) for reading, O_NONBLOCK. A FIFO is
/// then waited on until its writer writes (a FIFO that never had a writer reads as its end), in
/// steps of at most 50 ms, until \a deadline on \a clock or until \a interrupted is set.
/// \return the descriptor, O_NONBLOCK set. Errors: Timeout ("The input is a FIFO with no writer"
/// at the deadline, "Interrupted by a stop request" once \a interrupted), Io (open(2) or poll(2)
/// failed; errno kept).
[[nodiscard]] Result<platform::UniqueFd> openDeviceInput(const char *path, platform::PathKind kind,
                                                         platform::Clock &clock,
                                                         platform::TimePoint deadline,
                                                         const std::atomic<bool> &interrupted);

} // namespace depthtouch::drivers::ffmpeg
