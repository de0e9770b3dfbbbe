// Memory locking of a real-time thread (memory_lock.h, RealtimeThreadOptions::lockMode): what is
// locked, the page faults of a thread, the stack size of every thread of the table, and the
// guarantee itself: no page fault on the locked thread while the process is paged out. Cases that
// lock memory or change it process-wide run in a forked child.

#include "depthtouch/platform/memory_lock.h"

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <thread>
#include <dlfcn.h>
#include <fcntl.h>
#include <pthread.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/periodic_timer.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/thread_config.h"
#include "support/memory_pressure.h"

namespace depthtouch::platform {
namespace {

using std::chrono::milliseconds;

std::size_t page()
{
    return static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
}

/// \return true when a forked child may mlock() one page.
bool probeMlock()
{
    if (!memoryLockingAvailable())
        return false;
    const pid_t pid = fork();
    if (pid == 0) {
        static char probe[1];
        _exit(mlock(probe, 1) == 0 ? 0 : 1);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/// \return the "Locked:" figure (KiB) of the mapping in /proc/self/smaps that holds \a address, or
/// −1 when no mapping holds it.
double lockedKiBOfMappingAt(const void *address)
{
    std::FILE *f = std::fopen("/proc/self/smaps", "re");
    if (f == nullptr)
        return -1.0;
    const auto at = reinterpret_cast<std::uintptr_t>(address);
    char line[512];
    bool inside = false;
    double locked = -1.0;
    while (locked < 0.0 && std::fgets(line, sizeof(line), f) != nullptr) {
        unsigned long begin = 0, end = 0;
        long long kib = 0;
        // A mapping's header line opens with its range ("7f…-7f… r-xp …"), no field line does.
        if (std::sscanf(line, "%lx-%lx ", &begin, &end) == 2)
            inside = at >= begin && at < end;
        else if (inside && std::sscanf(line, "Locked: %lld kB", &kib) == 1)
            locked = static_cast<double>(kib);
    }
    std::fclose(f);
    return locked;
}

TEST(MemoryLockTest, lockRegionLocksTheMappedPagesUpToAHole)
{
    if (!probeMlock())
        GTEST_SKIP() << "the kernel refuses mlock() here (no CAP_IPC_LOCK, RLIMIT_MEMLOCK 0)";
    // GIVEN four mapped pages whose third is unmapped again
    const std::size_t p = page();
    auto *base = static_cast<unsigned char *>(
        mmap(nullptr, 4 * p, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0));
    ASSERT_NE(base, MAP_FAILED);
    ASSERT_EQ(munmap(base + 2 * p, p), 0);
    const double lockedBefore = lockedMiB();

    // WHEN a region from inside the first page over all four is locked
    const LockResult r = lockRegion({base + 100, 4 * p - 200});

    // THEN the two pages before the hole are locked, faulted in, and counted in VmLck
    EXPECT_EQ(r.failedErrno, 0);
    EXPECT_EQ(r.bytes, 2 * p);
    EXPECT_EQ(r.regions, 1);
    unsigned char resident[2] = {};
    ASSERT_EQ(mincore(base, 2 * p, resident), 0);
    EXPECT_EQ(resident[0] & 1, 1);
    EXPECT_EQ(resident[1] & 1, 1);
    EXPECT_NEAR(lockedMiB() - lockedBefore, static_cast<double>(2 * p) / (1024.0 * 1024.0), 1e-9);
    unlockRegion({base, 2 * p});
    EXPECT_NEAR(lockedMiB(), lockedBefore, 1e-9);
    munmap(base, 2 * p);
    munmap(base + 3 * p, p);
}

TEST(MemoryLockTest, lockLoadedObjectsLocksTheProgramAndTheRuntimeOnly)
{
    if (!probeMlock())
        GTEST_SKIP() << "the kernel refuses mlock() here (no CAP_IPC_LOCK, RLIMIT_MEMLOCK 0)";
    // GIVEN the prefix list of the runtime, and one that names no loaded object
    // WHEN each is locked
    const LockResult none =
        lockLoadedObjects(std::array<const char *, 2>{"libdoes-not-exist.so", nullptr}.data());
    const LockResult runtime = lockLoadedObjects(kRuntimeObjects);

    // THEN nothing is locked for the unknown name, and the program, libc and the others are, a few
    // MiB and not the whole process
    EXPECT_EQ(none.bytes, 0u);
    EXPECT_EQ(none.regions, 0);
    EXPECT_EQ(runtime.failedErrno, 0);
    EXPECT_GE(runtime.regions, 2 * 4); // at least the program and libc, each with its segments
    EXPECT_GT(runtime.bytes, 1024u * 1024u);
    EXPECT_LT(runtime.bytes, 64u * 1024u * 1024u);
    EXPECT_GE(lockedMiB() * 1024.0 * 1024.0, 0.99 * static_cast<double>(runtime.bytes));
    std::printf("runtime objects locked: %.1f MiB in %d segments; VmLck %.1f MiB, VmRSS %.1f MiB\n",
                static_cast<double>(runtime.bytes) / (1024.0 * 1024.0), runtime.regions,
                lockedMiB(), residentMiB());
}

TEST(MemoryLockTest, lockLoadedObjectsFromASharedObjectLocksThatObjectsOwnCode)
{
    if (!probeMlock())
        GTEST_SKIP() << "the kernel refuses mlock() here (no CAP_IPC_LOCK, RLIMIT_MEMLOCK 0)";
    // GIVEN a shared object that embeds the locking code, as the GStreamer element's plugin does,
    // loaded into this program, its code not locked
    void *module = dlopen(DT_LOCK_MODULE, RTLD_NOW | RTLD_LOCAL);
    ASSERT_NE(module, nullptr) << dlerror();
    using LockFromModule = long (*)(const void **);
    auto lockFromModule = reinterpret_cast<LockFromModule>(dlsym(module, "dtLockFromModule"));
    ASSERT_NE(lockFromModule, nullptr) << dlerror();
    const auto text = reinterpret_cast<const void *>(lockFromModule);
    EXPECT_EQ(lockedKiBOfMappingAt(text), 0.0);

    // WHEN that object locks the objects named "" (the program and the object holding the code)
    const void *reported = nullptr;
    const long bytes = lockFromModule(&reported);

    // THEN its own code segment is locked in whole, which the program's name alone never matched
    ASSERT_GT(bytes, 0);
    EXPECT_EQ(reported, text);
    const double locked = lockedKiBOfMappingAt(text);
    EXPECT_GT(locked, 0.0);
    std::printf("the module's code mapping: %.0f KiB locked of %ld bytes locked in all\n", locked,
                bytes);
    dlclose(module);
}

TEST(MemoryLockTest, threadPageFaultsCountTheCallingThreadsFirstTouches)
{
    // GIVEN 64 fresh anonymous pages
    const std::size_t p = page();
    constexpr std::size_t kPages = 64;
    auto *base = static_cast<volatile unsigned char *>(
        mmap(nullptr, kPages * p, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0));
    ASSERT_NE(base, MAP_FAILED);

    // WHEN another thread touches them while this one only reads its counters
    const PageFaults mineBefore = threadPageFaults();
    PageFaults other{};
    std::thread toucher([&] {
        const PageFaults before = threadPageFaults();
        for (std::size_t i = 0; i < kPages; ++i)
            base[i * p] = 1;
        const PageFaults after = threadPageFaults();
        other = {after.minor - before.minor, after.major - before.major};
    });
    toucher.join();
    const PageFaults mineAfter = threadPageFaults();

    // THEN the toucher counted one minor fault a page (or fewer with fault-around, never none), and
    // this thread none of them
    EXPECT_GE(other.minor, 1u);
    // (AddressSanitizer's shadow memory adds about one fault per 8 pages: 72 of 64 measured.)
    EXPECT_LE(other.minor, kPages + kPages / 4);
    EXPECT_EQ(other.major, 0u);
    EXPECT_LT(mineAfter.minor - mineBefore.minor, kPages / 2);
    munmap(const_cast<unsigned char *>(base), kPages * p);
}

TEST(MemoryLockTest, everyThreadOfTheTableGetsItsStackSize)
{
    // GIVEN every row of the thread table started as the product starts it (the haptic thread with
    // its real-time options but no lock, the others with kPlainThreadOptions); the control row is
    // the main thread's and is not started from the table
    for (const ThreadConfig &row : kThreadTable) {
        if (std::strcmp(row.name, kControlThread.name) == 0)
            continue;
        RealtimeThreadOptions options = kPlainThreadOptions;
        if (row.policy == SchedPolicy::Fifo)
            options.prefaultStack = true;
        std::size_t seen = 0;
        // WHEN the thread reads its own stack size
        RealtimeThread thread(row, options, [&seen](StopToken) {
            pthread_attr_t attr;
            if (pthread_getattr_np(pthread_self(), &attr) == 0) {
                (void)pthread_attr_getstacksize(&attr, &seen);
                pthread_attr_destroy(&attr);
            }
        });
        ASSERT_TRUE(thread.start()) << row.name;
        thread.join();
        // THEN it was created with the row's size, page-rounded (not the 8 MiB default of
        // RLIMIT_STACK), and has at least that much: glibc may hand out a cached stack of an ended
        // thread up to four times larger
        const std::size_t wanted = (row.stackBytes + page() - 1) / page() * page();
        EXPECT_EQ(thread.report().stackBytes, wanted) << row.name;
        EXPECT_GE(seen, wanted) << row.name;
        EXPECT_LE(seen, 4 * wanted + 64 * 1024) << row.name;
    }
}

/// What the child of the pressure test reports.
struct PressureOutcome {
    bool started = false;
    bool locked = false;
    int pagedOut = 0; ///< Mappings MADV_PAGEOUT accepted.
    bool pageoutKnown = false;
    std::uint64_t minor = 0; ///< Faults of the body after its warm-up.
    std::uint64_t major = 0;
    std::uint64_t cycles = 0;
    double sum = 0.0;
    char line[256] = {};
};

/// A read-only, file-backed region the body reads every cycle: the tail of this test program's own
/// file, which the loader does not map (debug sections), so its pages are this mapping's alone.
struct FileRegion {
    const unsigned char *data = nullptr;
    std::size_t bytes = 0;
};

FileRegion mapOwnFile(std::size_t want)
{
    const int fd = open("/proc/self/exe", O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return {};
    struct stat st {};
    FileRegion r;
    if (fstat(fd, &st) == 0 && static_cast<std::size_t>(st.st_size) > 2 * want) {
        const std::size_t offset = (static_cast<std::size_t>(st.st_size) - want) / page() * page();
        void *m = mmap(nullptr, want, PROT_READ, MAP_PRIVATE, fd, static_cast<off_t>(offset));
        if (m != MAP_FAILED)
            r = {static_cast<const unsigned char *>(m), want};
    }
    close(fd);
    return r;
}

/// In a forked child: the haptic thread's row runs a 1 kHz loop that reads 256 KiB of a
/// file mapping, calls into libm and copies into its stack; after a warm-up of 50 cycles the main
/// thread pages the whole process out (MADV_PAGEOUT) three times; the body counts its own faults
/// after the warm-up (getrusage(RUSAGE_THREAD) from inside, into preallocated fields).
PressureOutcome runUnderPressure(MemoryLockMode mode)
{
    const PressureOutcome none{};
    int fds[2];
    if (pipe(fds) != 0)
        return none;
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        // Everything the body touches is in one object, locked as a region; the body captures one
        // pointer (kept in the RealtimeThread, which locks itself).
        struct Shared {
            PressureOutcome o{};
            FileRegion file;
            std::atomic<std::uint64_t> cycles{0};
            std::atomic<bool> pressed{false};
        };
        static Shared shared;
        Shared *const s = &shared;
        PressureOutcome &o = s->o;
        constexpr std::size_t kRegion = 256 * 1024;
        s->file = mapOwnFile(kRegion);
        const MemoryRegion regions[] = {{s->file.data, s->file.bytes}, {s, sizeof(Shared)}};
        RealtimeThreadOptions options;
        options.lockMemory = mode != MemoryLockMode::None;
        options.lockMode = mode;
        options.regions = regions;
        options.regionCount = 2;
        RealtimeThread thread(kHapticThread, options, [s](StopToken stop) noexcept {
            PeriodicTimer timer(SteadyClock::instance(), milliseconds(1));
            timer.start();
            PageFaults warm{};
            unsigned char copy[4096];
            std::uint64_t n = 0;
            double sum = 0.0;
            while (!stop.stopRequested()) {
                (void)timer.wait();
                for (std::size_t i = 0; i < s->file.bytes; i += 4096)
                    sum += s->file.data[i];
                std::memcpy(copy, s->file.data + (n % 60) * 4096, sizeof(copy));
                sum += std::sin(static_cast<double>(copy[n % sizeof(copy)]));
                ++n;
                if (n == 50)
                    warm = threadPageFaults();
                s->cycles.store(n, std::memory_order_release);
                if (s->pressed.load(std::memory_order_acquire) && n > 50) {
                    const PageFaults now = threadPageFaults();
                    s->o.minor = now.minor - warm.minor;
                    s->o.major = now.major - warm.major;
                }
            }
            s->o.sum = sum;
        });
        const FileRegion &file = s->file;
        std::atomic<std::uint64_t> &cycles = s->cycles;
        std::atomic<bool> &pressed = s->pressed;
        o.started = file.data != nullptr && thread.start().has_value();
        o.locked = thread.report().memoryLocked;
        if (o.started) {
            while (cycles.load(std::memory_order_acquire) < 60)
                SteadyClock::instance().sleepFor(milliseconds(5));
            for (int round = 0; round < 3; ++round) {
                const test::PageOutResult p = test::pageOutProcess();
                o.pagedOut += p.mappings;
                o.pageoutKnown = o.pageoutKnown || p.supported;
                const std::uint64_t seen = cycles.load(std::memory_order_acquire);
                pressed.store(true, std::memory_order_release);
                while (cycles.load(std::memory_order_acquire) < seen + 100)
                    SteadyClock::instance().sleepFor(milliseconds(5));
            }
            thread.requestStop();
            thread.join();
            o.cycles = cycles.load();
        }
        thread.report().format(o.line, sizeof(o.line));
        const ssize_t written = write(fds[1], &o, sizeof(o));
        _exit(written == static_cast<ssize_t>(sizeof(o)) ? 0 : 1);
    }
    close(fds[1]);
    PressureOutcome o{};
    const ssize_t got = read(fds[0], &o, sizeof(o));
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    return got == static_cast<ssize_t>(sizeof(o)) ? o : none;
}

TEST(MemoryLockTest, lockedThreadTakesNoPageFaultUnderMemoryPressure)
{
    // GIVEN the loop without locking, paged out three times after its warm-up: the control, which
    // shows that the pressure reaches what the loop touches
    const PressureOutcome unlocked = runUnderPressure(MemoryLockMode::None);
    ASSERT_TRUE(unlocked.started) << unlocked.line;
    if (!unlocked.pageoutKnown)
        GTEST_SKIP() << "the kernel refuses madvise(MADV_PAGEOUT) (Linux < 5.4): no pressure";
    std::printf("unlocked: %llu minor, %llu major faults after the warm-up (%d mappings paged "
                "out; %llu cycles)\n",
                static_cast<unsigned long long>(unlocked.minor),
                static_cast<unsigned long long>(unlocked.major), unlocked.pagedOut,
                static_cast<unsigned long long>(unlocked.cycles));
    EXPECT_GT(unlocked.minor + unlocked.major, 0u)
        << "paging out did not reach the unlocked loop's pages: the test shows nothing";

    // WHEN the same loop runs with its memory locked as the haptic task's (Owned: stack, program,
    // C/C++ runtime, its regions)
    if (!memoryLockingAvailable())
        GTEST_SKIP() << "sanitizer build: memory locking is skipped by design";
    const PressureOutcome locked = runUnderPressure(MemoryLockMode::Owned);
    ASSERT_TRUE(locked.started) << locked.line;
    if (!locked.locked)
        GTEST_SKIP() << "the kernel refuses mlock() here (no CAP_IPC_LOCK, RLIMIT_MEMLOCK too "
                        "small): "
                     << locked.line;
    std::printf("locked (%s): %llu minor, %llu major faults after the warm-up (%d mappings paged "
                "out; %llu cycles)\n",
                locked.line, static_cast<unsigned long long>(locked.minor),
                static_cast<unsigned long long>(locked.major), locked.pagedOut,
                static_cast<unsigned long long>(locked.cycles));

    // THEN it took no page fault at all, minor or major
    EXPECT_EQ(locked.minor, 0u);
    EXPECT_EQ(locked.major, 0u);
    EXPECT_GE(locked.cycles, 350u);
    EXPECT_GT(locked.pagedOut, 0);
}

} // namespace
} // namespace depthtouch::platform
