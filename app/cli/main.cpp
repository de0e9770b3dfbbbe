/// \file
/// \brief `depthtouch`: the one executable of DepthTouch. Subcommands are listed in kCommands.

#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.h"

namespace {

using depthtouch::cli::RegisterCommand;

/// Every subcommand, in the order `depthtouch --help` lists them.
constexpr RegisterCommand kCommands[] = {
    &depthtouch::cli::registerDemoCommand,
    &depthtouch::cli::registerPlayCommand,
    &depthtouch::cli::registerBackendsCommand,
    &depthtouch::cli::registerTouchCommand,
    &depthtouch::cli::registerEncodeCommand,
    &depthtouch::cli::registerProbeCommand,
    &depthtouch::cli::registerBenchCommand,
};

} // namespace

int main(int argc, char **argv)
{
    CLI::App app{"DepthTouch: play color + depth 3D video and touch it with a haptic device",
                 "depthtouch"};
    app.set_version_flag("--version", "depthtouch " DT_VERSION);
    app.require_subcommand(1);
    // Bad input gets one clear line (CLI11's default adds a second "Run with --help" line).
    app.failure_message([](const CLI::App *, const CLI::Error &e) {
        return std::string("depthtouch: ") + e.what() + " (see --help)\n";
    });
    int exitCode = depthtouch::cli::kExitOk;
    for (RegisterCommand reg : kCommands)
        reg(app, exitCode);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError &e) {
        const int code = app.exit(e);
        // CLI11 returns 0 for --help/--version; any real parse error is bad input.
        return code == 0 ? 0 : depthtouch::cli::kExitBadInput;
    }
    return exitCode;
}
