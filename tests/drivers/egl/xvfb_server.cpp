#include "xvfb_server.h"

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <string_view>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace depthtouch::testing {

namespace {

constexpr int kDisplayFd = 9; ///< The descriptor Xvfb writes its display number to.
constexpr int kStartTimeoutMs = 10000;

} // namespace

XvfbServer::~XvfbServer()
{
    stop(SIGTERM);
}

std::string XvfbServer::findProgram()
{
    const char *path = std::getenv("PATH");
    std::string_view rest = path != nullptr ? path : "/usr/bin:/bin";
    while (!rest.empty()) {
        const std::size_t colon = rest.find(':');
        const std::string_view dir = rest.substr(0, colon);
        rest = colon == std::string_view::npos ? std::string_view() : rest.substr(colon + 1);
        if (dir.empty())
            continue;
        std::string candidate = std::string(dir) + "/Xvfb";
        if (::access(candidate.c_str(), X_OK) == 0)
            return candidate;
    }
    return {};
}

bool XvfbServer::start(bool reuseNumber)
{
    if (pid_ > 0)
        return true;
    const std::string program = findProgram();
    if (program.empty()) {
        why_ = "Xvfb is not installed (Debian package xvfb)";
        return false;
    }
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) {
        why_ = "pipe2 failed";
        return false;
    }
    std::vector<std::string> args = {program};
    if (reuseNumber && number_ >= 0)
        args.push_back(":" + std::to_string(number_));
    for (const char *a :
         {"-displayfd", "", "-screen", "0", "1280x720x24", "-nolisten", "tcp", "-noreset"})
        args.emplace_back(*a != '\0' ? std::string(a) : std::to_string(kDisplayFd));
    std::vector<char *> argv;
    for (std::string &a : args)
        argv.push_back(a.data());
    argv.push_back(nullptr);

    // fork() rather than posix_spawn(): the server must end with this program even when it
    // crashes (PR_SET_PDEATHSIG). Only async-signal-safe calls run between fork() and exec.
    const int devNull = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::prctl(PR_SET_PDEATHSIG, SIGTERM);
        if (fds[1] == kDisplayFd)
            ::fcntl(kDisplayFd, F_SETFD, 0); // dup2() onto itself keeps FD_CLOEXEC
        else
            ::dup2(fds[1], kDisplayFd);
        if (devNull >= 0) {
            ::dup2(devNull, STDOUT_FILENO);
            ::dup2(devNull, STDERR_FILENO);
        }
        ::execv(program.c_str(), argv.data());
        ::_exit(127);
    }
    if (devNull >= 0)
        ::close(devNull);
    ::close(fds[1]);
    if (pid < 0) {
        ::close(fds[0]);
        why_ = "cannot start Xvfb";
        return false;
    }
    pid_ = pid;

    // Xvfb writes "N\n" once it accepts connections.
    std::string text;
    pollfd p{fds[0], POLLIN, 0};
    while (text.find('\n') == std::string::npos) {
        const int n = ::poll(&p, 1, kStartTimeoutMs);
        if (n < 0 && errno == EINTR)
            continue;
        char buf[32];
        const ssize_t got = n > 0 ? ::read(fds[0], buf, sizeof(buf)) : 0;
        if (got <= 0)
            break;
        text.append(buf, static_cast<std::size_t>(got));
    }
    ::close(fds[0]);
    const int number = text.find('\n') != std::string::npos ? std::atoi(text.c_str()) : -1;
    if (number < 0 || text.empty() || text[0] < '0' || text[0] > '9') {
        stop(SIGKILL);
        why_ = "Xvfb did not report a display number within 10 s";
        return false;
    }
    number_ = number;
    name_ = ":" + std::to_string(number);
    return true;
}

void XvfbServer::stop(int signal)
{
    if (pid_ <= 0)
        return;
    ::kill(pid_, signal);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
}

} // namespace depthtouch::testing
