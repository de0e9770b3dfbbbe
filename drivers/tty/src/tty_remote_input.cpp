#include "depthtouch/drivers/tty/tty_remote_input.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <iterator>

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include "depthtouch/drivers/common/backend_options.h"
#include "depthtouch/drivers/common/poll_input.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Tty)

namespace depthtouch::drivers {

namespace {

constexpr const char *kOptionKeys[] = {"device"};
constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};
constexpr std::size_t kSignalCount = std::size(kSignals);

/// The terminal to restore from a signal handler: written before the handlers are installed and
/// cleared after they are removed, read only by the handler (async-signal-safe calls only).
struct SignalSlot {
    std::atomic<bool> active{false};
    int fd = -1;
    termios saved{};
    struct sigaction previous[kSignalCount]{};
};
SignalSlot gSlot;

void restoreOnSignal(int sig) noexcept
{
    const int savedErrno = errno;
    if (gSlot.active.load(std::memory_order_acquire))
        ::tcsetattr(gSlot.fd, TCSANOW, &gSlot.saved);
    for (std::size_t i = 0; i < kSignalCount; ++i) {
        if (kSignals[i] != sig)
            continue;
        const struct sigaction &prev = gSlot.previous[i];
        ::sigaction(sig, &prev, nullptr);
        if ((prev.sa_flags & SA_SIGINFO) == 0 && prev.sa_handler == SIG_DFL) {
            // Runs the default action (terminate) once this handler returns and unblocks it.
            ::raise(sig);
        } else if ((prev.sa_flags & SA_SIGINFO) == 0 && prev.sa_handler != SIG_IGN) {
            prev.sa_handler(sig);
        } else if ((prev.sa_flags & SA_SIGINFO) != 0 && prev.sa_sigaction != nullptr) {
            prev.sa_sigaction(sig, nullptr, nullptr);
        }
    }
    errno = savedErrno;
}

/// A key and the bytes that stand for it.
struct KeyBytes {
    std::string_view bytes;
    hal::Key key;
};

/// The keys of single bytes (both cases of a letter).
constexpr KeyBytes kByteKeys[] = {
    {" pP", hal::Key::PlayPause}, {"sS", hal::Key::Stop},      {"3", hal::Key::Mode3d},
    {"hH", hal::Key::Red},        {"rR", hal::Key::Green},     {"cC", hal::Key::Yellow},
    {"qQ", hal::Key::Exit},       {"+=", hal::Key::ChannelUp}, {"-", hal::Key::ChannelDown},
    {"oO", hal::Key::Info},       {"0*", hal::Key::VolumeUp},  {"9/", hal::Key::VolumeDown},
    {"mM", hal::Key::Mute}, // mpv's volume and mute keys
};

/// The keys of the final byte of an arrow key's escape sequence (ESC [ A .. D).
constexpr KeyBytes kArrowKeys[] = {
    {"A", hal::Key::Up},
    {"B", hal::Key::Down},
    {"C", hal::Key::Right},
    {"D", hal::Key::Left},
};

/// \return the key of the entry of \a table whose bytes hold \a c, hal::Key::Unknown when none
/// does.
template <std::size_t N> hal::Key keyOf(const KeyBytes (&table)[N], char c) noexcept
{
    for (const KeyBytes &k : table)
        if (k.bytes.find(c) != std::string_view::npos)
            return k.key;
    return hal::Key::Unknown;
}

} // namespace

std::size_t decodeTerminalKeys(std::string_view bytes, std::vector<hal::Key> &keys)
{
    std::size_t i = 0;
    while (i < bytes.size()) {
        const char c = bytes[i];
        if (c != '\x1b') {
            const hal::Key k = keyOf(kByteKeys, c);
            if (k != hal::Key::Unknown)
                keys.push_back(k);
            ++i;
            continue;
        }
        if (i + 1 >= bytes.size())
            return i; // ESC alone so far
        const char kind = bytes[i + 1];
        if (kind == 'O') {
            // SS3 (application cursor keys): ESC O A
            if (i + 2 >= bytes.size())
                return i;
            const hal::Key k = keyOf(kArrowKeys, bytes[i + 2]);
            if (k != hal::Key::Unknown)
                keys.push_back(k);
            i += 3;
            continue;
        }
        if (kind != '[') {
            i += 1; // a lone ESC followed by something else: skip the ESC
            continue;
        }
        // CSI: ESC [ parameters (0x30-0x3f) intermediates (0x20-0x2f) final (0x40-0x7e)
        std::size_t j = i + 2;
        while (j < bytes.size() && bytes[j] >= 0x20 && bytes[j] <= 0x3f)
            ++j;
        if (j >= bytes.size())
            return i;
        if (bytes[j] >= 0x40 && bytes[j] <= 0x7e && j == i + 2) {
            const hal::Key k = keyOf(kArrowKeys, bytes[j]);
            if (k != hal::Key::Unknown)
                keys.push_back(k);
        }
        i = j + 1;
    }
    return i;
}

Result<std::unique_ptr<hal::RemoteInput>> TtyRemoteInput::create(const hal::BackendConfig &cfg)
{
    DT_TRY(rejectUnknownOptions(cfg.options, kOptionKeys, std::size(kOptionKeys),
                                "Unknown tty remote input option"));
    std::string path;
    if (const auto device = cfg.options.find("device"))
        path = std::string(*device);
    else
        path = std::string(cfg.device);

    platform::UniqueFd owned;
    int fd = STDIN_FILENO;
    if (!path.empty()) {
        owned.reset(::open(path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC));
        if (!owned)
            return unexpected(Errc::NoDevice, "Cannot open the terminal", errno);
        fd = owned.get();
    }
    if (::isatty(fd) == 0) {
        DT_LOG(Tty, Info, "%s is not a terminal", path.empty() ? "Standard input" : path.c_str());
        return unexpected(Errc::NoDevice, "Not a terminal");
    }
    termios saved{};
    if (::tcgetattr(fd, &saved) != 0)
        return unexpected(Errc::NoDevice, "Cannot read the terminal mode", errno);

    if (gSlot.active.load() || gSlot.fd != -1)
        return unexpected(Errc::Busy, "The terminal keyboard is already in use");
    gSlot.fd = fd;
    gSlot.saved = saved;
    struct sigaction sa{};
    sa.sa_handler = &restoreOnSignal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;
    for (std::size_t i = 0; i < kSignalCount; ++i)
        ::sigaction(kSignals[i], nullptr, &gSlot.previous[i]);
    gSlot.active.store(true, std::memory_order_release);
    for (int sig : kSignals)
        ::sigaction(sig, &sa, nullptr);

    termios raw = saved;
    raw.c_lflag &= ~static_cast<tcflag_t>(ICANON | ECHO);
    raw.c_cc[VMIN] = 1;
    raw.c_cc[VTIME] = 0;
    if (::tcsetattr(fd, TCSANOW, &raw) != 0) {
        const int err = errno;
        for (std::size_t i = 0; i < kSignalCount; ++i)
            ::sigaction(kSignals[i], &gSlot.previous[i], nullptr);
        gSlot.active.store(false);
        gSlot.fd = -1;
        return unexpected(Errc::Io, "Cannot set the terminal mode", err);
    }
    DT_LOG(Tty, Info, "Reading keys from the terminal (space, s, arrows, 3, h, r, q)");
    return std::unique_ptr<hal::RemoteInput>(
        new TtyRemoteInput(std::move(owned), fd, cfg.clockRef()));
}

TtyRemoteInput::TtyRemoteInput(platform::UniqueFd owned, int fd, platform::Clock &clock) noexcept
    : owned_(std::move(owned)), fd_(fd), clock_(clock)
{
}

TtyRemoteInput::~TtyRemoteInput()
{
    ::tcsetattr(fd_, TCSANOW, &gSlot.saved);
    // Put back the previous handlers unless a signal already did.
    struct sigaction current{};
    for (std::size_t i = 0; i < kSignalCount; ++i) {
        ::sigaction(kSignals[i], nullptr, &current);
        if ((current.sa_flags & SA_SIGINFO) == 0 && current.sa_handler == &restoreOnSignal)
            ::sigaction(kSignals[i], &gSlot.previous[i], nullptr);
    }
    gSlot.active.store(false, std::memory_order_release);
    gSlot.fd = -1;
}

Result<void> TtyRemoteInput::readKeys()
{
    char buf[256];
    const ssize_t n = ::read(fd_, buf, sizeof buf);
    if (n < 0) {
        if (errno == EAGAIN || errno == EINTR)
            return ok();
        gone_ = true;
        return unexpected(Errc::NoDevice, "The terminal went away", errno);
    }
    if (n == 0) {
        gone_ = true;
        return unexpected(Errc::NoDevice, "The terminal hung up");
    }
    partial_.append(buf, static_cast<std::size_t>(n));
    std::vector<hal::Key> keys;
    const std::size_t used = decodeTerminalKeys(partial_, keys);
    partial_.erase(0, used);
    if (partial_.size() > 32)
        partial_.clear(); // an endless escape sequence: drop it
    const platform::TimePoint now = clock_.now();
    for (hal::Key k : keys) {
        queue_.push_back({k, hal::KeyAction::Press, now});
        queue_.push_back({k, hal::KeyAction::Release, now});
    }
    return ok();
}

Result<hal::KeyEvent> TtyRemoteInput::poll(hal::Deadline until)
{
    for (;;) {
        if (queueHead_ < queue_.size()) {
            const hal::KeyEvent e = queue_[queueHead_++];
            if (queueHead_ == queue_.size()) {
                queue_.clear();
                queueHead_ = 0;
            }
            return e;
        }
        if (gone_)
            return unexpected(Errc::NoDevice, "The terminal hung up");
        const platform::TimePoint now = clock_.now();
        const auto wait = until > now ? until - now : platform::Duration::zero();
        short revents = 0;
        const PollResult polled = pollInput(fd_, wait, revents);
        if (polled == PollResult::Interrupted)
            continue;
        if (polled == PollResult::Failed)
            return unexpected(Errc::Io, "poll() on the terminal failed", errno);
        if (polled == PollResult::Timeout) {
            partial_.clear(); // a lone ESC that nothing completed
            if (clock_.now() < until) {
                if (std::chrono::ceil<std::chrono::milliseconds>(wait) < kMaxPollWait)
                    clock_.sleepUntil(until); // a clock that is not the real one
                else
                    continue;
            }
            return unexpected(Errc::Timeout, "No key before the deadline");
        }
        if ((revents & POLLIN) == 0 && (revents & (POLLHUP | POLLERR | POLLNVAL)) != 0) {
            gone_ = true;
            return unexpected(Errc::NoDevice, "The terminal hung up");
        }
        DT_TRY(readKeys());
    }
}

} // namespace depthtouch::drivers
