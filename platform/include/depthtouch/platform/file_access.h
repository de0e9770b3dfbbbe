#pragma once
/// \file
/// \brief Reading input files and writing output files safely, whatever the path names: a bounded
/// read (a size limit, and a bounded wait for a FIFO's writer instead of blocking in open(2)), and
/// an output write that replaces only a regular file (or creates a new path) atomically, writes a
/// character device or a FIFO with a reader in place, and refuses anything else.
///
/// Errors carry static messages that name the kind of path ("is a directory", "is a FIFO with no
/// writer"); callers add the path. Codes: Errc::InvalidArgument for a path of the wrong kind or an
/// input over its limit (bad input), Errc::Timeout for a FIFO whose writer did not come,
/// Errc::Io for a failed read or write (with errno). Thread-safety: reentrant (no shared state).
/// The header is C++17-clean.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "depthtouch/platform/result.h"
#include "depthtouch/platform/unique_fd.h"

namespace depthtouch::platform {

/// \brief What a path names (stat(2): symbolic links followed).
enum class PathKind : std::uint8_t {
    Missing,     ///< Nothing there (or a dangling link).
    Regular,     ///< A regular file.
    Directory,   ///< A directory.
    CharDevice,  ///< A character device (/dev/null, /dev/zero, a tty).
    BlockDevice, ///< A block device (a disk).
    Fifo,        ///< A named pipe.
    Socket,      ///< A Unix-domain socket.
    Other,       ///< stat(2) failed for another reason (permission, name too long).
};

/// \return the kind of \a path (links followed).
PathKind pathKind(const char *path) noexcept;

/// \return "a regular file", "a directory", "a FIFO", ... (static string, for messages).
const char *pathKindName(PathKind kind) noexcept;

/// \brief How long an input FIFO may wait for its writer by default (ms): the same 10 s the media
/// sources give a silent stream.
inline constexpr std::chrono::milliseconds kDefaultFifoWait{10000};

/// \brief Opens the FIFO \a path for reading without blocking in open(2): waits at most \a wait
/// for a writer to write its first byte (poll(2)).
/// \return the descriptor, O_NONBLOCK still set (so a reader that honours EAGAIN can bound its own
///         waits; clear it with fcntl for blocking reads); Errc::Timeout when no data came within
///         \a wait, Errc::Io when open(2) or poll(2) fails.
Result<UniqueFd> openFifoForReading(const char *path, std::chrono::milliseconds wait);

/// \brief Reads the whole of \a path into memory, bounded: a regular file larger than \a maxBytes
/// is refused before anything is read, a device or FIFO (e.g. /dev/zero) after \a maxBytes + 1
/// bytes; a FIFO waits at most \a wait for its writer, then for each further read.
/// \return the bytes; Errc::InvalidArgument for a directory, socket or block device ("is a
///         directory"), or more than \a maxBytes ("is larger than the limit"); Errc::Timeout
///         (FIFO without a writer); Errc::Io (missing, unreadable; errno set).
Result<std::vector<std::uint8_t>>
readFileBounded(const std::string &path, std::size_t maxBytes,
                std::chrono::milliseconds wait = kDefaultFifoWait);

/// \brief How an output path is written.
enum class OutputMode : std::uint8_t {
    /// A new path or a regular file: written under a temporary name in the same directory and
    /// renamed over it (atomic: never a partial file).
    Replace,
    /// A character device (/dev/null, /dev/full) or a FIFO with a reader: opened and written as it
    /// is, never replaced.
    InPlace,
};

/// \brief Where and how to write an output.
struct OutputPlan {
    OutputMode mode = OutputMode::Replace;
    /// The path to write: \a path itself, or for a symbolic link the file it points to (so the
    /// link stays a link).
    std::string path;
    /// Replace only: the temporary name beside it (`PATH.tmp.PID`).
    std::string tempPath;
};

/// \brief Decides how \a path may be written (see OutputMode).
/// \return the plan; Errc::InvalidArgument for a directory, block device, socket or a FIFO with no
///         reader (opening it would block), a new path in a folder that is missing or not
///         writable, or an empty path.
Result<OutputPlan> planOutput(const std::string &path);

/// \brief Writes \a bytes to \a path by its plan (planOutput()): Replace writes the temporary file,
/// flushes and renames it; InPlace writes the device or FIFO directly. On failure no temporary
/// file is left and a replaced path keeps its old content.
/// \return Errc::InvalidArgument as planOutput(), or when the output cannot be created or
///         opened (missing directory, no permission; errno set): the path is unusable;
///         Errc::Io when writing (e.g. ENOSPC on /dev/full), closing or renaming fails: the output
///         is lost.
Result<void> writeOutputFile(const std::string &path, std::string_view bytes);

} // namespace depthtouch::platform
