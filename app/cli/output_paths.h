#pragma once
/// \file
/// \brief A command's `--out DIR`, checked before its long work (the output checks themselves are
/// depthtouch/platform/output_paths.h). Thread-safety: reentrant.

#include <string>
#include <string_view>

#include "depthtouch/platform/output_paths.h"

namespace depthtouch::cli {

/// \brief platform::checkOutputFolder() of a command's `--out DIR`, run before its long work: on
/// failure prints "depthtouch COMMAND: why" on stderr. \return kExitOk, or the exit code (1 or 2).
int checkOutFolder(std::string_view command, const std::string &dir);

} // namespace depthtouch::cli
