#pragma once
/// \file
/// \brief Error codes and Result<T>: the error channel of every platform, HAL and driver function.
///
/// Nothing here allocates: an Error holds a code, an errno value and a pointer to a static string,
/// so an error can be made and returned on the real-time thread. Member names follow std::expected,
/// so `Result<T>` can later become `std::expected<T, Error>` (C++23).
///
/// Thread-safety: value types; distinct objects may be used from distinct threads.
/// The header is C++17-clean.

#include <cstdint>
#include <new>
#include <type_traits>
#include <utility>

#include "depthtouch/platform/assert.h"

namespace depthtouch {

/// \brief What went wrong, in the few categories a caller can act on.
enum class Errc : std::uint8_t {
    InvalidArgument, ///< A parameter or input file is malformed or out of range.
    InvalidState,    ///< The call is not allowed in the object's current state (nothing was done).
    NotSupported,    ///< The backend, format or platform cannot do this.
    NoDevice,        ///< The device is absent, unplugged or does not answer.
    Busy,            ///< Try again later (queue full, resource in use).
    Timeout,         ///< A deadline passed before the operation completed.
    Io,              ///< Reading or writing a file, device or stream failed.
    OutOfResources,  ///< A fixed pool, ring or the system ran out of room.
    EndOfStream,     ///< No more data: the stream ended normally.
    PermissionDenied ///< The OS refused (e.g. SCHED_FIFO without the privilege).
};

/// \return the code's name, e.g. "NoDevice" (static string).
const char *errcName(Errc code) noexcept;

/// \brief An error: code, optional errno value and a static message.
struct Error {
    Errc code = Errc::InvalidArgument;
    int sysErrno = 0;         ///< errno of the failed system call, 0 when there is none.
    const char *what = "";    ///< Static string, never freed; describes the failure for a log line.

    constexpr Error() = default;
    constexpr Error(Errc c, const char *message, int err = 0) noexcept
        : code(c), sysErrno(err), what(message != nullptr ? message : "")
    {
    }

    /// Formats "what (CodeName[, strerror])" into \a buf of \a size bytes (always NUL-terminated).
    /// \return buf. Does not allocate; safe on any thread.
    const char *format(char *buf, std::size_t size) const noexcept;
};

/// Tag to construct a failed Result: `return unexpected(Errc::Io, "Failed to read header");`.
struct Unexpected {
    Error error;
};
constexpr Unexpected unexpected(Error e) noexcept { return Unexpected{e}; }
constexpr Unexpected unexpected(Errc code, const char *what, int err = 0) noexcept
{
    return Unexpected{Error(code, what, err)};
}

/// \brief A value of type T or an Error. Never allocates (T itself may).
///
/// Use: `if (!r) return unexpected(r.error());` then `r.value()` / `*r`. Calling value() on an
/// error, or error() on a value, is a programming bug (checked by DT_DEBUG_ASSERT in builds without
/// NDEBUG).
template <class T>
class [[nodiscard]] Result {
public:
    using value_type = T;

    Result(const T &v) : ok_(true) { new (&storage_.value) T(v); }                   // NOLINT
    Result(T &&v) : ok_(true) { new (&storage_.value) T(std::move(v)); }              // NOLINT
    Result(Unexpected u) noexcept : ok_(false) { storage_.error = u.error; }         // NOLINT
    Result(const Error &e) noexcept : ok_(false) { storage_.error = e; }             // NOLINT
    template <class U, class = std::enable_if_t<std::is_constructible_v<T, U &&> &&
                                                !std::is_same_v<std::decay_t<U>, Result> &&
                                                !std::is_same_v<std::decay_t<U>, Unexpected> &&
                                                !std::is_same_v<std::decay_t<U>, Error>>>
    Result(U &&v) : ok_(true) // NOLINT: implicit like std::expected
    {
        new (&storage_.value) T(std::forward<U>(v));
    }

    Result(const Result &o) : ok_(o.ok_)
    {
        if (ok_)
            new (&storage_.value) T(o.storage_.value);
        else
            storage_.error = o.storage_.error;
    }
    Result(Result &&o) noexcept(std::is_nothrow_move_constructible_v<T>) : ok_(o.ok_)
    {
        if (ok_)
            new (&storage_.value) T(std::move(o.storage_.value));
        else
            storage_.error = o.storage_.error;
    }
    /// Strong guarantee when T's move is noexcept: a throwing copy leaves *this unchanged.
    Result &operator=(const Result &o)
    {
        if (this != &o) {
            Result copy(o);
            *this = std::move(copy);
        }
        return *this;
    }
    /// Basic guarantee: if T's move constructor throws, *this holds an Errc::Io error ("value lost
    /// in assignment") instead of a half-built value.
    Result &operator=(Result &&o) noexcept(std::is_nothrow_move_constructible_v<T>)
    {
        if (this != &o) {
            destroy();
            ok_ = false;
            storage_.error = Error(Errc::Io, "value lost in assignment");
            if (o.ok_) {
                new (&storage_.value) T(std::move(o.storage_.value));
                ok_ = true;
            } else {
                storage_.error = o.storage_.error;
            }
        }
        return *this;
    }
    ~Result() { destroy(); }

    [[nodiscard]] bool has_value() const noexcept { return ok_; }
    explicit operator bool() const noexcept { return ok_; }

    /// \pre has_value() (checked by DT_DEBUG_ASSERT)
    T &value() &
    {
        DT_DEBUG_ASSERT(ok_);
        return storage_.value;
    }
    /// \pre has_value()
    const T &value() const &
    {
        DT_DEBUG_ASSERT(ok_);
        return storage_.value;
    }
    /// \pre has_value()
    T &&value() &&
    {
        DT_DEBUG_ASSERT(ok_);
        return std::move(storage_.value);
    }
    /// \pre has_value()
    T &operator*() & { return value(); }
    /// \pre has_value()
    const T &operator*() const & { return value(); }
    /// \pre has_value()
    T &&operator*() && { return std::move(*this).value(); }
    /// \pre has_value()
    T *operator->() { return &value(); }
    /// \pre has_value()
    const T *operator->() const { return &value(); }

    /// \pre !has_value() (checked by DT_DEBUG_ASSERT)
    [[nodiscard]] const Error &error() const noexcept
    {
        DT_DEBUG_ASSERT(!ok_);
        return storage_.error;
    }

    template <class U>
    T value_or(U &&fallback) const &
    {
        return ok_ ? storage_.value : static_cast<T>(std::forward<U>(fallback));
    }

private:
    void destroy() noexcept
    {
        if (ok_)
            storage_.value.~T();
    }

    union Storage {
        Storage() noexcept : error() {}
        ~Storage() {}
        T value;
        Error error;
    } storage_;
    bool ok_;
};

/// \brief Success without a value, or an Error.
template <>
class [[nodiscard]] Result<void> {
public:
    using value_type = void;

    constexpr Result() noexcept = default;
    constexpr Result(Unexpected u) noexcept : ok_(false), error_(u.error) {} // NOLINT
    constexpr Result(const Error &e) noexcept : ok_(false), error_(e) {}     // NOLINT

    [[nodiscard]] constexpr bool has_value() const noexcept { return ok_; }
    constexpr explicit operator bool() const noexcept { return ok_; }
    constexpr void value() const noexcept {}
    /// \pre !has_value()
    [[nodiscard]] constexpr const Error &error() const noexcept { return error_; }

private:
    bool ok_ = true;
    Error error_{};
};

/// Success for Result<void>: `return ok();`.
constexpr Result<void> ok() noexcept { return {}; }

} // namespace depthtouch

/// Returns the error of \a expr (a Result) from the enclosing function when it failed.
#define DT_TRY(expr)                                                                               \
    do {                                                                                           \
        auto &&dtTryResult_ = (expr);                                                              \
        if (!dtTryResult_)                                                                         \
            return ::depthtouch::unexpected(dtTryResult_.error());                                 \
    } while (0)
