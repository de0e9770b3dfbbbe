#pragma once
/// \file
/// \brief Subcommands of the `depthtouch` executable. Each one registers itself on the CLI11 app
/// and, when it runs, stores the process exit code: 0 success, 1 runtime failure, 2 bad input or
/// options. Thread-safety: main thread only.

namespace CLI {
class App;
}

namespace depthtouch::cli {

/// Exit codes shared by every subcommand.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitBadInput = 2;
/// A command ended by a stop signal before its work was done (128 + SIGINT, as shells report
/// Ctrl-C).
inline constexpr int kExitInterrupted = 130;

/// Adds one subcommand to \a app; its callback writes the exit code to \a exitCode.
using RegisterCommand = void (*)(CLI::App &app, int &exitCode);

void registerDemoCommand(CLI::App &app, int &exitCode);
void registerBackendsCommand(CLI::App &app, int &exitCode);
void registerTouchCommand(CLI::App &app, int &exitCode);
void registerEncodeCommand(CLI::App &app, int &exitCode);
void registerProbeCommand(CLI::App &app, int &exitCode);
void registerPlayCommand(CLI::App &app, int &exitCode);
/// `depthtouch bench`: a group; each benchmark adds itself under it.
void registerBenchCommand(CLI::App &app, int &exitCode);
void registerBenchHapticsCommand(CLI::App &bench, int &exitCode);
void registerBenchRenderCommand(CLI::App &bench, int &exitCode);
void registerBenchRtCommand(CLI::App &bench, int &exitCode);
void registerBenchMediaCommand(CLI::App &bench, int &exitCode);
void registerBenchFeelCommand(CLI::App &bench, int &exitCode);
void registerBenchAvCommand(CLI::App &bench, int &exitCode);
void registerBenchStabilityCommand(CLI::App &bench, int &exitCode);

} // namespace depthtouch::cli
