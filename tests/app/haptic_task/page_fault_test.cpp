// The haptic task keeps its real-time guarantee with the memory it locks (MemoryLockMode::Owned,
// docs/memory.md): on the steady clock at 1 kHz with the simulated hand stroking a 640x480 depth
// frame, the whole process is paged out (MADV_PAGEOUT) three times after the warm-up, and the
// haptic thread counts its own page faults (getrusage(RUSAGE_THREAD) from inside the thread,
// HapticStats::pageFaults*): zero. Its own process: it pages the process out.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fcntl.h>
#include <memory>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "app/haptic_task/frames.h"
#include "depthtouch/drivers/mock/sim_haptic_device.h"
#include "depthtouch/haptic_task/haptic_task.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/memory_lock.h"
#include "support/memory_pressure.h"

namespace depthtouch::haptic_task::test {
namespace {

using namespace std::chrono_literals;

/// A witness of the pressure: pages of this program's file the loader does not map (its tail), read
/// once, not locked; pageOutProcess() must take them away.
class Witness {
public:
    Witness()
    {
        const int fd = open("/proc/self/exe", O_RDONLY | O_CLOEXEC);
        struct stat st {};
        if (fd >= 0 && fstat(fd, &st) == 0 && st.st_size > static_cast<off_t>(2 * kBytes)) {
            const off_t offset = (st.st_size - static_cast<off_t>(kBytes)) / 4096 * 4096;
            void *m = mmap(nullptr, kBytes, PROT_READ, MAP_PRIVATE, fd, offset);
            data_ = m != MAP_FAILED ? static_cast<const unsigned char *>(m) : nullptr;
        }
        if (fd >= 0)
            close(fd);
        const volatile unsigned char *bytes = data_;
        for (std::size_t i = 0; bytes != nullptr && i < kBytes; i += 4096)
            sum_ = sum_ + bytes[i];
    }
    ~Witness()
    {
        if (data_ != nullptr)
            munmap(const_cast<unsigned char *>(data_), kBytes);
    }
    Witness(const Witness &) = delete;
    Witness &operator=(const Witness &) = delete;
    /// \return the pages of the witness mapped into this process now (the present bit of
    /// /proc/self/pagemap; mincore() would tell the page cache's residency instead), -1: unknown.
    [[nodiscard]] int mappedPages() const
    {
        if (data_ == nullptr)
            return -1;
        const int fd = open("/proc/self/pagemap", O_RDONLY | O_CLOEXEC);
        if (fd < 0)
            return -1;
        std::uint64_t entries[kBytes / 4096] = {};
        const auto first = reinterpret_cast<std::uintptr_t>(data_) / 4096;
        const ssize_t got =
            pread(fd, entries, sizeof(entries), static_cast<off_t>(first * sizeof(entries[0])));
        close(fd);
        if (got != static_cast<ssize_t>(sizeof(entries)))
            return -1;
        int n = 0;
        for (const std::uint64_t e : entries)
            n += static_cast<int>(e >> 63);
        return n;
    }

private:
    static constexpr std::size_t kBytes = 64 * 4096;
    const unsigned char *data_ = nullptr;
    volatile unsigned sum_ = 0;
};

/// Waits (on the steady clock) until the task has run \a updates updates.
void waitForUpdates(HapticTask &task, std::uint64_t updates)
{
    while (task.stats().updates < updates)
        platform::SteadyClock::instance().sleepFor(5ms);
}

TEST(HapticTaskPageFaultTest, lockedTaskTakesNoPageFaultUnderMemoryPressure)
{
    if (!platform::memoryLockingAvailable())
        GTEST_SKIP() << "sanitizer build: memory locking is skipped by design";
    // GIVEN the haptic task with its default memory lock, the simulated hand stroking a 640x480
    // frame on the steady clock
    platform::SteadyClock &clock = platform::SteadyClock::instance();
    auto handoff = DepthHandoff::create(640, 480, scene::SampleFormat::Gray16);
    ASSERT_TRUE(handoff);
    Frame16 frame(640, 480, 0.0);
    frame.fill([](double x, double y) { return 0.004 * std::sin(60.0 * x) * std::cos(40.0 * y); });
    ASSERT_TRUE((*handoff)->push(frame.view()));
    (*handoff)->setMediaOrigin(clock.now());
    hal::BackendConfig cfg;
    cfg.clock = &clock;
    cfg.options = hal::OptionList("intent=stroke,force=1.5,z=0.01,speed=0.05");
    auto settings = drivers::SimHandSettings::parse(cfg.options);
    ASSERT_TRUE(settings);
    auto device = std::make_unique<drivers::SimHapticDevice>(clock, *settings);
    HapticTaskConfig config;
    ASSERT_EQ(config.memoryLock, platform::MemoryLockMode::Owned);
    auto task = HapticTask::create(config, *device, **handoff, clock);
    ASSERT_TRUE(task) << task.error().what;
    ASSERT_TRUE((*task)->start());
    waitForUpdates(**task, HapticTask::kWarmupUpdates + 50);

    // WHEN the process is paged out three times, 150 updates apart
    depthtouch::test::PageOutResult pressure;
    const Witness witness;
    const int witnessBefore = witness.mappedPages();
    int witnessAfter = witnessBefore;
    for (int round = 0; round < 3; ++round) {
        const depthtouch::test::PageOutResult p = depthtouch::test::pageOutProcess();
        pressure.mappings += p.mappings;
        pressure.supported = pressure.supported || p.supported;
        if (round == 0)
            witnessAfter = witness.mappedPages();
        waitForUpdates(**task, (*task)->stats().updates + 150);
    }
    (*task)->stop();
    const HapticStats s = (*task)->stats();
    std::printf("%s\npage faults after the warm-up: %llu minor, %llu major (%llu in the warm-up); "
                "%llu updates, %.1f MiB locked for the task; paged out %d mappings (an unlocked "
                "witness: %d of its pages resident before, %d after)\n",
                s.thread.c_str(), static_cast<unsigned long long>(s.pageFaultsMinor),
                static_cast<unsigned long long>(s.pageFaultsMajor),
                static_cast<unsigned long long>(s.pageFaultsWarmup),
                static_cast<unsigned long long>(s.updates), s.lockedMiB, pressure.mappings,
                witnessBefore, witnessAfter);
    if (!pressure.supported)
        GTEST_SKIP() << "the kernel refuses madvise(MADV_PAGEOUT) (Linux < 5.4): no pressure";
    if (!(*task)->threadReport().memoryLocked)
        GTEST_SKIP() << "the kernel refuses mlock() here (no CAP_IPC_LOCK, RLIMIT_MEMLOCK too "
                        "small): "
                     << s.thread;

    // THEN the pressure was real (pages left the process) and the haptic thread took no page
    // fault, minor or major, while it ran its updates through it
    ASSERT_GT(witnessBefore, 0) << "no witness mapping: the test cannot show the pressure";
    EXPECT_LT(witnessAfter, witnessBefore);
    EXPECT_EQ(s.pageFaultsMinor, 0u);
    EXPECT_EQ(s.pageFaultsMajor, 0u);
    EXPECT_GE(s.updates, HapticTask::kWarmupUpdates + 50 + 3 * 150);
    EXPECT_GT(s.renderedUpdates, 0u);
    EXPECT_GT(s.lockedMiB, 0.0);
    EXPECT_LT(s.lockedMiB, 48.0);
    device->close();
}

} // namespace
} // namespace depthtouch::haptic_task::test
