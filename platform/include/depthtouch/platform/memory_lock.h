#pragma once
/// \file
/// \brief Keeping a real-time thread's memory resident without locking the whole process: mlock()
/// of the regions the thread owns, of the code and data of the loaded objects it runs (the program
/// and the C/C++ runtime), the process's resident and locked memory, and the page faults of the
/// calling thread (docs/memory.md, docs/style.md §4.2).
///
/// Why not mlockall(MCL_CURRENT): it faults in and locks every page mapped at that moment (every
/// shared library of the GL driver and of FFmpeg, every thread's stack): measured with the player,
/// 180-260 MiB resident and 280-420 MiB locked more than without haptics. MCL_ONFAULT with
/// MCL_FUTURE locks every page any thread touches later, so the locked memory grows with the
/// decoder pools and the GL driver. Locking what the real-time thread owns keeps the guarantee (no
/// page fault on it after its warm-up) with a few MiB locked.
///
/// Linux only (mlock, mincore, dl_iterate_phdr, /proc/self/status, RUSAGE_THREAD). The header is
/// C++17-clean.

#include <cstddef>
#include <cstdint>

#include "depthtouch/platform/result.h"

namespace depthtouch::platform {

/// \brief How RealtimeThread keeps a real-time thread's memory resident.
enum class MemoryLockMode : std::uint8_t {
    /// Nothing locked (the stack may still be pre-faulted).
    None,
    /// The thread's stack, the code and static data of the program and of the C/C++ runtime
    /// (kRuntimeObjects plus RealtimeThreadOptions::lockObjects), and the data regions its owner
    /// lists (RealtimeThreadOptions::regions), each with mlock(). The default.
    Owned,
    /// mlockall(MCL_CURRENT | MCL_FUTURE | MCL_ONFAULT) (Linux >= 4.4): every page is locked once
    /// any thread touches it, including every later mapping; falls back to All where the kernel
    /// does not know MCL_ONFAULT (EINVAL). For comparison (docs/memory.md).
    OnFault,
    /// mlockall(MCL_CURRENT): every page mapped at start, faulted in and locked (the earlier
    /// behaviour). For comparison (`bench rt`, docs/memory.md).
    All,
};

/// \return "none", "owned", "onfault" or "all" (static string). Reentrant.
const char *memoryLockModeName(MemoryLockMode mode) noexcept;

/// \brief A range of memory a real-time thread reads or writes: \a bytes bytes from \a address.
struct MemoryRegion {
    const void *address = nullptr;
    std::size_t bytes = 0;
};

/// Soname prefixes of the loaded objects whose code and static data a real-time thread runs in
/// every mode Owned locks: "" (the program itself, and the shared object this code is linked into
/// where it is one: the GStreamer element's plugin), "libc.so", "libm.so", "libstdc++.so",
/// "libgcc_s.so" and "ld-linux" (the dynamic loader, which resolves lazy bindings).
/// Null-terminated.
extern const char *const kRuntimeObjects[];

/// \brief What a lock of regions or objects obtained.
struct LockResult {
    std::size_t bytes = 0; ///< Bytes locked (whole pages).
    int regions = 0;       ///< Ranges locked.
    int failedErrno = 0;   ///< errno of the first mlock() that failed (0: none failed).
};

/// \brief mlock() the pages of \a region (rounded out to whole pages); pages that are not mapped
/// (found with mincore()) end the range, so a region given generously (an object of unknown size)
/// locks only the mapped part. Faults the pages in (a write fault for writable private mappings).
/// \return the bytes locked; LockResult::failedErrno is EPERM or ENOMEM when RLIMIT_MEMLOCK or the
/// missing CAP_IPC_LOCK refused it. Not real-time safe (syscalls that may block). Thread-safe.
LockResult lockRegion(const MemoryRegion &region) noexcept;

/// \brief mlock() every PT_LOAD segment (code, read-only data, data, bss) of the loaded objects
/// whose file name's last component starts with one of \a sonamePrefixes (null-terminated; "" is
/// the program itself and the object holding this function, where that is a shared object), found
/// with dl_iterate_phdr().
/// \return the bytes locked and the first failure, as lockRegion(). Not real-time safe.
/// Thread-safe.
LockResult lockLoadedObjects(const char *const *sonamePrefixes) noexcept;

/// \brief munlock() the pages of \a region, rounded out to whole pages (best effort). Pages shared
/// with another locked region are unlocked too: only for memory the caller alone locked.
void unlockRegion(const MemoryRegion &region) noexcept;

/// \return the process's resident memory (VmRSS of /proc/self/status), MiB, or −1 when unknown.
/// Not real-time safe (reads a file). Thread-safe.
double residentMiB() noexcept;

/// \return the process's locked memory (VmLck of /proc/self/status), MiB, or −1 when unknown.
/// Not real-time safe (reads a file). Thread-safe.
double lockedMiB() noexcept;

/// \brief Page faults of one thread (getrusage(RUSAGE_THREAD)).
struct PageFaults {
    std::uint64_t minor = 0; ///< Faults served without I/O (ru_minflt).
    std::uint64_t major = 0; ///< Faults that needed I/O (ru_majflt).
};

/// \return the calling thread's page faults since it started (zeros where RUSAGE_THREAD is not
/// available). Real-time safe: one syscall, no allocation, no lock.
PageFaults threadPageFaults() noexcept;

/// \return the size of the heap block \a p points to, as malloc_usable_size() (glibc), or \a
/// fallback where that is not available. \pre \a p is null or was returned by malloc() or
/// operator new (the start of a heap block). Not real-time safe.
std::size_t heapBlockBytes(const void *p, std::size_t fallback) noexcept;

/// \return the process's address space limit (the soft RLIMIT_AS, `ulimit -v`), bytes; 0 when
/// there is none (RLIM_INFINITY) or it cannot be read. Thread-safe.
std::uint64_t addressSpaceLimitBytes() noexcept;

} // namespace depthtouch::platform
