/// \file
/// \brief A command's `--out DIR`: see output_paths.h.

#include "output_paths.h"

#include <cstdio>

#include "commands.h"
#include "depthtouch/platform/message_text.h"

namespace depthtouch::cli {

int checkOutFolder(std::string_view command, const std::string &dir)
{
    const platform::OutputPathCheck c = platform::checkOutputFolder("--out", dir);
    if (c.exitCode != kExitOk)
        std::fprintf(stderr, "depthtouch %.*s: %s\n", static_cast<int>(command.size()),
                     command.data(), platform::printableText(c.message, 400).c_str());
    return c.exitCode;
}

} // namespace depthtouch::cli
