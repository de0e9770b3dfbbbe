#pragma once
/// \file
/// \brief The signals that end a command (`depthtouch play`, `encode`, `touch`) the clean way:
/// SIGINT, SIGTERM, SIGHUP (a closed terminal), SIGQUIT, SIGUSR1 and SIGXFSZ (`ulimit -f`; the
/// write that crossed the limit then fails with EFBIG and is reported as a lost output). While a
/// StopSignals lives, each of them only sets a flag that the command polls, so that its outputs are
/// finished and renamed, or removed, and never left cut under their final names or as temporary
/// files.
///
/// Thread-safety: one StopSignals at a time, made and destroyed on one thread; the handler is
/// async-signal-safe (lock-free atomic stores only).

#include <atomic>
#include <csignal>
#include <cstddef>

namespace depthtouch::platform {

/// The signals a StopSignals catches.
inline constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGXFSZ};
inline constexpr std::size_t kStopSignalCount = sizeof kStopSignals / sizeof kStopSignals[0];

/// \brief Catches kStopSignals for its lifetime: each sets \a flag (a lock-free atomic that
/// outlives this object) and is noted (caughtSignal()); the previous actions are restored on
/// destruction. With \a restart (SA_RESTART) a system call the signal interrupts is restarted;
/// without it, it fails with EINTR (a blocked read of an input returns, so the flag is seen).
class StopSignals {
public:
    StopSignals(std::atomic<bool> &flag, bool restart) noexcept;
    ~StopSignals();
    StopSignals(const StopSignals &) = delete;
    StopSignals &operator=(const StopSignals &) = delete;

    /// \return the first signal caught since the last StopSignals was made, 0 when none.
    [[nodiscard]] static int caughtSignal() noexcept;

private:
    struct sigaction previous_[kStopSignalCount] {};
};

/// \return the name of a stop signal ("SIGTERM"), "a signal" for another number. Static string.
[[nodiscard]] const char *stopSignalName(int sig) noexcept;

} // namespace depthtouch::platform
