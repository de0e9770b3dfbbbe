/// \file
/// \brief `depthtouch`: the one executable of DepthTouch. Subcommands are listed in kCommands.

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>

#include "command_line.h"
#include "commands.h"
#include "completion.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/stack_limit.h"

namespace {

using depthtouch::cli::RegisterCommand;

/// Every subcommand, in the order `depthtouch --help` lists them.
constexpr RegisterCommand kCommands[] = {
    &depthtouch::cli::registerDemoCommand,     &depthtouch::cli::registerPlayCommand,
    &depthtouch::cli::registerBackendsCommand, &depthtouch::cli::registerTouchCommand,
    &depthtouch::cli::registerEncodeCommand,   &depthtouch::cli::registerProbeCommand,
    &depthtouch::cli::registerBenchCommand,    &depthtouch::cli::registerCompletionCommand,
};

/// \return \a exitCode, or for a command that succeeded kExitFailure after one line when the
/// standard output lost a byte (a full disk, /dev/full, a reader that left): what a command
/// printed is its output too.
int checkStandardOutput(int exitCode)
{
    errno = 0;
    const bool flushed = std::fflush(stdout) == 0;
    const int err = errno;
    if ((flushed && std::ferror(stdout) == 0) || exitCode != depthtouch::cli::kExitOk)
        return exitCode; // a failed command has said why in its own line
    depthtouch::platform::printStderrLine(depthtouch::platform::LogLevel::Error,
                                          "depthtouch: cannot write the standard output: %s",
                                          std::strerror(err != 0 ? err : EIO));
    return depthtouch::cli::kExitFailure;
}

/// The new-handler: an allocation that fails (a memory or address space limit, `ulimit -v`) ends
/// the process with one line and exit 1 on whichever thread it happens, instead of an uncaught
/// std::bad_alloc (an abort and a core dump). Writes with fputs on the unbuffered stderr: nothing
/// here allocates.
[[noreturn]] void outOfMemory()
{
    std::fputs("depthtouch: out of memory: an allocation failed (is the address space limit, "
               "ulimit -v, too small?)\n",
               stderr);
    std::_Exit(depthtouch::cli::kExitFailure);
}

} // namespace

int main(int argc, char **argv)
{
    depthtouch::cli::CommandLine line{
        "DepthTouch: play color + depth 3D video and touch it with a haptic device", "depthtouch"};
    line.setVersion("depthtouch " DT_VERSION);
    depthtouch::cli::requireCommand(line.root());
    // Bad input gets one clear line, an error line in the journal of a service.
    line.sayMistakesInOneLine();
    // A reader that leaves (`| head`) is a write error (EPIPE) reported in one line, not a silent
    // death by SIGPIPE; sockets and pipes of the player see the same error.
    std::signal(SIGPIPE, SIG_IGN);
    std::set_new_handler(&outOfMemory);
    // `ulimit -s 48` would crash the first deep call of any thread (glibc sizes them all from it).
    if (const std::string why = depthtouch::platform::ensureStackLimit(); !why.empty()) {
        depthtouch::platform::printStderrLine(depthtouch::platform::LogLevel::Error,
                                              "depthtouch: %s", why.c_str());
        return depthtouch::cli::kExitFailure;
    }
    int exitCode = depthtouch::cli::kExitOk;
    for (RegisterCommand reg : kCommands)
        reg(line.root(), exitCode);
    switch (line.parseProgram(argc, argv)) {
    case depthtouch::cli::CommandLine::Parsed::Refused:
        return depthtouch::cli::kExitBadInput;
    case depthtouch::cli::CommandLine::Parsed::Shown:
        return checkStandardOutput(depthtouch::cli::kExitOk);
    case depthtouch::cli::CommandLine::Parsed::Ran:
        break;
    }
    return checkStandardOutput(exitCode);
}
