#pragma once
/// \file
/// \brief RealtimeThread: a thread started from a ThreadConfig entry with the real-time start-up
/// order of docs/style.md §4 (lock memory, explicit scheduling attributes, name, affinity,
/// pre-faulted stack), and the "graceful on host, strict on target" fallback when the kernel
/// refuses SCHED_FIFO.
///
/// The header is C++17-clean.

#include <atomic>
#include <cstddef>
#include <functional>
#include <pthread.h>
#include <semaphore.h>

#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/memory_lock.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/platform/thread_config.h"

namespace depthtouch::platform {

/// \brief Lets a thread body see that its owner asked it to stop (a C++17 stand-in for
/// std::stop_token).
///
/// Thread-safety: thread-safe. Real-time safe (one atomic load).
class StopToken {
public:
    /// Wraps \a flag, which must outlive the token.
    explicit StopToken(const std::atomic<bool> &flag) noexcept : flag_(&flag) {}
    /// \return true once RealtimeThread::requestStop() was called (or the thread is being
    /// destroyed).
    [[nodiscard]] bool stopRequested() const noexcept
    {
        return flag_->load(std::memory_order_acquire);
    }

private:
    const std::atomic<bool> *flag_;
};

/// \brief How strictly RealtimeThread::start() applies the real-time settings.
struct RealtimeThreadOptions {
    /// When the kernel refuses SCHED_FIFO or the memory lock, fail start() with
    /// Errc::PermissionDenied instead of logging once and running without it (the target's
    /// --require-rt).
    bool requireRt = false;
    /// Keep the thread's memory resident as lockMode says (process-wide, idempotent). Skipped in
    /// AddressSanitizer/ThreadSanitizer builds, see memoryLockingAvailable().
    bool lockMemory = true;
    /// CPU to pin the thread to, or -1 to leave the affinity alone.
    int cpuAffinity = -1;
    /// Touch the stack before the body runs (stackBytes minus a 16 KiB margin), so that the body
    /// takes no page fault on it. Off for threads that only need the table's stack size.
    bool prefaultStack = true;
    /// How the memory is kept resident (with lockMemory). MemoryLockMode::Owned, the default,
    /// mlock()s the thread's stack, the code and static data of the program and of the C/C++
    /// runtime (kRuntimeObjects and lockObjects) and \a regions: a few MiB, where
    /// mlockall(MCL_CURRENT) (MemoryLockMode::All, the earlier behaviour) faulted in and
    /// locked every library and every thread's stack mapped at that moment (measured with the
    /// player: 280-420 MiB locked, 180-260 MiB more resident than without haptics; docs/memory.md).
    MemoryLockMode lockMode = MemoryLockMode::Owned;
    /// MemoryLockMode::Owned: the data the body reads or writes (its objects, buffers and rings),
    /// \a regionCount of them; read by start() only. Null for none.
    const MemoryRegion *regions = nullptr;
    std::size_t regionCount = 0; ///< Entries of \a regions.
    /// MemoryLockMode::Owned: soname prefixes of further loaded objects whose code the body runs
    /// (e.g. "libusb-1.0.so" for a USB device), null-terminated; read by start() only. Null for
    /// none.
    const char *const *lockObjects = nullptr;
};

/// \brief Options for a SCHED_OTHER thread of the table that is not real-time: no memory locking,
/// no affinity, no stack pre-faulting; only the table's name, policy and stack size.
inline constexpr RealtimeThreadOptions kPlainThreadOptions{false, false, -1, false};

/// \brief What RealtimeThread::start() actually obtained from the kernel.
struct RealtimeThreadReport {
    const char *name = ""; ///< ThreadConfig::name.
    SchedPolicy policy =
        SchedPolicy::Other; ///< Policy read back on the thread (pthread_getschedparam).
    int priority = 0;       ///< Absolute priority read back on the thread (0 for SCHED_OTHER).
    bool rtRefused =
        false; ///< SCHED_FIFO was requested, refused, and the thread runs at SCHED_OTHER.
    bool memoryLocked = false; ///< The memory lock of lockMode succeeded for this start().
    /// The lock applied: RealtimeThreadOptions::lockMode, All where OnFault fell back, None when
    /// nothing was locked.
    MemoryLockMode lockMode = MemoryLockMode::None;
    /// MemoryLockMode::Owned: bytes this start() locked (stack, objects, regions; pages locked
    /// before by another start() count again). 0 for the other modes.
    std::size_t lockedBytes = 0;
    int cpu = -1;              ///< Requested CPU (RealtimeThreadOptions::cpuAffinity), -1 for none.
    bool affinityApplied = false;         ///< The thread is pinned to \a cpu.
    std::size_t stackBytes = 0;           ///< Stack size in bytes as created (page-rounded).
    std::size_t stackPrefaultedBytes = 0; ///< Bytes of stack touched before the body ran.

    /// \brief Formats the report as one line, e.g. "dt-haptic: SCHED_FIFO priority 90, memory
    /// locked, CPU 1, stack 262144 B (245760 B pre-faulted)", into \a buf of \a size bytes (always
    /// NUL-terminated). \return buf. Reentrant; does not allocate.
    const char *format(char *buf, std::size_t size) const noexcept;
};

/// \return false in builds whose sanitizer reserves terabytes of shadow memory (AddressSanitizer,
/// ThreadSanitizer, MemorySanitizer), where mlockall() would try to lock all of it (and mlock() of
/// the runtime's objects all their shadow); RealtimeThread then locks nothing (logged once). true
/// otherwise. Reentrant.
bool memoryLockingAvailable() noexcept;

/// \brief A POSIX thread configured from one ThreadConfig of the priority table.
///
/// start() does, in order: the memory lock of RealtimeThreadOptions::lockMode (when
/// RealtimeThreadOptions::lockMemory: mlock() of the objects and regions for Owned, mlockall()
/// for OnFault and All); pthread_create() with the config's stack size and explicit
/// scheduling attributes (SCHED_FIFO at absolutePriority(config), or SCHED_OTHER); then, on the new
/// thread, the name, the CPU affinity, and (RealtimeThreadOptions::prefaultStack) pre-faulting of
/// the stack (stackBytes minus a 16 KiB margin), locked with mlock() when memory is locked, before
/// the body runs. start() returns once the new thread has finished that set-up, so report() is
/// complete. Real-time starts (SCHED_FIFO, or memory locked) are logged at Info, others at Debug.
///
/// When the kernel refuses SCHED_FIFO (EPERM: no CAP_SYS_NICE and RLIMIT_RTPRIO below the priority)
/// or the memory lock (mlock()/mlockall(): EPERM/ENOMEM, no CAP_IPC_LOCK and RLIMIT_MEMLOCK too
/// small), start() logs one
/// warning per process and continues without it (SCHED_OTHER, unlocked memory) unless
/// RealtimeThreadOptions::requireRt is set; then it fails with Errc::PermissionDenied and an
/// Error::what that says how to grant the privilege.
///
/// The body is given at construction (it may allocate then) and runs once on the new thread with a
/// StopToken; it should return soon after StopToken::stopRequested(). It must not throw: an
/// exception leaving it terminates the process.
///
/// Thread-safety: thread-bound (construct, start(), join() and destroy on one owner thread), except
/// requestStop(), stopRequested() and finished(), which are thread-safe and real-time safe.
class RealtimeThread {
public:
    /// The thread function. Stored before start(); invoking it does not allocate.
    using Body = std::function<void(StopToken)>;

    /// \param[in] config entry of the priority table (copied; its name must be a static string)
    /// \param[in] options real-time strictness, memory locking and affinity
    /// \param[in] body function to run on the new thread
    RealtimeThread(const ThreadConfig &config, RealtimeThreadOptions options, Body body);
    /// requestStop(), then join().
    ~RealtimeThread();

    /// \brief Starts the thread (see the class comment for the order of steps). Not real-time safe.
    /// \return success, or:
    /// - Errc::InvalidState: already started;
    /// - Errc::InvalidArgument: no body, an invalid ThreadConfig, or a CPU that does not exist
    ///   or is not allowed (sysErrno from pthread_setaffinity_np; the body does not run);
    /// - Errc::PermissionDenied: requireRt and the kernel refused SCHED_FIFO or the memory lock;
    /// - Errc::OutOfResources: pthread_create() failed with EAGAIN.
    [[nodiscard]] Result<void> start();

    /// Asks the body to return (sets the StopToken). Thread-safe, real-time safe.
    void requestStop() noexcept { stop_.store(true, std::memory_order_release); }
    /// \return true once requestStop() was called. Thread-safe.
    [[nodiscard]] bool stopRequested() const noexcept
    {
        return stop_.load(std::memory_order_acquire);
    }
    /// Waits until the body has returned. No-op when not started or already joined.
    void join() noexcept;
    /// \return true between a successful start() and join().
    [[nodiscard]] bool joinable() const noexcept { return joinable_; }
    /// \return true once the body has returned. Thread-safe.
    [[nodiscard]] bool finished() const noexcept
    {
        return finished_.load(std::memory_order_acquire);
    }

    /// \return what start() obtained; complete after a successful start().
    [[nodiscard]] const RealtimeThreadReport &report() const noexcept { return report_; }
    /// \return the configuration given at construction.
    [[nodiscard]] const ThreadConfig &config() const noexcept { return config_; }

private:
    DT_DISABLE_COPY_AND_MOVE(RealtimeThread)

    static void *entry(void *self) noexcept;
    /// Step 1 of start(): the memory lock of options_.lockMode, into report_.
    Result<void> lockMemory();
    void run() noexcept;

    const ThreadConfig config_;
    const RealtimeThreadOptions options_;
    Body body_;

    pthread_t thread_{};
    bool joinable_ = false;
    sem_t ready_;                 ///< Posted by the new thread when its set-up is done.
    MemoryRegion stackLocked_;    ///< The stack the new thread locked (unlocked when it ends).
    int setupErrno_ = 0;          ///< Written by the new thread before posting ready_.
    RealtimeThreadReport report_; ///< Thread-side fields written before posting ready_.
    std::atomic<bool> stop_{false};
    std::atomic<bool> finished_{false};
};

} // namespace depthtouch::platform
