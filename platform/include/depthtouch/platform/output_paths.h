#pragma once
/// \file
/// \brief Output files named on the command line (`--record`, `--force-log`, `--stats`): checked
/// before a run, so that a mistyped folder is bad input at once and an output that cannot take a
/// byte (/dev/full) is lost output at once, not after a whole run (they are written with
/// writeOutputFile, which reports every error).
/// An output is also compared with every input and every other output by file identity (device and
/// inode, symbolic links and `..` resolved), never by spelling: an output that names an input or
/// another output is bad input before any work starts (as `cp` and `sort -o` refuse it).
/// Thread-safety: reentrant.

#include <string>
#include <string_view>
#include <vector>

namespace depthtouch::platform {

/// \brief The exit codes an OutputPathCheck carries (those of the `depthtouch` commands): usable,
/// lost output (it cannot be written), bad input.
inline constexpr int kOutputUsable = 0;
inline constexpr int kOutputLost = 1;
inline constexpr int kOutputBadInput = 2;

/// \brief The result of checkOutputPath(): exit code 0 (usable), 1 (cannot be written: lost
/// output) or 2 (bad input), and the one-line reason.
struct OutputPathCheck {
    int exitCode = 0;
    std::string message; ///< e.g. "--record '/nonexistent/r.mkv': no folder '/nonexistent'".
};

/// \brief Checks the output path \a path of option \a option (e.g. "--stats") without changing
/// anything: its folder must exist, be a folder and take a new file (checkFolderWritable():
/// a read-only folder is bad input, a full one lost output); an existing directory is bad input
/// unless \a directoryIsLost; an existing non-regular file other than a FIFO (a device) must accept
/// a write of zero bytes (/dev/full does not: lost output). An empty \a path is fine (no output).
OutputPathCheck checkOutputPath(std::string_view option, const std::string &path,
                                bool directoryIsLost = false);

/// \brief Checks an output folder \a dir of option \a option (`--snapshot-dir`, `--out DIR`): it
/// may not exist yet, but then the nearest folder that does must take new files; an existing one
/// must be a folder that takes new files. Nothing is left changed. An empty \a dir is fine.
OutputPathCheck checkOutputFolder(std::string_view option, const std::string &dir);

/// \brief A path named on the command line and how a message names it ("--stats", "the input").
struct NamedPath {
    std::string option;
    std::string path;
};

/// \brief Refuses (bad input) an output of \a outputs that is the same file as one of \a inputs
/// or as another output, by fileIdentity(). Skipped: empty paths, URLs (`scheme://`),
/// inputs that are not existing regular files (a device, a FIFO, a name that is not a file such
/// as `synthetic:head`), and outputs that are devices or FIFOs (written in place, never
/// replaced: `/dev/null` may be named twice).
/// \return exit code 0, or 2 with the line "OUT 'a' is the same file as IN 'b'".
OutputPathCheck checkDistinctPaths(const std::vector<NamedPath> &inputs,
                                   const std::vector<NamedPath> &outputs);

} // namespace depthtouch::platform
