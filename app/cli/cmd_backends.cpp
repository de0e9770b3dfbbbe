/// \file
/// \brief `depthtouch backends`: the compiled-in HAL backends of each kind, in autoprobe order.

#include <cstdio>

#include "command_line.h"
#include "commands.h"
#include "depthtouch/drivers/backends.h"

namespace depthtouch::cli {

void registerBackendsCommand(CLI::App &app, int &exitCode)
{
    CLI::App &cmd = addCommand(app, "backends", "List the compiled-in HAL backends of each kind");
    onRun(cmd, [&exitCode] {
        using drivers::BackendKind;
        constexpr BackendKind kKinds[] = {BackendKind::MediaSource, BackendKind::VideoDecoder,
                                          BackendKind::Display,     BackendKind::HapticDevice,
                                          BackendKind::RemoteInput, BackendKind::DepthCamera,
                                          BackendKind::AudioOutput};
        for (BackendKind kind : kKinds) {
            std::printf("%s:\n", drivers::backendKindName(kind));
            for (const hal::BackendInfo &b : drivers::listBackends(kind))
                std::printf("  %-10s %s%s\n", b.name, b.description,
                            b.autoProbe ? "" : " (only when named)");
        }
        exitCode = kExitOk;
    });
}

} // namespace depthtouch::cli
