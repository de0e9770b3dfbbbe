#pragma once
/// \file
/// \brief Assertions for programmer bugs (never for conditions that inputs, devices or the OS can
/// cause: those return an Error).
///
/// - DT_ASSERT(cond) is checked in every build type. On failure it prints
///   "file:line: function(): assertion `cond' failed" on stderr and aborts.
/// - DT_DEBUG_ASSERT(cond) is the same but compiled out when NDEBUG is defined (Release,
///   RelWithDebInfo); use it on hot paths.
///
/// The condition must have no side effects: DT_DEBUG_ASSERT does not evaluate it in NDEBUG builds,
/// and a reader must be able to delete any assert without changing the program.
///
/// Real-time safety: a passing assert is one branch. A failing assert writes to stderr and aborts
/// the process (no allocation), which is acceptable because the program is already broken.
/// Thread-safety: reentrant. The header is C++17-clean.

namespace depthtouch::platform {

/// \brief Reports a failed assertion on stderr and calls std::abort().
/// \param[in] expression text of the condition
/// \param[in] file source file (__FILE__)
/// \param[in] line source line (__LINE__)
/// \param[in] function enclosing function (__func__)
///
/// Does not allocate; writes with a single write(2). Thread-safety: reentrant. Never returns.
[[noreturn]] void assertionFailed(const char *expression, const char *file, int line,
                                  const char *function) noexcept;

} // namespace depthtouch::platform

/// Aborts with file:line when \a cond is false, in every build type. \a cond must have no side
/// effects.
#define DT_ASSERT(cond)                                                                            \
    ((cond) ? static_cast<void>(0)                                                                 \
            : ::depthtouch::platform::assertionFailed(#cond, __FILE__, __LINE__, __func__))

#ifdef NDEBUG
/// Compiled out in NDEBUG builds: \a cond is not evaluated (but must still compile).
#define DT_DEBUG_ASSERT(cond) static_cast<void>(sizeof((cond) ? 1 : 0))
#else
/// Same as DT_ASSERT in builds without NDEBUG.
#define DT_DEBUG_ASSERT(cond) DT_ASSERT(cond)
#endif
