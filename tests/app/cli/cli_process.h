#pragma once
/// \file
/// \brief Test support: runs a program (the `depthtouch` executable) with a time limit, its
/// stdout and stderr kept apart, and signals it while it runs. Header-only; POSIX.
/// Thread-safety: one Process per thread.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace depthtouch::testing {

/// \brief How a run ended.
struct ProcessResult {
    int exitCode = -1;     ///< Exit status, or -1 when killed by a signal.
    int signal = 0;        ///< The signal that ended it, 0 when it exited.
    bool timedOut = false; ///< Killed (SIGKILL) at the time limit.
    double seconds = 0.0;  ///< Wall time from start to end.
    std::string out;       ///< Everything written to stdout.
    std::string err;       ///< Everything written to stderr.

    /// \return the number of lines on stderr (a last line without '\n' counts).
    [[nodiscard]] std::size_t errLines() const
    {
        const auto n = static_cast<std::size_t>(std::count(err.begin(), err.end(), '\n'));
        return n + (!err.empty() && err.back() != '\n' ? 1 : 0);
    }
};

/// \return \a r in one line and stderr after it, for a failed expectation: the exit code, a
/// time-out, the signal, the run time (seconds) and at most the first 2000 characters of stderr.
inline std::string describe(const ProcessResult &r)
{
    return "exit " + std::to_string(r.exitCode) + (r.timedOut ? " (timed out)" : "") + ", signal " +
           std::to_string(r.signal) + ", " + std::to_string(r.seconds) + " s, stderr:\n" +
           r.err.substr(0, 2000);
}

/// Waits until process \a pid catches signal \a sig (its handler is installed: /proc/PID/status,
/// SigCgt), at most \a limit. \return whether it does. A test that signals a program must wait
/// for this, not for a fixed time: a sanitizer build on a busy machine starts in seconds.
inline bool waitUntilCaught(pid_t pid, int sig, std::chrono::milliseconds limit)
{
    const auto end = std::chrono::steady_clock::now() + limit;
    const std::string path = "/proc/" + std::to_string(pid) + "/status";
    while (std::chrono::steady_clock::now() < end) {
        std::ifstream in(path);
        std::string line;
        while (std::getline(in, line)) {
            if (line.rfind("SigCgt:", 0) != 0)
                continue;
            const unsigned long long mask = std::stoull(line.substr(7), nullptr, 16);
            if ((mask >> (sig - 1)) & 1u)
                return true;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
}

/// \brief A child process started at construction; killed (SIGKILL) if still running at
/// destruction.
class Process {
public:
    explicit Process(const std::vector<std::string> &argv)
    {
        outFd_ = anonymousFile();
        errFd_ = anonymousFile();
        start_ = std::chrono::steady_clock::now();
        pid_ = ::fork();
        if (pid_ == 0) {
            const int in = ::open("/dev/null", O_RDONLY);
            ::dup2(in, STDIN_FILENO);
            ::dup2(outFd_, STDOUT_FILENO);
            ::dup2(errFd_, STDERR_FILENO);
            std::vector<char *> args;
            for (const std::string &a : argv)
                args.push_back(const_cast<char *>(a.c_str()));
            args.push_back(nullptr);
            ::execv(args[0], args.data());
            ::_exit(127);
        }
    }
    ~Process()
    {
        if (pid_ > 0 && !done_) {
            ::kill(pid_, SIGKILL);
            ::waitpid(pid_, nullptr, 0);
        }
        ::close(outFd_);
        ::close(errFd_);
    }
    Process(const Process &) = delete;
    Process &operator=(const Process &) = delete;

    /// Sends \a sig to the child.
    void signal(int sig) const { ::kill(pid_, sig); }
    /// \return the child's process id.
    [[nodiscard]] pid_t pid() const noexcept { return pid_; }

    /// \brief Waits up to \a limit for the end (then kills it with SIGKILL and reports timedOut).
    ProcessResult wait(std::chrono::milliseconds limit)
    {
        ProcessResult r;
        int status = 0;
        const auto end = start_ + limit;
        for (;;) {
            const pid_t got = ::waitpid(pid_, &status, WNOHANG);
            if (got == pid_)
                break;
            if (got < 0)
                return r;
            if (std::chrono::steady_clock::now() >= end) {
                ::kill(pid_, SIGKILL);
                ::waitpid(pid_, &status, 0);
                r.timedOut = true;
                break;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        done_ = true;
        r.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        if (WIFEXITED(status))
            r.exitCode = WEXITSTATUS(status);
        else if (WIFSIGNALED(status))
            r.signal = WTERMSIG(status);
        r.out = readAll(outFd_);
        r.err = readAll(errFd_);
        return r;
    }

private:
    static int anonymousFile()
    {
        char name[] = "/tmp/dt-process-XXXXXX";
        const int fd = ::mkstemp(name);
        ::unlink(name);
        return fd;
    }
    static std::string readAll(int fd)
    {
        std::string s;
        ::lseek(fd, 0, SEEK_SET);
        char buf[4096];
        ssize_t n = 0;
        while ((n = ::read(fd, buf, sizeof buf)) > 0 && s.size() < (std::size_t{64} << 20))
            s.append(buf, static_cast<std::size_t>(n));
        return s;
    }

    pid_t pid_ = -1;
    int outFd_ = -1;
    int errFd_ = -1;
    bool done_ = false;
    std::chrono::steady_clock::time_point start_;
};

/// \brief Runs \a argv to its end or for at most \a limit.
inline ProcessResult runProcess(const std::vector<std::string> &argv,
                                std::chrono::milliseconds limit)
{
    Process p(argv);
    return p.wait(limit);
}

} // namespace depthtouch::testing
