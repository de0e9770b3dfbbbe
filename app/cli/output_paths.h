#pragma once
/// \file
/// \brief Output files named on the command line (`--record`, `--force-log`, `--stats`): checked
/// before a run, so that a mistyped folder is bad input at once and an output that cannot take a
/// byte (/dev/full) is lost output at once, not after a whole run (they are written with
/// platform::writeOutputFile, which reports every error).
/// Thread-safety: reentrant.

#include <string>
#include <string_view>

namespace depthtouch::cli {

/// \brief The result of checkOutputPath(): exit code 0 (usable), 1 (cannot be written: lost
/// output) or 2 (bad input), and the one-line reason.
struct OutputPathCheck {
    int exitCode = 0;
    std::string message; ///< e.g. "--record '/nonexistent/r.mkv': no folder '/nonexistent'".
};

/// \brief Checks the output path \a path of option \a option (e.g. "--stats") without creating or
/// changing anything: its folder must exist and be a folder (else bad input); an existing
/// directory is bad input unless \a directoryIsLost; an existing non-regular file other than a
/// FIFO (a device) must accept a write of zero bytes (/dev/full does not: lost output).
/// An empty \a path is fine (no output).
OutputPathCheck checkOutputPath(std::string_view option, const std::string &path,
                                bool directoryIsLost = false);

} // namespace depthtouch::cli
