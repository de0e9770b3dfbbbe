// The real-time discipline of the haptic thread, proven by interposition: this program replaces
// malloc/calloc/realloc/free (glibc, not under AddressSanitizer), operator new/delete,
// pthread_mutex_lock/trylock, the rwlock and semaphore waits, write/writev/pwrite and the stdio
// writers. Each replacement counts a call when a thread_local flag is set, then forwards. The
// task's thread hook sets the flag on the haptic thread before its first update, so every call it
// makes from then on is counted: the test fails if it allocates, takes a lock or writes a file.
//
// The task runs in real time (SteadyClock) with the simulated hand, a decoder thread publishing a
// moving depth video, run-time disable/enable, an unplug and a reconnect.
#include "depthtouch/haptic_task/haptic_task.h"

#include <algorithm>
#include <atomic>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <dlfcn.h>
#include <mutex>
#include <new>
#include <pthread.h>
#include <semaphore.h>
#include <sys/syscall.h>
#include <sys/uio.h>
#include <thread>
#include <unistd.h>

#include <gtest/gtest.h>

#include "app/haptic_task/frames.h"
#include "depthtouch/drivers/mock/sim_haptic_device.h"

#if defined(__SANITIZE_ADDRESS__)
#define DT_INTERPOSE_MALLOC 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define DT_INTERPOSE_MALLOC 0
#endif
#endif
#if !defined(DT_INTERPOSE_MALLOC) && defined(__GLIBC__)
#define DT_INTERPOSE_MALLOC 1
#endif
#ifndef DT_INTERPOSE_MALLOC
#define DT_INTERPOSE_MALLOC 0
#endif

namespace {

thread_local bool tWatched = false;
std::atomic<std::uint64_t> gAllocations{0};
std::atomic<std::uint64_t> gFrees{0};
std::atomic<std::uint64_t> gLocks{0};
std::atomic<std::uint64_t> gWrites{0};

inline void countIf(std::atomic<std::uint64_t> &counter) noexcept
{
    if (tWatched)
        counter.fetch_add(1, std::memory_order_relaxed);
}

template <class F> F resolve(const char *name) noexcept
{
    return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

/// The name of a forwarded function, as a template argument (one lookup per function).
template <std::size_t N> struct Symbol {
    constexpr Symbol(const char (&s)[N]) noexcept { std::copy_n(s, N, name); }
    char name[N];
};

/// Counts a call in \a counter (when the thread is watched) and forwards \a args to the next
/// definition of the function named \a S, of type R(Args...), looked up on the first call.
/// \return what that definition returns.
template <Symbol S, class R, class... Args>
R countAndForward(std::atomic<std::uint64_t> &counter, Args... args)
{
    static const auto real = resolve<R (*)(Args...)>(S.name);
    countIf(counter);
    return real(args...);
}

} // namespace

// ---- Heap ------------------------------------------------------------------------------------
#if DT_INTERPOSE_MALLOC
extern "C" {
void *__libc_malloc(std::size_t);
void *__libc_calloc(std::size_t, std::size_t);
void *__libc_realloc(void *, std::size_t);
void __libc_free(void *);
void *__libc_memalign(std::size_t, std::size_t);

void *malloc(std::size_t size)
{
    countIf(gAllocations);
    return __libc_malloc(size);
}
void *calloc(std::size_t n, std::size_t size)
{
    countIf(gAllocations);
    return __libc_calloc(n, size);
}
void *realloc(void *p, std::size_t size)
{
    countIf(gAllocations);
    return __libc_realloc(p, size);
}
void free(void *p)
{
    if (p != nullptr)
        countIf(gFrees);
    __libc_free(p);
}
void *aligned_alloc(std::size_t alignment, std::size_t size)
{
    countIf(gAllocations);
    return __libc_memalign(alignment, size);
}
int posix_memalign(void **out, std::size_t alignment, std::size_t size)
{
    countIf(gAllocations);
    void *p = __libc_memalign(alignment, size);
    if (p == nullptr)
        return ENOMEM;
    *out = p;
    return 0;
}
}
#endif

// Every unaligned operator new/delete, so they always pair with malloc/free.
void *operator new(std::size_t size)
{
    countIf(gAllocations);
    if (void *p = std::malloc(size != 0 ? size : 1))
        return p;
    throw std::bad_alloc();
}
void *operator new[](std::size_t size)
{
    return ::operator new(size);
}
void *operator new(std::size_t size, const std::nothrow_t &) noexcept
{
    countIf(gAllocations);
    return std::malloc(size != 0 ? size : 1);
}
void *operator new[](std::size_t size, const std::nothrow_t &t) noexcept
{
    return ::operator new(size, t);
}
void operator delete(void *p) noexcept
{
    if (p != nullptr)
        countIf(gFrees);
    std::free(p);
}
void operator delete[](void *p) noexcept
{
    ::operator delete(p);
}
void operator delete(void *p, std::size_t) noexcept
{
    ::operator delete(p);
}
void operator delete[](void *p, std::size_t) noexcept
{
    ::operator delete(p);
}
void operator delete(void *p, const std::nothrow_t &) noexcept
{
    ::operator delete(p);
}
void operator delete[](void *p, const std::nothrow_t &) noexcept
{
    ::operator delete(p);
}

// ---- Locks -----------------------------------------------------------------------------------
extern "C" {
int pthread_mutex_lock(pthread_mutex_t *m)
{
    return countAndForward<"pthread_mutex_lock", int>(gLocks, m);
}
int pthread_mutex_trylock(pthread_mutex_t *m)
{
    return countAndForward<"pthread_mutex_trylock", int>(gLocks, m);
}
int pthread_rwlock_rdlock(pthread_rwlock_t *l)
{
    return countAndForward<"pthread_rwlock_rdlock", int>(gLocks, l);
}
int pthread_rwlock_wrlock(pthread_rwlock_t *l)
{
    return countAndForward<"pthread_rwlock_wrlock", int>(gLocks, l);
}
int sem_wait(sem_t *s)
{
    return countAndForward<"sem_wait", int>(gLocks, s);
}

// ---- Writes ----------------------------------------------------------------------------------
ssize_t write(int fd, const void *buf, std::size_t count)
{
    countIf(gWrites);
    return static_cast<ssize_t>(syscall(SYS_write, fd, buf, count));
}
ssize_t writev(int fd, const struct iovec *iov, int n)
{
    countIf(gWrites);
    return static_cast<ssize_t>(syscall(SYS_writev, fd, iov, n));
}
ssize_t pwrite(int fd, const void *buf, std::size_t count, off_t offset)
{
    countIf(gWrites);
    return static_cast<ssize_t>(syscall(SYS_pwrite64, fd, buf, count, offset));
}
std::size_t fwrite(const void *p, std::size_t size, std::size_t n, FILE *f)
{
    return countAndForward<"fwrite", std::size_t>(gWrites, p, size, n, f);
}
int fputs(const char *s, FILE *f)
{
    return countAndForward<"fputs", int>(gWrites, s, f);
}
int fputc(int c, FILE *f)
{
    return countAndForward<"fputc", int>(gWrites, c, f);
}
int vfprintf(FILE *f, const char *format, va_list args)
{
    return countAndForward<"vfprintf", int>(gWrites, f, format, args);
}
// The interposers pass their caller's format on (clang's -Wformat-nonliteral would stop them).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
int fprintf(FILE *f, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    const int n = vfprintf(f, format, args);
    va_end(args);
    return n;
}
int __fprintf_chk(FILE *f, int, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    const int n = vfprintf(f, format, args);
    va_end(args);
    return n;
}
int __vfprintf_chk(FILE *f, int, const char *format, va_list args)
{
    return vfprintf(f, format, args);
}
#pragma GCC diagnostic pop
int fflush(FILE *f)
{
    return countAndForward<"fflush", int>(gWrites, f);
}
}

namespace depthtouch::haptic_task {
namespace {

using namespace std::chrono_literals;

struct Counts {
    std::uint64_t allocations, frees, locks, writes;
};

Counts snapshot()
{
    return {gAllocations.load(), gFrees.load(), gLocks.load(), gWrites.load()};
}

void watchThisThread(void *) noexcept
{
    tWatched = true;
}

TEST(DisciplineTest, interposersCountOnAWatchedThread)
{
    // The instrument itself: a watched thread that allocates, locks and writes is caught.
    const Counts before = snapshot();
    std::thread t([] {
        watchThisThread(nullptr);
        auto *p = new int(3);
        delete p;
        void *m = std::malloc(64);
        std::free(m);
        std::mutex mutex;
        mutex.lock();
        mutex.unlock();
        FILE *f = std::fopen("/dev/null", "w");
        if (f != nullptr) {
            std::fwrite("x", 1, 1, f);
            std::fprintf(f, "%d\n", 42);
            std::fclose(f);
        }
        const ssize_t n = ::write(-1, "x", 1);
        (void)n;
        tWatched = false;
    });
    t.join();
    const Counts after = snapshot();
    EXPECT_GE(after.allocations - before.allocations, DT_INTERPOSE_MALLOC ? 2u : 1u);
    EXPECT_GE(after.frees - before.frees, DT_INTERPOSE_MALLOC ? 2u : 1u);
    EXPECT_GE(after.locks - before.locks, 1u);
    EXPECT_GE(after.writes - before.writes, 3u);
}

TEST(DisciplineTest, hapticThreadNeverAllocatesLocksOrWritesAfterStart)
{
#ifndef __GLIBC__
    GTEST_SKIP() << "The interposers need glibc";
#endif
    platform::SteadyClock &clock = platform::SteadyClock::instance();
    constexpr int kW = 96;
    constexpr int kH = 72;
    auto handoff = DepthHandoff::create(kW, kH, scene::SampleFormat::Gray16);
    ASSERT_TRUE(handoff);
    hal::BackendConfig cfg;
    cfg.options =
        hal::OptionList("intent=stroke,force=2,z=0.01,speed=0.1,path=-0.03:-0.01/0.03:0.01");
    auto settings = drivers::SimHandSettings::parse(cfg.options);
    ASSERT_TRUE(settings);
    drivers::SimHapticDevice sim(clock, *settings);

    HapticTaskConfig c;
    c.rampTime = 0.02;
    c.telemetryIntervalMs = 2;
    c.reconnectIntervalMs = 5;
    c.threadHook = &watchThisThread;
    char dir[] = "/tmp/dt-discipline-XXXXXX";
    ASSERT_NE(mkdtemp(dir), nullptr);
    c.forceLogPath = std::string(dir) + "/force-log.csv"; // written, but not by the haptic thread
    auto task = HapticTask::create(c, sim, **handoff, clock);
    ASSERT_TRUE(task);

    // A decoder thread publishes a moving bump at about 100 fps.
    std::atomic<bool> decoding{true};
    (*handoff)->setMediaOrigin(clock.now());
    std::thread decoder([&] {
        test::Frame16 frame(kW, kH, 0.0);
        for (int i = 0; decoding.load(); ++i) {
            frame.pts = i * 0.01;
            const double cx = 0.03 * std::sin(i * 0.05);
            frame.fill([&](double x, double y) {
                return -0.01 + 0.008 * std::exp(-((x - cx) * (x - cx) + y * y) / 2e-4);
            });
            if (!(*handoff)->push(frame.view()))
                ADD_FAILURE() << "push failed";
            clock.sleepFor(10ms);
        }
    });

    const Counts before = snapshot();
    ASSERT_TRUE((*task)->start());
    clock.sleepFor(150ms);
    (*task)->setEnabled(false);
    clock.sleepFor(50ms);
    (*task)->setEnabled(true);
    const HapticStats mid = (*task)->stats();
    // Unplug, then plug back: the lost path and the reconnection. Each waits for the task to have
    // seen it (a loaded machine may run the haptic thread late); the 10 s only guards against a
    // hang.
    auto waitUntil = [&clock](auto done) {
        const auto deadline = clock.now() + 10s;
        while (!done() && clock.now() < deadline)
            clock.sleepFor(1ms);
        return done();
    };
    sim.disconnect();
    EXPECT_TRUE(waitUntil([&] { return (*task)->stats().deviceLosses >= 1; }))
        << "the unplug was not seen";
    sim.reconnect();
    EXPECT_TRUE(waitUntil([&] { return (*task)->stats().reconnects >= 1; })) << "no reconnection";
    const std::uint64_t afterReconnect = (*task)->stats().updates;
    EXPECT_TRUE(waitUntil([&] { return (*task)->stats().updates >= afterReconnect + 50; }));
    (*task)->stop();
    const Counts after = snapshot();
    decoding.store(false);
    decoder.join();

    const HapticStats s = (*task)->stats();
    EXPECT_EQ(after.allocations - before.allocations, 0u) << "allocations on the haptic thread";
    EXPECT_EQ(after.frees - before.frees, 0u) << "frees on the haptic thread";
    EXPECT_EQ(after.locks - before.locks, 0u) << "locks taken on the haptic thread";
    EXPECT_EQ(after.writes - before.writes, 0u) << "writes on the haptic thread";
    // The run did what it should have: updates, rendering, contact, an unplug and a reconnect.
    EXPECT_GT(s.updates, 50u);
    EXPECT_GT(mid.renderedUpdates, 10u);
    EXPECT_GT(s.contactUpdates, 0u);
    EXPECT_EQ(s.deviceLosses, 1u);
    EXPECT_GE(s.reconnects, 1u);
    std::remove(c.forceLogPath.c_str());
    rmdir(dir);
}

} // namespace
} // namespace depthtouch::haptic_task
