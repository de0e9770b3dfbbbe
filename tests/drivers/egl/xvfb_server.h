#pragma once
/// \file
/// \brief A private Xvfb X server for tests of the X11 display: started on a free display number
/// (Xvfb -displayfd picks it and reports it once the server accepts connections), stopped or
/// killed on request, restarted on the same number. The server ends with the thread that started
/// it, even when the test program crashes (PR_SET_PDEATHSIG).
/// Thread-safety: thread-bound.

#include <string>

#include <sys/types.h>

namespace depthtouch::testing {

class XvfbServer {
public:
    XvfbServer() = default;
    ~XvfbServer();
    XvfbServer(const XvfbServer &) = delete;
    XvfbServer &operator=(const XvfbServer &) = delete;

    /// \return the path of the Xvfb program found on $PATH, or an empty string.
    static std::string findProgram();

    /// \brief Starts Xvfb with one 1280×720×24 screen; on the display number of the last start()
    /// when \a reuseNumber (a restart), else on a free one.
    /// \return false (with why()) when Xvfb is missing or did not come up within 10 s.
    bool start(bool reuseNumber = false);
    /// Ends the server with \a signal (SIGTERM: clean, SIGKILL: as a crash) and reaps it.
    void stop(int signal);
    /// \return the display name, e.g. ":93"; empty before the first start().
    [[nodiscard]] const std::string &name() const noexcept { return name_; }
    [[nodiscard]] bool running() const noexcept { return pid_ > 0; }
    [[nodiscard]] const std::string &why() const noexcept { return why_; }

private:
    pid_t pid_ = -1;
    int number_ = -1;
    std::string name_;
    std::string why_;
};

} // namespace depthtouch::testing
