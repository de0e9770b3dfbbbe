#pragma once
/// \file
/// \brief The stack every thread of the process gets, whatever `ulimit -s` says.
///
/// glibc sizes the main thread's stack and the default stack of every thread it starts
/// (std::thread, and the threads of FFmpeg, Mesa and ALSA, which take the default) from
/// RLIMIT_STACK's soft limit read at start-up: with `ulimit -s 48` the first deep call on any of
/// them overflows, a SIGSEGV with no word. ensureStackLimit() raises the soft limit (up to the
/// hard one) and the default thread stack to a minimum at start, or says why it cannot.
/// References: getrlimit(2), pthread_setattr_default_np(3), pthread_create(3) ("On Linux/x86-32,
/// the default stack size for a new thread is ... the RLIMIT_STACK resource limit").
/// Thread-safety: call once from main() before any thread starts.

#include <cstddef>
#include <string>

namespace depthtouch::platform {

/// The stack the process asks for, bytes: well above what the deepest thread measured needs (the
/// headless EGL display and the FFmpeg decoders crashed below 64 KiB), and a small part of the
/// usual 8 MiB default.
inline constexpr std::size_t kMinimumStackBytes = std::size_t{1} << 20;

/// Makes RLIMIT_STACK's soft limit and the default stack of new threads at least \a minimumBytes
/// (unlimited and larger limits are kept).
/// \return "" when done; else one line for the user: the hard limit below \a minimumBytes (naming
/// `ulimit -s` and both sizes in KiB), or the system call that failed with its strerror().
std::string ensureStackLimit(std::size_t minimumBytes = kMinimumStackBytes);

} // namespace depthtouch::platform
