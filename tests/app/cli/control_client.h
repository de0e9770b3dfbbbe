#pragma once
/// \file
/// \brief Test support: a client of the player's control socket (JSON lines): one request line
/// out, its reply line back (event lines met on the way are kept in `events`). Header-only.
/// Thread-safety: one client per thread.

#include <sys/socket.h>
#include <sys/time.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

namespace depthtouch::testing {

/// See the file comment.
class ControlClient {
public:
    ControlClient() = default;
    ControlClient(const ControlClient &) = delete;
    ControlClient &operator=(const ControlClient &) = delete;
    ~ControlClient()
    {
        if (fd_ >= 0)
            ::close(fd_);
    }

    /// Connects to the socket at \a path, trying again for up to \a timeout. \return success.
    bool connect(const std::string &path, std::chrono::milliseconds timeout)
    {
        const auto end = std::chrono::steady_clock::now() + timeout;
        while (std::chrono::steady_clock::now() < end) {
            fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
            sockaddr_un addr{};
            addr.sun_family = AF_UNIX;
            std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", path.c_str());
            if (::connect(fd_, reinterpret_cast<sockaddr *>(&addr), sizeof addr) == 0)
                return true;
            ::close(fd_);
            fd_ = -1;
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        return false;
    }

    /// Sends \a requestLine and returns the first reply line (not an event), or "" when none
    /// came within \a timeout. lastReplySeconds() then holds the time the reply took.
    std::string request(const std::string &requestLine,
                        std::chrono::milliseconds timeout = std::chrono::milliseconds(5000))
    {
        const auto start = std::chrono::steady_clock::now();
        lastReplySeconds_ = -1.0;
        const std::string out = requestLine + "\n";
        if (::write(fd_, out.data(), out.size()) != static_cast<ssize_t>(out.size()))
            return {};
        const auto end = start + timeout;
        while (std::chrono::steady_clock::now() < end) {
            const std::size_t nl = buffer_.find('\n');
            if (nl != std::string::npos) {
                std::string line = buffer_.substr(0, nl);
                buffer_.erase(0, nl + 1);
                if (line.find("\"event\"") == std::string::npos) {
                    lastReplySeconds_ =
                        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
                            .count();
                    return line;
                }
                events.push_back(line);
                continue;
            }
            char buf[1024];
            timeval tv{0, 10000};
            ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
            const ssize_t n = ::read(fd_, buf, sizeof buf);
            if (n > 0)
                buffer_.append(buf, static_cast<std::size_t>(n));
            else if (n == 0)
                return {};
        }
        return {};
    }

    /// Seconds the last request's reply took (-1: none came).
    [[nodiscard]] double lastReplySeconds() const noexcept { return lastReplySeconds_; }

    std::vector<std::string> events; ///< Event lines received, in order.

private:
    int fd_ = -1;
    std::string buffer_;
    double lastReplySeconds_ = -1.0;
};

} // namespace depthtouch::testing
