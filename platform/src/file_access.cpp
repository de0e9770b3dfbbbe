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

/// Writes all of \a bytes to \a fd (blocking descriptor). \return false with errno on failure.
bool writeAll(int fd, std::string_view bytes) noexcept
{
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            if (n == 0)
                errno = EIO;
            return false;
        }
        done += static_cast<std::size_t>(n);
    }
    return true;
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

Result<void> writeOutputFile(const std::string &path, std::string_view bytes)
{
    auto plan = planOutput(path);
    if (!plan)
        return unexpected(plan.error());
    if (plan->mode == OutputMode::InPlace) {
        UniqueFd fd(::open(plan->path.c_str(), O_WRONLY | O_NONBLOCK | O_CREAT | O_CLOEXEC, 0666));
        if (!fd)
            return unexpected(Errc::InvalidArgument, "cannot open the output", errno);
        DT_TRY(clearNonBlocking(fd.get()));
        if (!writeAll(fd.get(), bytes))
            return unexpected(Errc::Io, "cannot write the output", errno);
        if (::close(fd.release()) != 0)
            return unexpected(Errc::Io, "cannot write the output", errno);
        return ok();
    }
    const std::string &tmp = plan->tempPath;
    UniqueFd fd(::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666));
    if (!fd)
        return unexpected(Errc::InvalidArgument, "cannot create the output", errno);
    if (!writeAll(fd.get(), bytes) || ::fsync(fd.get()) != 0 || ::close(fd.release()) != 0) {
        const int err = errno;
        (void)::unlink(tmp.c_str());
        return unexpected(Errc::Io, "cannot write the output", err);
    }
    if (::rename(tmp.c_str(), plan->path.c_str()) != 0) {
        const int err = errno;
        (void)::unlink(tmp.c_str());
        return unexpected(Errc::Io, "cannot rename the output into place", err);
    }
    return ok();
}

} // namespace depthtouch::platform
