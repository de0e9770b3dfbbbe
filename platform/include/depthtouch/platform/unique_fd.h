#pragma once
/// \file
/// \brief UniqueFd: sole owner of a file descriptor, closed on destruction (after libcamera
/// UniqueFD).
///
/// The header is C++17-clean.

#include <cerrno>
#include <unistd.h>
#include <utility>

namespace depthtouch::platform {

/// \brief Owns one file descriptor (or none: -1) and closes it when destroyed or reset.
///
/// Move-only. close() errors are ignored (the descriptor is released either way on Linux) and errno
/// is preserved across the close, so a UniqueFd going out of scope does not overwrite the errno of
/// the call that failed just before.
///
/// Thread-safety: reentrant (distinct objects on distinct threads; one object on one thread at a
/// time). Real-time safety: get(), isValid() and release() are real-time safe; reset() and the
/// destructor call close(2).
class UniqueFd {
public:
    /// An empty UniqueFd (-1).
    constexpr UniqueFd() noexcept = default;
    /// Takes ownership of \a fd (-1 for none).
    constexpr explicit UniqueFd(int fd) noexcept : fd_(fd) {}
    UniqueFd(UniqueFd &&other) noexcept : fd_(other.release()) {}
    UniqueFd &operator=(UniqueFd &&other) noexcept
    {
        reset(other.release());
        return *this;
    }
    UniqueFd(const UniqueFd &) = delete;
    UniqueFd &operator=(const UniqueFd &) = delete;
    ~UniqueFd() { reset(); }

    /// \return the descriptor (still owned), or -1.
    [[nodiscard]] constexpr int get() const noexcept { return fd_; }
    /// \return true when a descriptor is owned (>= 0).
    [[nodiscard]] constexpr bool isValid() const noexcept { return fd_ >= 0; }
    /// \return isValid().
    constexpr explicit operator bool() const noexcept { return isValid(); }

    /// \brief Gives up ownership without closing.
    /// \return the descriptor, which the caller must now close, or -1.
    [[nodiscard]] int release() noexcept
    {
        const int fd = fd_;
        fd_ = -1;
        return fd;
    }

    /// \brief Closes the owned descriptor (if any) and takes ownership of \a fd.
    /// Resetting to the descriptor already owned keeps it open.
    void reset(int fd = -1) noexcept
    {
        if (fd_ >= 0 && fd_ != fd) {
            const int savedErrno = errno;
            ::close(fd_);
            errno = savedErrno;
        }
        fd_ = fd;
    }

    /// Exchanges the descriptors of two objects.
    void swap(UniqueFd &other) noexcept { std::swap(fd_, other.fd_); }

private:
    int fd_ = -1;
};

/// Exchanges the descriptors of \a a and \a b.
inline void swap(UniqueFd &a, UniqueFd &b) noexcept
{
    a.swap(b);
}

} // namespace depthtouch::platform
