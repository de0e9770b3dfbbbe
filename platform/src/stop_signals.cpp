/// \file
/// \brief StopSignals: see stop_signals.h.

#include "depthtouch/platform/stop_signals.h"

#include <cerrno>

namespace depthtouch::platform {

namespace {

std::atomic<std::atomic<bool> *> gFlag{nullptr};
std::atomic<int> gCaught{0};
static_assert(std::atomic<std::atomic<bool> *>::is_always_lock_free &&
                  std::atomic<int>::is_always_lock_free && std::atomic<bool>::is_always_lock_free,
              "the signal handler needs lock-free atomics");

extern "C" void onStopSignal(int sig)
{
    const int savedErrno = errno;
    int none = 0;
    gCaught.compare_exchange_strong(none, sig);
    if (std::atomic<bool> *flag = gFlag.load())
        flag->store(true);
    errno = savedErrno;
}

} // namespace

StopSignals::StopSignals(std::atomic<bool> &flag, bool restart) noexcept
{
    gCaught.store(0);
    gFlag.store(&flag);
    struct sigaction sa {};
    sa.sa_handler = &onStopSignal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = restart ? SA_RESTART : 0;
    for (std::size_t i = 0; i < kStopSignalCount; ++i)
        ::sigaction(kStopSignals[i], &sa, &previous_[i]);
}

StopSignals::~StopSignals()
{
    for (std::size_t i = 0; i < kStopSignalCount; ++i)
        ::sigaction(kStopSignals[i], &previous_[i], nullptr);
    gFlag.store(nullptr);
}

int StopSignals::caughtSignal() noexcept
{
    return gCaught.load();
}

const char *stopSignalName(int sig) noexcept
{
    switch (sig) {
    case SIGINT:
        return "SIGINT";
    case SIGTERM:
        return "SIGTERM";
    case SIGHUP:
        return "SIGHUP";
    case SIGQUIT:
        return "SIGQUIT";
    case SIGUSR1:
        return "SIGUSR1";
    case SIGXFSZ:
        return "SIGXFSZ";
    default:
        return "a signal";
    }
}

} // namespace depthtouch::platform
