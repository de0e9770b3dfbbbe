#include "depthtouch/platform/realtime_thread.h"

#include <alloca.h>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits.h>
#include <sched.h>
#include <sys/mman.h>
#include <unistd.h>
#include <utility>

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Thread)

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define DT_SHADOW_MEMORY_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) ||                         \
    __has_feature(memory_sanitizer)
#define DT_SHADOW_MEMORY_SANITIZER 1
#endif
#endif

namespace depthtouch::platform {

namespace {

/// Static texts for Error::what (never allocated).
constexpr const char *kFifoRefused = "SCHED_FIFO refused by the kernel: run as root or with "
                                     "CAP_SYS_NICE (setcap cap_sys_nice+ep, systemd "
                                     "AmbientCapabilities=CAP_SYS_NICE), or allow real-time "
                                     "priorities with RLIMIT_RTPRIO (limits.conf "
                                     "'@group - rtprio 99', systemd LimitRTPRIO=99)";
constexpr const char *kMlockRefused =
    "Memory locking (mlock/mlockall) refused by the kernel: run as root or with CAP_IPC_LOCK, or "
    "raise RLIMIT_MEMLOCK (limits.conf '@group - memlock unlimited', systemd "
    "LimitMEMLOCK=infinity)";

/// Stack left untouched below the pre-faulting frame: room for the frames that run it and for a
/// signal handler that may arrive meanwhile.
constexpr std::size_t kStackPrefaultMargin = 16 * 1024;

std::size_t pageSize() noexcept
{
    const long size = sysconf(_SC_PAGESIZE);
    return size > 0 ? static_cast<std::size_t>(size) : 4096;
}

std::size_t roundUp(std::size_t value, std::size_t multiple) noexcept
{
    return (value + multiple - 1) / multiple * multiple;
}

const char *errnoText(int err, char *buf, std::size_t size) noexcept
{
    // GNU strerror_r returns the message, which may or may not be buf.
    return strerror_r(err, buf, size);
}

/// Owns a pthread_attr_t.
class ThreadAttributes {
public:
    ThreadAttributes() noexcept { ok_ = pthread_attr_init(&attr_) == 0; }
    ~ThreadAttributes()
    {
        if (ok_)
            pthread_attr_destroy(&attr_);
    }
    ThreadAttributes(const ThreadAttributes &) = delete;
    ThreadAttributes &operator=(const ThreadAttributes &) = delete;

    [[nodiscard]] bool ok() const noexcept { return ok_; }
    pthread_attr_t *get() noexcept { return &attr_; }

    /// \return 0 or the error number of the first failing pthread_attr_* call.
    int setScheduling(int policy, int priority) noexcept
    {
        sched_param param{};
        param.sched_priority = priority;
        int rc = pthread_attr_setinheritsched(&attr_, PTHREAD_EXPLICIT_SCHED);
        if (rc == 0)
            rc = pthread_attr_setschedpolicy(&attr_, policy);
        if (rc == 0)
            rc = pthread_attr_setschedparam(&attr_, &param);
        return rc;
    }

private:
    pthread_attr_t attr_{};
    bool ok_ = false;
};

/// Locks the calling thread's stack in memory (mapped after the process-wide lock, or the thread's
/// own under MemoryLockMode::Owned). Best effort: a refusal leaves the pre-faulted pages resident
/// as long as nothing reclaims them. \return the region locked (empty when refused).
MemoryRegion lockOwnStack() noexcept
{
    pthread_attr_t attr;
    if (pthread_getattr_np(pthread_self(), &attr) != 0)
        return {};
    void *stackLow = nullptr;
    std::size_t stackSize = 0;
    const int rc = pthread_attr_getstack(&attr, &stackLow, &stackSize);
    pthread_attr_destroy(&attr);
    if (rc != 0 || mlock(stackLow, stackSize) != 0)
        return {};
    return {stackLow, stackSize};
}

/// Process-wide mlockall() of MemoryLockMode::All or OnFault. \return 0 or the errno of the
/// refusal; \a applied is the mode in force (All where the kernel does not know MCL_ONFAULT).
int lockAll(MemoryLockMode mode, MemoryLockMode &applied) noexcept
{
    applied = mode;
#ifdef MCL_ONFAULT
    if (mode == MemoryLockMode::OnFault) {
        if (mlockall(MCL_CURRENT | MCL_FUTURE | MCL_ONFAULT) == 0)
            return 0;
        if (errno != EINVAL)
            return errno;
        DT_LOG_ONCE(Thread, Warning,
                    "mlockall(MCL_ONFAULT) is not known to this kernel (Linux < 4.4): locking "
                    "every mapped page instead (mlockall(MCL_CURRENT))");
    }
#endif
    applied = MemoryLockMode::All;
    return mlockall(MCL_CURRENT) == 0 ? 0 : errno;
}

/// MemoryLockMode::Owned: mlock() of \a self (the thread object: its stop flag and the body's
/// captures), the runtime's and the options' objects and the regions. \return 0 or the errno of
/// the first refusal (the rest is still locked); adds to \a bytes.
int lockOwned(const MemoryRegion &self, const RealtimeThreadOptions &options,
              std::size_t &bytes) noexcept
{
    LockResult all = lockRegion(self);
    const LockResult runtime = lockLoadedObjects(kRuntimeObjects);
    all.bytes += runtime.bytes;
    if (all.failedErrno == 0)
        all.failedErrno = runtime.failedErrno;
    const LockResult extra = lockLoadedObjects(options.lockObjects);
    all.bytes += extra.bytes;
    if (all.failedErrno == 0)
        all.failedErrno = extra.failedErrno;
    for (std::size_t i = 0; options.regions != nullptr && i < options.regionCount; ++i) {
        const LockResult r = lockRegion(options.regions[i]);
        all.bytes += r.bytes;
        if (all.failedErrno == 0)
            all.failedErrno = r.failedErrno;
    }
    bytes += all.bytes;
    return all.failedErrno;
}

/// Touches \a wanted bytes of the calling thread's stack (minus kStackPrefaultMargin, and never
/// more than is left below the current frame), one write per page, so the body does not take page
/// faults on its first deep calls. \return the number of bytes touched.
__attribute__((noinline)) std::size_t prefaultStack(std::size_t wanted) noexcept
{
    pthread_attr_t attr;
    if (pthread_getattr_np(pthread_self(), &attr) != 0)
        return 0;
    void *stackLow = nullptr;
    std::size_t stackSize = 0;
    const int rc = pthread_attr_getstack(&attr, &stackLow, &stackSize);
    pthread_attr_destroy(&attr);
    if (rc != 0)
        return 0;
    // The frame address is on the real stack even when a sanitizer moves locals to a fake stack.
    const auto here = reinterpret_cast<std::uintptr_t>(__builtin_frame_address(0));
    const auto low = reinterpret_cast<std::uintptr_t>(stackLow);
    const std::size_t left = here > low ? here - low : 0;
    std::size_t budget = wanted < left ? wanted : left;
    if (budget <= kStackPrefaultMargin)
        return 0;
    budget -= kStackPrefaultMargin;
    auto *bytes = static_cast<volatile unsigned char *>(alloca(budget));
    const std::size_t page = pageSize();
    for (std::size_t offset = 0; offset < budget; offset += page)
        bytes[offset] = 0;
    bytes[budget - 1] = 0;
    return budget;
}

} // namespace

bool memoryLockingAvailable() noexcept
{
#ifdef DT_SHADOW_MEMORY_SANITIZER
    return false;
#else
    return true;
#endif
}

const char *RealtimeThreadReport::format(char *buf, std::size_t size) const noexcept
{
    if (buf == nullptr || size == 0)
        return buf;
    char cpuText[32];
    if (cpu < 0)
        std::snprintf(cpuText, sizeof(cpuText), "no CPU affinity");
    else if (affinityApplied)
        std::snprintf(cpuText, sizeof(cpuText), "CPU %d", cpu);
    else
        std::snprintf(cpuText, sizeof(cpuText), "CPU %d not applied", cpu);
    char lockText[64];
    if (!memoryLocked)
        std::snprintf(lockText, sizeof(lockText), "not locked");
    else if (lockMode == MemoryLockMode::Owned)
        std::snprintf(lockText, sizeof(lockText), "locked (owned, %.1f MiB)",
                      static_cast<double>(lockedBytes) / (1024.0 * 1024.0));
    else
        std::snprintf(lockText, sizeof(lockText), "locked (%s)", memoryLockModeName(lockMode));
    std::snprintf(buf, size, "%s: %s priority %d%s, memory %s, %s, stack %zu B (%zu B pre-faulted)",
                  name, schedPolicyName(policy), priority, rtRefused ? " (SCHED_FIFO refused)" : "",
                  lockText, cpuText, stackBytes, stackPrefaultedBytes);
    return buf;
}

namespace {

/// Real-time threads say what they obtained; the plain ones only when asked (DT_LOG=debug).
void logStarted(const ThreadConfig &config, const RealtimeThreadOptions &options,
                const RealtimeThreadReport &report) noexcept
{
    char line[256];
    if (config.policy == SchedPolicy::Fifo ||
        (options.lockMemory && options.lockMode != MemoryLockMode::None))
        DT_LOG(Thread, Info, "Started %s", report.format(line, sizeof(line)));
    else
        DT_LOG(Thread, Debug, "Started %s", report.format(line, sizeof(line)));
}

} // namespace

RealtimeThread::RealtimeThread(const ThreadConfig &config, RealtimeThreadOptions options, Body body)
    : config_(config), options_(options), body_(std::move(body))
{
    sem_init(&ready_, 0, 0);
}

RealtimeThread::~RealtimeThread()
{
    requestStop();
    join();
    sem_destroy(&ready_);
}

Result<void> RealtimeThread::lockMemory()
{
    if (!options_.lockMemory || options_.lockMode == MemoryLockMode::None)
        return ok();
    if (!memoryLockingAvailable()) {
        DT_LOG_ONCE(Thread, Warning,
                    "Not locking memory: this sanitizer build reserves terabytes of shadow memory");
        return ok();
    }
    MemoryLockMode applied = options_.lockMode;
    std::size_t bytes = 0;
    const int err = options_.lockMode == MemoryLockMode::Owned
                        ? lockOwned({this, sizeof(*this)}, options_, bytes)
                        : lockAll(options_.lockMode, applied);
    if (err != 0) {
        if (options_.requireRt)
            return unexpected(Errc::PermissionDenied, kMlockRefused, err);
        char errText[128];
        DT_LOG_ONCE(Thread, Warning,
                    "Failed to lock memory (%s, %s): %s; real-time threads may take page faults. "
                    "Grant CAP_IPC_LOCK or raise RLIMIT_MEMLOCK (limits.conf memlock, systemd "
                    "LimitMEMLOCK=infinity)",
                    applied == MemoryLockMode::Owned ? "mlock" : "mlockall",
                    memoryLockModeName(applied), errnoText(err, errText, sizeof(errText)));
        return ok();
    }
    report_.memoryLocked = true;
    report_.lockMode = applied;
    report_.lockedBytes = bytes;
    return ok();
}

Result<void> RealtimeThread::start()
{
    if (joinable_ || finished())
        return unexpected(Errc::InvalidState, "RealtimeThread::start() called twice");
    if (!body_)
        return unexpected(Errc::InvalidArgument, "RealtimeThread has no body");
    if (!isValidThreadConfig(config_))
        return unexpected(
            Errc::InvalidArgument,
            "Invalid ThreadConfig: name must be 1..15 characters, priority <= 0 (0 for "
            "SCHED_OTHER), stack >= 64 KiB");
    if (options_.cpuAffinity >= CPU_SETSIZE || options_.cpuAffinity < -1)
        return unexpected(Errc::InvalidArgument,
                          "Failed to set the CPU affinity: CPU number out of range", EINVAL);

    report_ = RealtimeThreadReport{};
    report_.name = config_.name;
    report_.cpu = options_.cpuAffinity;
    setupErrno_ = 0;
    char errText[128];

    // 1. Lock memory before anything real-time exists, so neither the stack about to be created
    //    nor the data and code the body runs take a page fault on the real-time path.
    if (auto locked = lockMemory(); !locked)
        return locked;

    // 2. Create the thread with explicit attributes: it is born with its stack size and policy, and
    //    does not inherit the creator's (possibly SCHED_FIFO) scheduling.
    ThreadAttributes attr;
    if (!attr.ok())
        return unexpected(Errc::OutOfResources, "Failed to initialise thread attributes");
    std::size_t stackBytes = config_.stackBytes;
    if (stackBytes < static_cast<std::size_t>(PTHREAD_STACK_MIN))
        stackBytes = static_cast<std::size_t>(PTHREAD_STACK_MIN);
    stackBytes = roundUp(stackBytes, pageSize());
    int rc = pthread_attr_setstacksize(attr.get(), stackBytes);
    if (rc != 0)
        return unexpected(Errc::InvalidArgument, "Failed to set the thread stack size", rc);
    report_.stackBytes = stackBytes;

    rc = attr.setScheduling(toSchedPolicy(config_.policy), absolutePriority(config_));
    if (rc != 0)
        return unexpected(Errc::InvalidArgument, "Failed to set the thread scheduling attributes",
                          rc);
    rc = pthread_create(&thread_, attr.get(), &RealtimeThread::entry, this);
    if (rc == EPERM && config_.policy == SchedPolicy::Fifo) {
        if (options_.requireRt)
            return unexpected(Errc::PermissionDenied, kFifoRefused, rc);
        DT_LOG_ONCE(
            Thread, Warning,
            "SCHED_FIFO refused for thread %s (%s): running at SCHED_OTHER. Run as root or with "
            "CAP_SYS_NICE, or raise RLIMIT_RTPRIO (limits.conf rtprio, systemd LimitRTPRIO=99); "
            "use --require-rt to make this fatal",
            config_.name, errnoText(rc, errText, sizeof(errText)));
        report_.rtRefused = true;
        rc = attr.setScheduling(SCHED_OTHER, 0);
        if (rc == 0)
            rc = pthread_create(&thread_, attr.get(), &RealtimeThread::entry, this);
    }
    if (rc != 0) {
        if (rc == EAGAIN)
            return unexpected(Errc::OutOfResources, "Failed to create thread", rc);
        if (rc == EPERM)
            return unexpected(Errc::PermissionDenied, "Failed to create thread", rc);
        return unexpected(Errc::InvalidArgument, "Failed to create thread", rc);
    }
    joinable_ = true;

    // 3. Wait for the thread's own set-up (name, affinity, stack) so report() is complete.
    while (sem_wait(&ready_) != 0 && errno == EINTR) {
    }
    if (setupErrno_ != 0) {
        join();
        return unexpected(
            Errc::InvalidArgument,
            "Failed to set the CPU affinity: no such CPU, or not allowed for this process",
            setupErrno_);
    }

    logStarted(config_, options_, report_);
    return ok();
}

void RealtimeThread::join() noexcept
{
    if (!joinable_)
        return;
    pthread_join(thread_, nullptr);
    joinable_ = false;
}

void *RealtimeThread::entry(void *self) noexcept
{
    static_cast<RealtimeThread *>(self)->run();
    return nullptr;
}

void RealtimeThread::run() noexcept
{
    const pthread_t self = pthread_self();

    // Names longer than 15 characters make pthread_setname_np fail: truncate instead (the config
    // was validated, so this only guards against future changes).
    char name[kMaxThreadNameLength + 1] = {};
    std::strncpy(name, config_.name, kMaxThreadNameLength);
    pthread_setname_np(self, name);

    if (options_.cpuAffinity >= 0) {
        cpu_set_t cpus;
        CPU_ZERO(&cpus);
        CPU_SET(static_cast<std::size_t>(options_.cpuAffinity), &cpus);
        const int rc = pthread_setaffinity_np(self, sizeof(cpus), &cpus);
        if (rc != 0) {
            setupErrno_ = rc;
            sem_post(&ready_);
            return; // start() joins and reports the error; the body does not run
        }
        report_.affinityApplied = true;
    }

    if (options_.prefaultStack)
        report_.stackPrefaultedBytes = prefaultStack(report_.stackBytes);
    stackLocked_ = {};
    if (report_.memoryLocked && report_.lockMode != MemoryLockMode::OnFault) {
        stackLocked_ = lockOwnStack();
        if (report_.lockMode == MemoryLockMode::Owned)
            report_.lockedBytes += stackLocked_.bytes;
    }

    int policy = SCHED_OTHER;
    sched_param param{};
    if (pthread_getschedparam(self, &policy, &param) == 0) {
        report_.policy = policy == SCHED_FIFO ? SchedPolicy::Fifo : SchedPolicy::Other;
        report_.priority = param.sched_priority;
    }

    // From here on the creator reads report_ and this thread no longer writes it (sem_post orders
    // the writes above before start() returns).
    sem_post(&ready_);
    body_(StopToken(stop_));
    // glibc keeps the stacks of ended threads for reuse: give the pages back to the kernel's
    // reclaim now rather than keep them locked in its cache.
    unlockRegion(stackLocked_);
    finished_.store(true, std::memory_order_release);
}

} // namespace depthtouch::platform
