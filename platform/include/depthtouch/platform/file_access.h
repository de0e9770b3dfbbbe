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
#include <cstdio>
#include <optional>
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

/// \brief A file output written as a stream (rsync's way): a regular file or a new path is written
/// under its temporary name beside it (planOutput()) and renamed over the final name by commit()
/// only, after every byte reached the disk; a device or a FIFO with a reader is written in place.
/// Destroyed or abort()ed without a successful commit(), the temporary file is removed and the
/// final name keeps what it held. Move-only; thread-bound (one writer).
class OutputFile {
public:
    OutputFile() = default;
    ~OutputFile() { abort(); }
    OutputFile(OutputFile &&other) noexcept;
    OutputFile &operator=(OutputFile &&other) noexcept;
    OutputFile(const OutputFile &) = delete;
    OutputFile &operator=(const OutputFile &) = delete;

    /// \brief Opens \a path by its plan (planOutput()).
    /// \return the open output; Errc::InvalidArgument as planOutput(), or when the file cannot be
    ///         created or opened (errno set).
    static Result<OutputFile> open(const std::string &path);

    /// \return true between a successful open() and commit() or abort().
    [[nodiscard]] bool isOpen() const noexcept { return file_ != nullptr; }
    /// \return the stream to write (null when not open).
    [[nodiscard]] std::FILE *stream() const noexcept { return file_; }
    /// \return the temporary name being written, empty when written in place or not open.
    [[nodiscard]] const std::string &tempPath() const noexcept { return tempPath_; }

    /// \brief Flushes, checks the stream's error flag, syncs, closes and renames the temporary file
    /// over the final name.
    /// \return Errc::Io when a write, the sync, the close or the rename failed (errno of the
    ///         first failure; the temporary file is removed); Errc::InvalidState when not open.
    Result<void> commit();

    /// \brief Closes without finishing: the temporary file is removed (in place: just closed).
    void abort() noexcept;

private:
    std::FILE *file_ = nullptr;
    std::string finalPath_;
    std::string tempPath_; ///< Empty when written in place.
};

/// \brief Writes \a bytes to \a path by its plan (planOutput()): Replace writes the temporary file,
/// flushes and renames it; InPlace writes the device or FIFO directly. On failure no temporary
/// file is left and a replaced path keeps its old content.
/// \return Errc::InvalidArgument as planOutput(), or when the output cannot be created or
///         opened (missing directory, no permission; errno set): the path is unusable;
///         Errc::Io when writing (e.g. ENOSPC on /dev/full), closing or renaming fails: the output
///         is lost.
Result<void> writeOutputFile(const std::string &path, std::string_view bytes);

/// \brief Checks that a new file can be made in the folder \a dir now (a file is created there
/// and removed at once: permissions, a read-only or full file system, root's rights all count).
/// \return Errc::InvalidArgument when \a dir is not a folder or refuses new files (EACCES, EPERM,
///         EROFS; errno set); Errc::Io for another failure (ENOSPC, EDQUOT, EIO: lost output).
Result<void> checkFolderWritable(const std::string &dir);

/// \brief The identity of what a path names, to tell whether two paths name the same file however
/// they are spelled (symbolic links and `..` resolved by the kernel): an existing file's device and
/// inode; for a new path, its folder's device and inode and its last name.
struct FileIdentity {
    std::uint64_t device = 0;
    std::uint64_t inode = 0;
    std::string name;     ///< The last name for a new path; empty for an existing file.
    bool regular = false; ///< An existing regular file (not a device, FIFO or folder).
    friend bool operator==(const FileIdentity &a, const FileIdentity &b)
    {
        return a.device == b.device && a.inode == b.inode && a.name == b.name;
    }
    friend bool operator!=(const FileIdentity &a, const FileIdentity &b) { return !(a == b); }
};

/// \brief The identity of \a path (see FileIdentity): a dangling symbolic link is the path it
/// points to (writing through it creates that file).
/// \return nullopt when \a path names nothing and no folder of it exists (nor can), or is empty.
std::optional<FileIdentity> fileIdentity(const std::string &path);

} // namespace depthtouch::platform
