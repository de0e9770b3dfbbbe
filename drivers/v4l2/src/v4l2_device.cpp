#include "depthtouch/drivers/v4l2/v4l2_device.h"

#include <fcntl.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <utility>

namespace depthtouch::drivers {

namespace {

std::atomic<V4l2DeviceFactory> gFactory{nullptr};

/// N of "videoN", or -1 when \a name is not a video node name.
long videoIndex(const std::string &name) noexcept
{
    constexpr std::string_view kPrefix = "video";
    if (name.size() <= kPrefix.size() || name.compare(0, kPrefix.size(), kPrefix) != 0)
        return -1;
    char *end = nullptr;
    const char *digits = name.c_str() + kPrefix.size();
    const long n = std::strtol(digits, &end, 10);
    return (end != digits && *end == '\0' && n >= 0) ? n : -1;
}

} // namespace

std::vector<std::string> SystemV4l2Device::listNodes()
{
    std::vector<std::pair<long, std::string>> found;
    std::error_code ec;
    for (const auto &e : std::filesystem::directory_iterator("/dev", ec)) {
        const std::string name = e.path().filename().string();
        const long n = videoIndex(name);
        if (n >= 0)
            found.emplace_back(n, e.path().string());
    }
    std::sort(found.begin(), found.end());
    std::vector<std::string> out;
    out.reserve(found.size());
    for (auto &f : found)
        out.push_back(std::move(f.second));
    return out;
}

int SystemV4l2Device::open(const char *path, int flags) noexcept
{
    return ::open(path, flags | O_CLOEXEC); // NOLINT(cppcoreguidelines-pro-type-vararg)
}

int SystemV4l2Device::close(int fd) noexcept
{
    return ::close(fd);
}

int SystemV4l2Device::ioctl(int fd, unsigned long request, void *arg) noexcept
{
    return ::ioctl(fd, request, arg); // NOLINT(cppcoreguidelines-pro-type-vararg)
}

void *SystemV4l2Device::mmap(std::size_t length, int prot, int flags, int fd,
                             std::uint32_t offset) noexcept
{
    return ::mmap(nullptr, length, prot, flags, fd, static_cast<off_t>(offset));
}

int SystemV4l2Device::munmap(void *addr, std::size_t length) noexcept
{
    return ::munmap(addr, length);
}

int SystemV4l2Device::poll(pollfd *fds, std::size_t count, platform::Duration timeout) noexcept
{
    timespec ts{};
    timespec *tsp = nullptr;
    if (timeout >= platform::Duration::zero()) {
        const auto ns = timeout.count();
        ts.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
        ts.tv_nsec = static_cast<long>(ns % 1'000'000'000);
        tsp = &ts;
    }
    return ::ppoll(fds, static_cast<nfds_t>(count), tsp, nullptr);
}

std::unique_ptr<V4l2Device> makeV4l2Device(platform::Clock &clock)
{
    if (const V4l2DeviceFactory f = gFactory.load(std::memory_order_acquire))
        return f(clock);
    return std::make_unique<SystemV4l2Device>();
}

V4l2DeviceFactory setV4l2DeviceFactory(V4l2DeviceFactory factory) noexcept
{
    return gFactory.exchange(factory, std::memory_order_acq_rel);
}

int v4l2Ioctl(V4l2Device &dev, int fd, unsigned long request, void *arg) noexcept
{
    for (;;) {
        if (dev.ioctl(fd, request, arg) != -1)
            return 0;
        const int err = errno;
        if (err != EINTR)
            return err != 0 ? err : EIO;
    }
}

namespace {

/// The errno values that mean more than Io to a caller (errcOfErrno()).
constexpr std::pair<int, Errc> kErrnoCodes[] = {
    {ENODEV, Errc::NoDevice},         {ENXIO, Errc::NoDevice},
    {ENOENT, Errc::NoDevice},         {EBUSY, Errc::Busy},
    {EAGAIN, Errc::Timeout},          {ETIMEDOUT, Errc::Timeout},
    {EINVAL, Errc::NotSupported},     {ENOTTY, Errc::NotSupported},
    {EACCES, Errc::PermissionDenied}, {EPERM, Errc::PermissionDenied},
    {ENOMEM, Errc::OutOfResources},
};

} // namespace

Errc errcOfErrno(int err) noexcept
{
    for (const auto &[code, errc] : kErrnoCodes)
        if (code == err)
            return errc;
    return Errc::Io;
}

const char *fourccName(std::uint32_t fourcc, char (&out)[5]) noexcept
{
    for (int i = 0; i < 4; ++i) {
        const auto c = static_cast<char>((fourcc >> (8 * i)) & 0xffU);
        out[i] = (c >= 0x20 && c < 0x7f) ? c : '?';
    }
    out[4] = '\0';
    return out;
}

void V4l2Fd::reset() noexcept
{
    if (fd_ >= 0 && dev_ != nullptr) {
        const int saved = errno;
        dev_->close(fd_);
        errno = saved;
    }
    fd_ = -1;
}

} // namespace depthtouch::drivers
