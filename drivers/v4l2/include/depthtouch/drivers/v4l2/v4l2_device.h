#pragma once
/// \file
/// \brief V4l2Device: the kernel side of V4L2 (open, close, ioctl, mmap, munmap, poll) behind an
/// interface, so the V4L2 backends run against the real syscalls in production and against a fake
/// kernel in tests; plus the helpers every V4L2 backend uses on top of it.
///
/// The interface mirrors the syscalls: a call that fails returns -1 (MAP_FAILED for mmap) and sets
/// errno. File descriptors are the implementation's: an fd from one V4l2Device means nothing to
/// another. Thread-safety: an implementation is reentrant on distinct descriptors (the real one is
/// thread-safe). Not real-time safe.

#include <poll.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers {

/// \brief The kernel side of V4L2.
class V4l2Device {
public:
    virtual ~V4l2Device() = default;

    /// \return the paths of the video device nodes (/dev/videoN), in increasing N.
    [[nodiscard]] virtual std::vector<std::string> listNodes() = 0;
    /// open(2) of a device node. \return a descriptor, or -1 with errno (ENOENT: no such node).
    virtual int open(const char *path, int flags) noexcept = 0;
    /// close(2). \return 0, or -1 with errno.
    virtual int close(int fd) noexcept = 0;
    /// ioctl(2) with a VIDIOC_* request. \return 0 (or the request's result), or -1 with errno.
    virtual int ioctl(int fd, unsigned long request, void *arg) noexcept = 0;
    /// mmap(2) of a buffer (offset from VIDIOC_QUERYBUF). \return the mapping, or MAP_FAILED.
    virtual void *mmap(std::size_t length, int prot, int flags, int fd,
                       std::uint32_t offset) noexcept = 0;
    /// munmap(2). \return 0, or -1 with errno.
    virtual int munmap(void *addr, std::size_t length) noexcept = 0;
    /// ppoll(2) of \a count descriptors, waiting at most \a timeout (negative: forever).
    /// \return the number of descriptors with events, 0 on timeout, or -1 with errno (EINTR).
    virtual int poll(pollfd *fds, std::size_t count, platform::Duration timeout) noexcept = 0;

protected:
    V4l2Device() = default;
    DT_DISABLE_COPY_AND_MOVE(V4l2Device)
};

/// \brief The real kernel: the syscalls on /dev/video*. Thread-safe.
class SystemV4l2Device final : public V4l2Device {
public:
    SystemV4l2Device() = default;
    [[nodiscard]] std::vector<std::string> listNodes() override;
    int open(const char *path, int flags) noexcept override;
    int close(int fd) noexcept override;
    int ioctl(int fd, unsigned long request, void *arg) noexcept override;
    void *mmap(std::size_t length, int prot, int flags, int fd,
               std::uint32_t offset) noexcept override;
    int munmap(void *addr, std::size_t length) noexcept override;
    int poll(pollfd *fds, std::size_t count, platform::Duration timeout) noexcept override;
};

/// \brief Makes the kernel side a backend factory uses; \a clock is the backend's clock.
using V4l2DeviceFactory = std::unique_ptr<V4l2Device> (*)(platform::Clock &clock);

/// \return the kernel side for the V4L2 backend factories (V4l2DepthCamera::create(), the
/// v4l2m2m probe): a SystemV4l2Device unless a test installed another factory.
std::unique_ptr<V4l2Device> makeV4l2Device(platform::Clock &clock);

/// \brief Replaces the kernel side of the backend factories (tests run the backend tables against a
/// fake kernel); nullptr restores the real one. Thread-safe (atomic), but call it before creating
/// backends. \return the previous factory (nullptr for the real one).
V4l2DeviceFactory setV4l2DeviceFactory(V4l2DeviceFactory factory) noexcept;

/// \brief ioctl that retries on EINTR. \return 0 on success, else the errno value (never EINTR).
int v4l2Ioctl(V4l2Device &dev, int fd, unsigned long request, void *arg) noexcept;

/// \return the HAL code of errno value \a err: NoDevice (ENODEV, ENXIO, ENOENT), Busy (EBUSY),
/// Timeout (EAGAIN, ETIMEDOUT), NotSupported (EINVAL, ENOTTY), PermissionDenied (EACCES, EPERM),
/// OutOfResources (ENOMEM), Io otherwise.
Errc errcOfErrno(int err) noexcept;

/// \brief Writes the four characters of \a fourcc ("Z16 ") into \a out (5 bytes with the NUL).
/// \return out.
const char *fourccName(std::uint32_t fourcc, char (&out)[5]) noexcept;

/// \brief An open descriptor of a V4l2Device, closed on destruction. Move-only. Thread-bound.
class V4l2Fd {
public:
    V4l2Fd() noexcept = default;
    V4l2Fd(V4l2Device &dev, int fd) noexcept : dev_(&dev), fd_(fd) {}
    V4l2Fd(V4l2Fd &&o) noexcept : dev_(o.dev_), fd_(o.fd_) { o.fd_ = -1; }
    V4l2Fd &operator=(V4l2Fd &&o) noexcept
    {
        if (this != &o) {
            reset();
            dev_ = o.dev_;
            fd_ = o.fd_;
            o.fd_ = -1;
        }
        return *this;
    }
    V4l2Fd(const V4l2Fd &) = delete;
    V4l2Fd &operator=(const V4l2Fd &) = delete;
    ~V4l2Fd() { reset(); }

    /// Closes the descriptor (errno preserved).
    void reset() noexcept;
    [[nodiscard]] int get() const noexcept { return fd_; }
    [[nodiscard]] bool isOpen() const noexcept { return fd_ >= 0; }

private:
    V4l2Device *dev_ = nullptr;
    int fd_ = -1;
};

} // namespace depthtouch::drivers
