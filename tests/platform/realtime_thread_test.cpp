// RealtimeThread changes process-wide state (scheduling, mlock, rlimits, capabilities): every
// case that could do so runs in a forked child, which reports back through a pipe; the parent
// asserts.

#include "depthtouch/platform/realtime_thread.h"

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <linux/capability.h>
#include <pthread.h>
#include <sched.h>
#include <string>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/periodic_timer.h"

namespace depthtouch::platform {
namespace {

using std::chrono::milliseconds;

/// What one start() in the child did, as plain data that can cross the pipe.
struct StartOutcome {
    bool attempted = false;
    bool started = false;
    int errc = -1;
    int sysErrno = 0;
    char what[512] = {};
    SchedPolicy policy = SchedPolicy::Other;
    int priority = -1;
    bool rtRefused = false;
    bool memoryLocked = false;
    bool affinityApplied = false;
    std::size_t stackBytes = 0;
    std::size_t prefaulted = 0;
    char line[256] = {};
    bool bodyRan = false;
    int bodyPolicy = -1;
    int bodyPriority = -1;
    int bodyCpu = -1;
    char bodyName[16] = {};
    std::uint64_t bodyCycles = 0;
};

/// Everything a child reports.
struct ChildOutcome {
    StartOutcome starts[3];
    int warnings = 0;
    char firstWarning[512] = {};
    bool skipped = false;
    char skipReason[256] = {};
};

void copyText(char *dst, std::size_t size, const char *src)
{
    std::snprintf(dst, size, "%s", src != nullptr ? src : "");
}

void countWarnings(void *user, LogLevel level, const char * /*category*/, const char *message)
{
    auto *out = static_cast<ChildOutcome *>(user);
    if (level < LogLevel::Warning)
        return;
    if (out->warnings++ == 0)
        copyText(out->firstWarning, sizeof(out->firstWarning), message);
}

/// Starts a thread with \a config and \a options whose body records how it runs (and, with
/// \a periodicCycles, runs that many 1 ms PeriodicTimer cycles on the steady clock), then joins it.
void startAndJoin(const ThreadConfig &config, RealtimeThreadOptions options, StartOutcome &o,
                  int periodicCycles = 0)
{
    o.attempted = true;
    RealtimeThread thread(config, options, [&o, periodicCycles](StopToken) {
        int policy = -1;
        sched_param param{};
        pthread_getschedparam(pthread_self(), &policy, &param);
        o.bodyPolicy = policy;
        o.bodyPriority = param.sched_priority;
        o.bodyCpu = sched_getcpu();
        pthread_getname_np(pthread_self(), o.bodyName, sizeof(o.bodyName));
        if (periodicCycles > 0) {
            PeriodicTimer timer(SteadyClock::instance(), milliseconds(1));
            timer.start();
            for (int i = 0; i < periodicCycles; ++i)
                (void)timer.wait();
            o.bodyCycles = timer.cycles();
        }
        o.bodyRan = true;
    });
    const Result<void> r = thread.start();
    o.started = r.has_value();
    if (!r) {
        o.errc = static_cast<int>(r.error().code);
        o.sysErrno = r.error().sysErrno;
        copyText(o.what, sizeof(o.what), r.error().what);
    }
    thread.join();
    const RealtimeThreadReport &report = thread.report();
    o.policy = report.policy;
    o.priority = report.priority;
    o.rtRefused = report.rtRefused;
    o.memoryLocked = report.memoryLocked;
    o.affinityApplied = report.affinityApplied;
    o.stackBytes = report.stackBytes;
    o.prefaulted = report.stackPrefaultedBytes;
    report.format(o.line, sizeof(o.line));
}

/// Runs \a scenario in a forked child and returns what it reported. Fails the test when the child
/// crashes or reports nothing.
template <class Scenario>
bool runInChild(Scenario scenario, ChildOutcome &out)
{
    int fds[2];
    if (pipe(fds) != 0) {
        ADD_FAILURE() << "pipe: " << std::strerror(errno);
        return false;
    }
    const pid_t pid = fork();
    if (pid < 0) {
        ADD_FAILURE() << "fork: " << std::strerror(errno);
        return false;
    }
    if (pid == 0) {
        close(fds[0]);
        auto *result = new ChildOutcome();
        setLogSink(&countWarnings, result);
        scenario(*result);
        setLogSink(nullptr, nullptr);
        const auto *bytes = reinterpret_cast<const char *>(result);
        std::size_t done = 0;
        while (done < sizeof(ChildOutcome)) {
            const ssize_t n = write(fds[1], bytes + done, sizeof(ChildOutcome) - done);
            if (n <= 0)
                _exit(3);
            done += static_cast<std::size_t>(n);
        }
        _exit(0);
    }
    close(fds[1]);
    auto *bytes = reinterpret_cast<char *>(&out);
    std::size_t done = 0;
    while (done < sizeof(ChildOutcome)) {
        const ssize_t n = read(fds[0], bytes + done, sizeof(ChildOutcome) - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            break;
        done += static_cast<std::size_t>(n);
    }
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "child status " << status;
    EXPECT_EQ(done, sizeof(ChildOutcome)) << "child reported nothing (crashed?)";
    return done == sizeof(ChildOutcome);
}

/// \return true when a forked child may switch itself to SCHED_FIFO at \a priority.
bool probeFifo(int priority)
{
    const pid_t pid = fork();
    if (pid == 0) {
        sched_param param{};
        param.sched_priority = priority;
        _exit(sched_setscheduler(0, SCHED_FIFO, &param) == 0 ? 0 : 1);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/// \return true when a forked child may lock what the default MemoryLockMode::Owned locks (the
/// runtime's objects, a few MiB: more than some RLIMIT_MEMLOCK defaults allow without privilege).
bool probeMlockall()
{
    if (!memoryLockingAvailable())
        return false;
    const pid_t pid = fork();
    if (pid == 0)
        _exit(lockLoadedObjects(kRuntimeObjects).failedErrno == 0 ? 0 : 1);
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/// Removes capability \a cap from the calling process's effective, permitted and inheritable sets.
bool dropCapability(int cap)
{
    __user_cap_header_struct header{};
    header.version = _LINUX_CAPABILITY_VERSION_3;
    header.pid = 0;
    __user_cap_data_struct data[_LINUX_CAPABILITY_U32S_3] = {};
    if (syscall(SYS_capget, &header, data) != 0)
        return false;
    const auto index = static_cast<unsigned>(CAP_TO_INDEX(cap));
    const auto mask = static_cast<__u32>(CAP_TO_MASK(cap));
    data[index].effective &= ~mask;
    data[index].permitted &= ~mask;
    data[index].inheritable &= ~mask;
    return syscall(SYS_capset, &header, data) == 0;
}

/// Marks a child's outcome skipped, for \a reason.
void skipChild(ChildOutcome &o, const char *reason)
{
    o.skipped = true;
    copyText(o.skipReason, sizeof(o.skipReason), reason);
}

/// runInChild() of \a scenario in a child that first lowers the limit \a resource (RLIMIT_...) to 0
/// and drops capability \a cap; where either fails, the outcome is skipped for \a reason and
/// \a scenario does not run.
template <class Scenario>
bool runInChildWithout(decltype(RLIMIT_RTPRIO) resource, int cap, const char *reason,
                       Scenario scenario, ChildOutcome &out)
{
    return runInChild(
        [&](ChildOutcome &o) {
            const rlimit none{0, 0};
            if (setrlimit(resource, &none) != 0 || !dropCapability(cap)) {
                skipChild(o, reason);
                return;
            }
            scenario(o);
        },
        out);
}

bool contains(const char *text, const char *needle)
{
    return std::strstr(text, needle) != nullptr;
}

TEST(RealtimeThreadTest, hapticConfigGetsFifoWhenPrivilegedAndRunsTheBody)
{
    // GIVEN whether this process may use SCHED_FIFO at the haptic priority and lock memory (probed
    // in forked children)
    const int hapticPriority = absolutePriority(kHapticThread);
    const bool fifoAllowed = probeFifo(hapticPriority);
    const bool mlockAllowed = probeMlockall();

    // WHEN a child starts the haptic thread (graceful mode), running 50 periodic cycles, and, if
    // privileged, once more with requireRt
    ChildOutcome out;
    ASSERT_TRUE(runInChild(
        [fifoAllowed](ChildOutcome &o) {
            startAndJoin(kHapticThread, RealtimeThreadOptions{false, true, -1}, o.starts[0], 50);
            if (fifoAllowed)
                startAndJoin(kHapticThread, RealtimeThreadOptions{true, true, -1}, o.starts[1]);
        },
        out));

    // THEN it started, reporting the policy the kernel actually gave, and the body ran with it
    const StartOutcome &s = out.starts[0];
    ASSERT_TRUE(s.started) << s.what;
    std::printf("SCHED_FIFO %s, mlockall %s; report: %s\n", fifoAllowed ? "allowed" : "refused",
                mlockAllowed ? "allowed" : "refused", s.line);
    EXPECT_TRUE(s.bodyRan);
    EXPECT_EQ(s.bodyCycles, 50u);
    EXPECT_EQ(s.policy, fifoAllowed ? SchedPolicy::Fifo : SchedPolicy::Other) << s.line;
    EXPECT_EQ(s.bodyPolicy, fifoAllowed ? SCHED_FIFO : SCHED_OTHER);
    EXPECT_EQ(s.priority, fifoAllowed ? hapticPriority : 0);
    EXPECT_EQ(s.bodyPriority, s.priority);
    EXPECT_EQ(s.rtRefused, !fifoAllowed);
    EXPECT_EQ(s.memoryLocked, mlockAllowed);
    // AND it has its name and its stack, pre-faulted up to a margin (less when static TLS, which
    // glibc carves from the same allocation, is large, as under ThreadSanitizer)
    EXPECT_STREQ(s.bodyName, kHapticThread.name);
    EXPECT_GE(s.stackBytes, kHapticThread.stackBytes);
    EXPECT_GT(s.prefaulted, 0u);
    EXPECT_LE(s.prefaulted, s.stackBytes - 16 * 1024);
    EXPECT_TRUE(contains(s.line, "dt-haptic")) << s.line;
    EXPECT_TRUE(contains(s.line, schedPolicyName(s.policy))) << s.line;
    // AND a refusal was logged once at most, only when there was one
    EXPECT_EQ(out.warnings, (fifoAllowed ? 0 : 1) +
                                (mlockAllowed || !memoryLockingAvailable() ? 0 : 1) +
                                (memoryLockingAvailable() ? 0 : 1))
        << out.firstWarning;
    if (fifoAllowed) {
        ASSERT_TRUE(out.starts[1].started) << out.starts[1].what;
        EXPECT_EQ(out.starts[1].policy, SchedPolicy::Fifo);
        EXPECT_TRUE(out.starts[1].bodyRan);
    }
}

TEST(RealtimeThreadTest, refusedFifoFallsBackOrFailsWhenRequired)
{
    // GIVEN a child where the kernel refuses SCHED_FIFO: RLIMIT_RTPRIO 0 and no CAP_SYS_NICE
    ChildOutcome out;
    ASSERT_TRUE(runInChildWithout(
        RLIMIT_RTPRIO, CAP_SYS_NICE, "cannot lower RLIMIT_RTPRIO or drop CAP_SYS_NICE",
        [](ChildOutcome &o) {
            sched_param param{};
            param.sched_priority = 1;
            if (sched_setscheduler(0, SCHED_FIFO, &param) == 0) {
                skipChild(o, "the kernel still grants SCHED_FIFO");
                return;
            }
            // WHEN the haptic thread starts twice in graceful mode, then once with requireRt
            startAndJoin(kHapticThread, RealtimeThreadOptions{false, false, -1}, o.starts[0]);
            startAndJoin(kHapticThread, RealtimeThreadOptions{false, false, -1}, o.starts[1]);
            startAndJoin(kHapticThread, RealtimeThreadOptions{true, false, -1}, o.starts[2]);
        },
        out));
    if (out.skipped)
        GTEST_SKIP() << out.skipReason;

    // THEN graceful starts run the body at SCHED_OTHER and say so
    for (int i = 0; i < 2; ++i) {
        const StartOutcome &s = out.starts[i];
        ASSERT_TRUE(s.started) << s.what;
        EXPECT_TRUE(s.bodyRan);
        EXPECT_EQ(s.policy, SchedPolicy::Other);
        EXPECT_EQ(s.bodyPolicy, SCHED_OTHER);
        EXPECT_TRUE(s.rtRefused);
        EXPECT_TRUE(contains(s.line, "SCHED_FIFO refused")) << s.line;
    }
    // AND the refusal was logged once for both, explaining it
    EXPECT_EQ(out.warnings, 1);
    EXPECT_TRUE(contains(out.firstWarning, "SCHED_FIFO refused")) << out.firstWarning;
    // AND the strict start failed with PermissionDenied and a message saying how to grant it
    const StartOutcome &strict = out.starts[2];
    EXPECT_FALSE(strict.started);
    EXPECT_FALSE(strict.bodyRan);
    EXPECT_EQ(strict.errc, static_cast<int>(Errc::PermissionDenied));
    EXPECT_EQ(strict.sysErrno, EPERM);
    EXPECT_TRUE(contains(strict.what, "SCHED_FIFO")) << strict.what;
    EXPECT_TRUE(contains(strict.what, "CAP_SYS_NICE")) << strict.what;
    EXPECT_TRUE(contains(strict.what, "RLIMIT_RTPRIO")) << strict.what;
}

TEST(RealtimeThreadTest, refusedMemoryLockFallsBackOrFailsWhenRequired)
{
    if (!memoryLockingAvailable())
        GTEST_SKIP() << "sanitizer build: memory locking is skipped by design";
    // GIVEN a child where the kernel refuses mlock and mlockall: RLIMIT_MEMLOCK 0 and no
    // CAP_IPC_LOCK
    ChildOutcome out;
    ASSERT_TRUE(runInChildWithout(
        RLIMIT_MEMLOCK, CAP_IPC_LOCK, "cannot lower RLIMIT_MEMLOCK or drop CAP_IPC_LOCK",
        [](ChildOutcome &o) {
            static char probe[1];
            if (mlock(probe, 1) == 0 || mlockall(MCL_CURRENT) == 0) {
                munlockall();
                skipChild(o, "the kernel still grants mlock");
                return;
            }
            // WHEN a thread with memory locking starts in graceful mode (the default lock: the
            // memory it owns), then with requireRt, then with requireRt and mlockall (All)
            startAndJoin(kTelemetryThread, RealtimeThreadOptions{false, true, -1}, o.starts[0]);
            startAndJoin(kTelemetryThread, RealtimeThreadOptions{true, true, -1}, o.starts[1]);
            RealtimeThreadOptions all{true, true, -1};
            all.lockMode = MemoryLockMode::All;
            startAndJoin(kTelemetryThread, all, o.starts[2]);
        },
        out));
    if (out.skipped)
        GTEST_SKIP() << out.skipReason;

    // THEN the graceful start runs without locked memory, logged once
    ASSERT_TRUE(out.starts[0].started) << out.starts[0].what;
    EXPECT_TRUE(out.starts[0].bodyRan);
    EXPECT_FALSE(out.starts[0].memoryLocked);
    EXPECT_TRUE(contains(out.starts[0].line, "not locked")) << out.starts[0].line;
    EXPECT_EQ(out.warnings, 1);
    EXPECT_TRUE(contains(out.firstWarning, "Failed to lock memory (mlock, owned)"))
        << out.firstWarning;
    // AND the strict starts fail with PermissionDenied naming the call and the fix
    for (int i = 1; i < 3; ++i) {
        const StartOutcome &strict = out.starts[i];
        EXPECT_FALSE(strict.started);
        EXPECT_FALSE(strict.bodyRan);
        EXPECT_EQ(strict.errc, static_cast<int>(Errc::PermissionDenied));
        EXPECT_TRUE(strict.sysErrno == EPERM || strict.sysErrno == ENOMEM) << strict.sysErrno;
        EXPECT_TRUE(contains(strict.what, "mlock/mlockall")) << strict.what;
        EXPECT_TRUE(contains(strict.what, "RLIMIT_MEMLOCK")) << strict.what;
    }
}

TEST(RealtimeThreadTest, cpuAffinityIsAppliedOrRejected)
{
    // GIVEN a child starting control threads pinned to CPU 0, to a CPU that does not exist, and to
    // a CPU number out of range
    ChildOutcome out;
    ASSERT_TRUE(runInChild(
        [](ChildOutcome &o) {
            startAndJoin(kControlThread, RealtimeThreadOptions{false, false, 0}, o.starts[0]);
            startAndJoin(kControlThread, RealtimeThreadOptions{false, false, CPU_SETSIZE - 1},
                         o.starts[1]);
            startAndJoin(kControlThread, RealtimeThreadOptions{false, false, CPU_SETSIZE},
                         o.starts[2]);
        },
        out));
    // THEN the first runs on CPU 0
    ASSERT_TRUE(out.starts[0].started) << out.starts[0].what;
    EXPECT_TRUE(out.starts[0].affinityApplied);
    EXPECT_EQ(out.starts[0].bodyCpu, 0);
    EXPECT_TRUE(contains(out.starts[0].line, "CPU 0")) << out.starts[0].line;
    // AND the others fail with InvalidArgument without running the body
    for (int i = 1; i < 3; ++i) {
        EXPECT_FALSE(out.starts[i].started);
        EXPECT_FALSE(out.starts[i].bodyRan);
        EXPECT_EQ(out.starts[i].errc, static_cast<int>(Errc::InvalidArgument))
            << out.starts[i].what;
        EXPECT_TRUE(contains(out.starts[i].what, "CPU affinity")) << out.starts[i].what;
    }
}

// The cases below use SCHED_OTHER threads without memory locking or affinity: no process-wide state
// changes, so they run in the test process.

constexpr RealtimeThreadOptions kPlainOptions{false, false, -1};

TEST(RealtimeThreadTest, requestStopEndsTheBodyAndJoinWaits)
{
    // GIVEN a running thread whose body loops until asked to stop
    std::atomic<int> loops{0};
    RealtimeThread thread(kTelemetryThread, kPlainOptions, [&loops](StopToken stop) {
        while (!stop.stopRequested()) {
            ++loops;
            SteadyClock::instance().sleepFor(milliseconds(1));
        }
    });
    ASSERT_TRUE(thread.start());
    EXPECT_TRUE(thread.joinable());
    while (loops.load() < 3)
        SteadyClock::instance().sleepFor(milliseconds(1));
    EXPECT_FALSE(thread.finished());
    // WHEN a stop is requested and the thread joined
    thread.requestStop();
    thread.join();
    // THEN the body returned and the thread is no longer joinable
    EXPECT_TRUE(thread.stopRequested());
    EXPECT_TRUE(thread.finished());
    EXPECT_FALSE(thread.joinable());
    thread.join(); // a second join is a no-op
}

TEST(RealtimeThreadTest, destructorStopsAndJoins)
{
    // GIVEN a thread whose body runs until stopped
    std::atomic<bool> bodyReturned{false};
    {
        RealtimeThread thread(kTelemetryThread, kPlainOptions, [&bodyReturned](StopToken stop) {
            while (!stop.stopRequested())
                SteadyClock::instance().sleepFor(milliseconds(1));
            bodyReturned = true;
        });
        ASSERT_TRUE(thread.start());
        // WHEN it goes out of scope
    }
    // THEN the destructor stopped it and waited for the body
    EXPECT_TRUE(bodyReturned.load());
}

TEST(RealtimeThreadTest, startTwiceIsInvalidState)
{
    // GIVEN a started thread
    RealtimeThread thread(kTelemetryThread, kPlainOptions, [](StopToken) {});
    ASSERT_TRUE(thread.start());
    // WHEN started again
    const Result<void> again = thread.start();
    // THEN the second start is refused
    ASSERT_FALSE(again);
    EXPECT_EQ(again.error().code, Errc::InvalidState);
}

TEST(RealtimeThreadTest, missingBodyOrBadConfigIsInvalidArgument)
{
    // GIVEN a thread without body and one with a 16-character name
    RealtimeThread noBody(kTelemetryThread, kPlainOptions, RealtimeThread::Body());
    RealtimeThread longName(ThreadConfig{"0123456789abcdef", SchedPolicy::Other, 0, 256 * 1024},
                            kPlainOptions, [](StopToken) {});
    // WHEN started
    const Result<void> a = noBody.start();
    const Result<void> b = longName.start();
    // THEN both fail with InvalidArgument
    ASSERT_FALSE(a);
    EXPECT_EQ(a.error().code, Errc::InvalidArgument);
    ASSERT_FALSE(b);
    EXPECT_EQ(b.error().code, Errc::InvalidArgument);
}

TEST(RealtimeThreadTest, reportFormatsAsOneLine)
{
    // GIVEN reports of a real-time and of a refused thread
    RealtimeThreadReport rt;
    rt.name = "dt-haptic";
    rt.policy = SchedPolicy::Fifo;
    rt.priority = 90;
    rt.memoryLocked = true;
    rt.lockMode = MemoryLockMode::Owned;
    rt.lockedBytes = 10 * 1024 * 1024 + 512 * 1024;
    rt.cpu = 1;
    rt.affinityApplied = true;
    rt.stackBytes = 262144;
    rt.stackPrefaultedBytes = 245760;
    RealtimeThreadReport refused = rt;
    refused.policy = SchedPolicy::Other;
    refused.priority = 0;
    refused.rtRefused = true;
    refused.memoryLocked = false;
    refused.cpu = -1;
    refused.affinityApplied = false;
    char buf[256];
    // THEN each prints as one line
    EXPECT_STREQ(rt.format(buf, sizeof(buf)),
                 "dt-haptic: SCHED_FIFO priority 90, memory locked (owned, 10.5 MiB), CPU 1, stack "
                 "262144 B (245760 B pre-faulted)");
    RealtimeThreadReport all = rt;
    all.lockMode = MemoryLockMode::All;
    all.lockedBytes = 0;
    EXPECT_TRUE(contains(all.format(buf, sizeof(buf)), "memory locked (all), CPU 1")) << buf;
    EXPECT_STREQ(refused.format(buf, sizeof(buf)), "dt-haptic: SCHED_OTHER priority 0 (SCHED_FIFO "
                                                   "refused), memory not locked, no CPU affinity, "
                                                   "stack 262144 B (245760 B pre-faulted)");
    char tiny[10];
    EXPECT_EQ(std::strlen(rt.format(tiny, sizeof(tiny))), sizeof(tiny) - 1);
}

} // namespace
} // namespace depthtouch::platform
