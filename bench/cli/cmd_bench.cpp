/// \file
/// \brief `depthtouch bench`: benchmark programs (speed and accuracy figures, CSV + PNG charts).

#include "command_line.h"
#include "commands.h"

namespace depthtouch::cli {

void registerBenchCommand(CLI::App &app, int &exitCode)
{
    CLI::App &bench =
        addCommand(app, "bench", "Benchmarks: print figures, write CSV, JSON and PNG charts");
    requireCommand(bench);
    registerBenchHapticsCommand(bench, exitCode);
    registerBenchRenderCommand(bench, exitCode);
    registerBenchRtCommand(bench, exitCode);
    registerBenchMediaCommand(bench, exitCode);
    registerBenchFeelCommand(bench, exitCode);
    registerBenchAvCommand(bench, exitCode);
    registerBenchStabilityCommand(bench, exitCode);
}

} // namespace depthtouch::cli
