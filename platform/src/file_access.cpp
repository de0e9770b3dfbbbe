#include "depthtouch/platform/file_access.h"

#include "depthtouch/platform/enum_names.h"

#include <array>
#include <cerrno>
#include <climits>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <utility>

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

namespace depthtouch::platform {

namespace {

using Clock = std::chrono::steady_clock;

PathKind kindOf(mode_t mode) noexcept
{
    // The file types of st_mode (S_IFMT bits) that have a PathKind of their own.
    static constexpr std::array<std::pair<mode_t, PathKind>, 6> kTypes = {{
        {S_IFREG, PathKind::Regular},
        {S_IFDIR, PathKind::Directory},
        {S_IFCHR, PathKind::CharDevice},
        {S_IFBLK, PathKind::BlockDevice},
        {S_IFIFO, PathKind::Fifo},
        {S_IFSOCK, PathKind::Socket},
    }};
    for (const auto &[type, kind] : kTypes)
        if ((mode & S_IFMT) == type)
            return kind;
    return PathKind::Other;
}

/// Waits until \a fd has data (or its writer hung up) or \a deadline passes.
/// \return true when readable; false on timeout. errno set on a poll failure (returns false too).
bool waitReadable(int fd, Clock::time_point deadline, bool &pollFailed) noexcept
{
    pollFailed = false;
    for (;;) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
        if (left <= 0)
            return false;
        pollfd p{fd, POLLIN, 0};
        const int n = ::poll(&p, 1, left > INT_MAX ? INT_MAX : static_cast<int>(left));
        if (n > 0)
            return true;
        if (n < 0 && errno != EINTR) {
            pollFailed = true;
            return false;
        }
    }
}

Result<void> clearNonBlocking(int fd) noexcept
{
    const int flags = ::fcntl(fd, F_GETFL);
    if (flags < 0 || ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) < 0)
        return unexpected(Errc::Io, "cannot make the descriptor blocking", errno);
    return ok();
}

} // namespace

PathKind pathKind(const char *path) noexcept
{
    struct stat st {};
    if (path == nullptr || ::stat(path, &st) != 0)
        return path != nullptr && (errno == ENOENT || errno == ENOTDIR) ? PathKind::Missing
                                                                        : PathKind::Other;
    return kindOf(st.st_mode);
}

const char *pathKindName(PathKind kind) noexcept
{
    static constexpr std::array<const char *, 8> kNames = {
        "missing",        "a regular file", "a directory", "a character device",
        "a block device", "a FIFO",         "a socket",    "not accessible"};
    static_assert(kNames.size() == static_cast<std::size_t>(PathKind::Other) + 1);
    return enumName(kind, kNames, "unknown");
}

Result<UniqueFd> openFifoForReading(const char *path, std::chrono::milliseconds wait)
{
    // O_NONBLOCK: open(2) of a FIFO for reading returns at once instead of waiting for a writer.
    UniqueFd fd(::open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC));
    if (!fd)
        return unexpected(Errc::Io, "cannot open the FIFO", errno);
    // A FIFO that never had a writer polls as not readable (no POLLHUP) until one writes.
    bool pollFailed = false;
    if (!waitReadable(fd.get(), Clock::now() + wait, pollFailed)) {
        if (pollFailed)
            return unexpected(Errc::Io, "cannot wait for the FIFO", errno);
        return unexpected(Errc::Timeout, "is a FIFO with no writer (gave up waiting)");
    }
    return fd;
}

Result<std::vector<std::uint8_t>> readFileBounded(const std::string &path, std::size_t maxBytes,
                                                  std::chrono::milliseconds wait)
{
    const PathKind kind = pathKind(path.c_str());
    if (kind == PathKind::Directory || kind == PathKind::Socket || kind == PathKind::BlockDevice)
        return unexpected(Errc::InvalidArgument, kind == PathKind::Directory ? "is a directory"
                                                 : kind == PathKind::Socket ? "is a socket"
                                                                            : "is a block device");
    UniqueFd fd;
    const Clock::time_point start = Clock::now();
    if (kind == PathKind::Fifo) {
        auto f = openFifoForReading(path.c_str(), wait);
        if (!f)
            return unexpected(f.error());
        fd = std::move(*f);
    } else {
        fd.reset(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
        if (!fd)
            return unexpected(Errc::Io, "cannot open the file", errno);
    }
    struct stat st {};
    if (::fstat(fd.get(), &st) != 0)
        return unexpected(Errc::Io, "cannot read the file", errno);
    if (S_ISREG(st.st_mode) && static_cast<std::uintmax_t>(st.st_size) > maxBytes)
        return unexpected(Errc::InvalidArgument, "is larger than the limit");
    std::vector<std::uint8_t> bytes;
    if (S_ISREG(st.st_mode))
        bytes.reserve(static_cast<std::size_t>(st.st_size));
    std::uint8_t buf[65536];
    // A FIFO keeps its O_NONBLOCK: each wait for more data is bounded by the same \a wait.
    Clock::time_point deadline = start + wait;
    for (;;) {
        const ssize_t n = ::read(fd.get(), buf, sizeof buf);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0 && errno == EAGAIN) {
            bool pollFailed = false;
            if (!waitReadable(fd.get(), deadline, pollFailed))
                return pollFailed ? unexpected(Errc::Io, "cannot wait for the FIFO", errno)
                                  : unexpected(Errc::Timeout, "is a FIFO whose writer went silent");
            continue;
        }
        if (n < 0)
            return unexpected(Errc::Io, "cannot read the file", errno);
        if (n == 0)
            break;
        if (bytes.size() + static_cast<std::size_t>(n) > maxBytes)
            return unexpected(Errc::InvalidArgument, "is larger than the limit");
        bytes.insert(bytes.end(), buf, buf + n);
        deadline = Clock::now() + wait;
    }
    return bytes;
}

Result<OutputPlan> planOutput(const std::string &path)
{
    if (path.empty())
        return unexpected(Errc::InvalidArgument, "empty output name");
    OutputPlan plan;
    plan.path = path;
    struct stat lst {};
    if (::lstat(path.c_str(), &lst) == 0 && S_ISLNK(lst.st_mode)) {
        // Write through the link to the file it names; the link stays.
        char *real = ::realpath(path.c_str(), nullptr);
        if (real == nullptr) {
            plan.mode = OutputMode::InPlace; // dangling: open(O_CREAT) creates its target
            return plan;
        }
        plan.path = real;
        std::free(real);
    }
    const PathKind kind = pathKind(plan.path.c_str());
    switch (kind) {
    case PathKind::Missing:
    case PathKind::Regular:
    case PathKind::Other: {
        // The temporary file goes beside it: the folder must exist and take new files.
        const std::size_t slash = plan.path.rfind('/');
        const std::string dir = slash == std::string::npos ? "."
                                : slash == 0               ? "/"
                                                           : plan.path.substr(0, slash);
        if (pathKind(dir.c_str()) != PathKind::Directory)
            return unexpected(Errc::InvalidArgument, "is in a folder that does not exist");
        if (::access(dir.c_str(), W_OK) != 0)
            return unexpected(Errc::InvalidArgument, "is in a folder that cannot be written",
                              errno);
        plan.mode = OutputMode::Replace;
        plan.tempPath = plan.path + ".tmp." + std::to_string(::getpid());
        return plan;
    }
    case PathKind::CharDevice:
        plan.mode = OutputMode::InPlace;
        return plan;
    case PathKind::Fifo: {
        // With no reader, open(O_WRONLY) would block; O_NONBLOCK fails with ENXIO instead.
        UniqueFd probe(::open(plan.path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC));
        if (!probe)
            return unexpected(Errc::InvalidArgument, "is a FIFO with no reader");
        // Held open until the process ends: closing the only write end would give the reader an
        // end of file before the output is opened for real (`cat fifo` would end, and the tool
        // would then find no reader). The reader sees the end when the process exits.
        (void)probe.release();
        plan.mode = OutputMode::InPlace;
        return plan;
    }
    case PathKind::Directory:
        return unexpected(Errc::InvalidArgument, "is a directory");
    case PathKind::BlockDevice:
        return unexpected(Errc::InvalidArgument, "is a block device (not replaced or written)");
    case PathKind::Socket:
        return unexpected(Errc::InvalidArgument, "is a socket");
    }
    return unexpected(Errc::InvalidArgument, "cannot be written");
}

OutputFile::OutputFile(OutputFile &&other) noexcept
    : file_(std::exchange(other.file_, nullptr)), finalPath_(std::move(other.finalPath_)),
      tempPath_(std::move(other.tempPath_))
{
    other.tempPath_.clear();
}

OutputFile &OutputFile::operator=(OutputFile &&other) noexcept
{
    if (this != &other) {
        abort();
        file_ = std::exchange(other.file_, nullptr);
        finalPath_ = std::move(other.finalPath_);
        tempPath_ = std::move(other.tempPath_);
        other.tempPath_.clear();
    }
    return *this;
}

Result<OutputFile> OutputFile::open(const std::string &path)
{
    auto plan = planOutput(path);
    if (!plan)
        return unexpected(plan.error());
    OutputFile out;
    UniqueFd fd;
    if (plan->mode == OutputMode::InPlace) {
        fd.reset(::open(plan->path.c_str(), O_WRONLY | O_NONBLOCK | O_CREAT | O_CLOEXEC, 0666));
        if (!fd)
            return unexpected(Errc::InvalidArgument, "cannot open the output", errno);
        DT_TRY(clearNonBlocking(fd.get()));
    } else {
        fd.reset(::open(plan->tempPath.c_str(),
                        O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0666));
        if (!fd)
            return unexpected(Errc::InvalidArgument, "cannot create the output", errno);
        out.tempPath_ = plan->tempPath;
    }
    out.finalPath_ = plan->path;
    out.file_ = ::fdopen(fd.get(), "w");
    if (out.file_ == nullptr)
        return unexpected(Errc::Io, "cannot open the output", errno); // ~OutputFile removes it
    (void)fd.release();
    return out;
}

Result<void> OutputFile::commit()
{
    if (file_ == nullptr)
        return unexpected(Errc::InvalidState, "the output is not open");
    std::FILE *f = std::exchange(file_, nullptr);
    int err = 0;
    // A write that failed earlier (a full disk) left the stream's error flag set; its errno is
    // gone by now, so it reads as EIO.
    if (std::fflush(f) != 0)
        err = errno;
    else if (std::ferror(f) != 0)
        err = EIO;
    if (err == 0 && !tempPath_.empty() && ::fsync(::fileno(f)) != 0)
        err = errno;
    if (std::fclose(f) != 0 && err == 0)
        err = errno;
    const char *what = "cannot write the output";
    if (err == 0 && !tempPath_.empty() && ::rename(tempPath_.c_str(), finalPath_.c_str()) != 0) {
        err = errno;
        what = "cannot rename the output into place";
    }
    if (err != 0 && !tempPath_.empty())
        (void)::unlink(tempPath_.c_str());
    tempPath_.clear();
    if (err != 0)
        return unexpected(Errc::Io, what, err);
    return ok();
}

void OutputFile::abort() noexcept
{
    if (file_ != nullptr)
        (void)std::fclose(std::exchange(file_, nullptr));
    if (!tempPath_.empty())
        (void)::unlink(tempPath_.c_str());
    tempPath_.clear();
}

Result<void> writeOutputFile(const std::string &path, std::string_view bytes)
{
    auto out = OutputFile::open(path);
    if (!out)
        return unexpected(out.error());
    if (!bytes.empty() &&
        std::fwrite(bytes.data(), 1, bytes.size(), out->stream()) != bytes.size()) {
        const int err = errno;
        out->abort();
        return unexpected(Errc::Io, "cannot write the output", err);
    }
    return out->commit();
}

Result<void> checkFolderWritable(const std::string &dir)
{
    const std::string folder = dir.empty() ? std::string(".") : dir;
    if (pathKind(folder.c_str()) != PathKind::Directory)
        return unexpected(Errc::InvalidArgument, "is not a folder");
    // A real file, made and removed: access(2) says yes to root on a folder where nothing can be
    // made (a read-only mount, an immutable folder, /proc).
    const std::string probe = folder + "/.dt-write-check." + std::to_string(::getpid());
    UniqueFd fd(::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600));
    if (!fd) {
        const int err = errno;
        if (err == EEXIST)
            return ok(); // a file could be made there (by this process, a moment ago)
        const bool refused = err == EACCES || err == EPERM || err == EROFS || err == ENOENT;
        return unexpected(refused ? Errc::InvalidArgument : Errc::Io,
                          "is a folder where no file can be made", err);
    }
    fd.reset();
    (void)::unlink(probe.c_str());
    return ok();
}

std::optional<FileIdentity> fileIdentity(const std::string &path)
{
    std::string p = path;
    // A dangling link is followed by hand (at most as many hops as the kernel allows).
    for (int hops = 0; hops < 40 && !p.empty(); ++hops) {
        struct stat st {};
        if (::stat(p.c_str(), &st) == 0) {
            FileIdentity id;
            id.device = static_cast<std::uint64_t>(st.st_dev);
            id.inode = static_cast<std::uint64_t>(st.st_ino);
            id.regular = S_ISREG(st.st_mode);
            return id;
        }
        const std::size_t slash = p.rfind('/');
        const std::string dir = slash == std::string::npos ? "."
                                : slash == 0               ? "/"
                                                           : p.substr(0, slash);
        struct stat lst {};
        if (::lstat(p.c_str(), &lst) == 0 && S_ISLNK(lst.st_mode)) {
            std::array<char, 4096> target{};
            const ssize_t n = ::readlink(p.c_str(), target.data(), target.size() - 1);
            if (n <= 0)
                return std::nullopt;
            const std::string to(target.data(), static_cast<std::size_t>(n));
            p = to.front() == '/' ? to : dir + "/" + to;
            continue;
        }
        // A new path: its folder (resolved by the kernel) and its last name.
        const std::string name = slash == std::string::npos ? p : p.substr(slash + 1);
        if (name.empty() || name == "." || name == ".." || ::stat(dir.c_str(), &st) != 0 ||
            !S_ISDIR(st.st_mode))
            return std::nullopt;
        FileIdentity id;
        id.device = static_cast<std::uint64_t>(st.st_dev);
        id.inode = static_cast<std::uint64_t>(st.st_ino);
        id.name = name;
        return id;
    }
    return std::nullopt;
}

} // namespace depthtouch::platform
