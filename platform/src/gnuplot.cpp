#include "depthtouch/platform/gnuplot.h"

#include "depthtouch/platform/enum_names.h"

#include <array>
#include <cerrno>
#include <fcntl.h>
#include <spawn.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

namespace depthtouch::platform {

namespace {

/// Runs gnuplot on \a script with the file actions \a actions (nullptr: none) and waits for it.
PlotStatus spawnGnuplot(const std::string &script,
                        const posix_spawn_file_actions_t *actions) noexcept
{
    char program[] = "gnuplot";
    // posix_spawnp takes non-const argv strings but does not modify them.
    char *argv[] = {program, const_cast<char *>(script.c_str()), nullptr};
    pid_t pid = 0;
    // glibc's posix_spawnp reports a missing program (ENOENT) as its return value.
    const int err = posix_spawnp(&pid, program, actions, nullptr, argv, environ);
    if (err == ENOENT)
        return PlotStatus::NoGnuplot;
    if (err != 0)
        return PlotStatus::Failed;
    int status = 0;
    while (waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR)
            return PlotStatus::Failed;
    }
    return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? PlotStatus::Drawn : PlotStatus::Failed;
}

} // namespace

PlotStatus runGnuplot(const std::string &script) noexcept
{
    return spawnGnuplot(script, nullptr);
}

PlotStatus runGnuplot(const std::string &script, const std::string &messages) noexcept
{
    posix_spawn_file_actions_t actions;
    if (posix_spawn_file_actions_init(&actions) != 0)
        return PlotStatus::Failed;
    PlotStatus st = PlotStatus::Failed;
    if (posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, messages.c_str(),
                                         O_WRONLY | O_CREAT | O_APPEND, 0644) == 0)
        st = spawnGnuplot(script, &actions);
    posix_spawn_file_actions_destroy(&actions);
    return st;
}

const char *plotStatusNote(PlotStatus status) noexcept
{
    static constexpr std::array<const char *, 3> kNotes = {
        "", "gnuplot not found: no PNG chart (install gnuplot-nox)",
        "gnuplot failed: the PNG chart may be missing"};
    return enumName(status, kNotes, "");
}

} // namespace depthtouch::platform
