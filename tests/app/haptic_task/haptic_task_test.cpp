// HapticTask on simulated time (platform::ManualClock, Blocking mode: the test advances the clock
// by one period and the haptic thread runs exactly one update): the closed loop with the simulated
// hand, the watchdog, hot-plug, the enable ramp, the force-rate limit, the clamp and the stop
// paths.
#include "depthtouch/haptic_task/haptic_task.h"

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <string>
#include <sys/mman.h>
#include <unistd.h>
#include <vector>

#include <gtest/gtest.h>

#include "app/haptic_task/task_rig.h"
#include "depthtouch/platform/log.h"

namespace depthtouch::haptic_task {
namespace {

using namespace std::chrono_literals;
using platform::ManualClock;
using test::Frame16;
using test::kH;
using test::kW;
using test::makeSim;
using test::pressScript;
using test::Rig;
using test::startPressingFlat;

/// A device that makes its reads take simulated time (a slow USB transaction), for the deadline
/// watchdog. Delegates everything else.
class SlowDevice final : public test::DelegatingDevice {
public:
    SlowDevice(hal::HapticDevice &inner, ManualClock &clock)
        : DelegatingDevice(inner), clock_(clock)
    {
    }
    Result<void> read(hal::HapticState &out) noexcept override
    {
        if (slowCycles_.load() > 0) {
            slowCycles_.fetch_sub(1);
            clock_.advance(3ms);
        }
        return DelegatingDevice::read(out);
    }
    Result<void> commandForce(const hal::Vec3 &force) noexcept override
    {
        const double magnitude =
            std::sqrt(force.x * force.x + force.y * force.y + force.z * force.z);
        if (magnitude > largestCommand_.load())
            largestCommand_.store(magnitude);
        return DelegatingDevice::commandForce(force);
    }

    /// The next \a n reads each take 3 ms (three periods at 1 kHz).
    void makeSlow(int n) { slowCycles_.store(n); }
    /// Forgets the forces commanded so far (largestCommand()).
    void markCommands() { largestCommand_.store(0.0); }
    /// \return the largest force commanded since markCommands(), N.
    double largestCommand() const { return largestCommand_.load(); }

private:
    ManualClock &clock_;
    std::atomic<int> slowCycles_{0};
    std::atomic<double> largestCommand_{0.0};
};

struct PressRun {
    glm::dvec3 force{};
    hal::Vec3 hand{};
    HapticStats stats;
};

/// The paper's Fig. 12 set-up on a static surface: the simulated hand presses a point of a flat
/// surface at z = −10 mm with 2 N.
PressRun runStaticPress(const std::string &forceLog)
{
    Rig rig;
    auto sim = makeSim(rig.clock(), "intent=press,force=2,x=0.005,y=-0.004,z=0.02");
    rig.publishFlat(-0.01);
    HapticTaskConfig c = Rig::baseConfig();
    c.forceLogPath = forceLog;
    rig.start(*sim, c);
    rig.runMs(1500);
    PressRun run;
    run.force = rig.task().lastForce();
    run.hand = sim->position();
    rig.finish();
    run.stats = rig.task().stats();
    return run;
}

TEST(HapticTaskTest, simulatedHandRestsOnAStaticSurfaceWithForceEqualToKTimesPenetration)
{
    char dir[] = "/tmp/dt-haptic-task-XXXXXX";
    ASSERT_NE(mkdtemp(dir), nullptr);
    const std::string log = std::string(dir) + "/force-log.csv";
    const PressRun run = runStaticPress(log);
    // THEN the hand is in contact, pushed back with its own 2 N, and F = k·penetration
    const double surface = test::heightOf(test::nearness16(-0.01));
    const double penetration = surface - run.hand.z;
    EXPECT_GT(penetration, 0.0);
    EXPECT_NEAR(run.force.z, 2.0, 0.02);
    EXPECT_NEAR(run.force.x, 0.0, 0.02);
    EXPECT_NEAR(run.force.y, 0.0, 0.02);
    EXPECT_NEAR(run.force.z, 800.0 * penetration, 0.02);
    EXPECT_GT(run.stats.contactUpdates, 1000u);
    EXPECT_LE(run.stats.maxForce, 8.5);
    EXPECT_EQ(run.stats.safetyReleases, 0u);
    EXPECT_EQ(run.stats.updates, 1500u);
    EXPECT_EQ(run.stats.overruns, 0u);
    EXPECT_EQ(run.stats.telemetryDropped, 0u);
    // AND the energy into the hand at the device's port (haptics/passivity.h): pressing a passive
    // spring the hand gave energy (< 0), at most what the spring holds at rest, ½·k·penetration²
    // (less where the enable ramp's gain was under 1), and got little back at any time
    EXPECT_LT(run.stats.energy, 0.0);
    EXPECT_GE(run.stats.energy, -0.5 * 800.0 * penetration * penetration * 1.01);
    EXPECT_LT(run.stats.energyPeak, 1e-4);
    // AND the force log has the docs/architecture.md §4 header and one row per rendered update
    std::ifstream in(log);
    std::string line;
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_EQ(line,
              "t,hip_x,hip_y,hip_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,contact,released,play_t,gain");
    std::size_t rows = 0;
    double lastPlayT = -1.0;
    double lastGain = -1.0;
    while (std::getline(in, line)) {
        ++rows;
        // play_t, column 13, counts the updates' wake-ups from the first: 1 ms apart here
        const std::size_t gainComma = line.rfind(',');
        const std::size_t playComma = line.rfind(',', gainComma - 1);
        const double playT = std::stod(line.substr(playComma + 1, gainComma - playComma - 1));
        EXPECT_GT(playT, lastPlayT);
        lastPlayT = playT;
        // gain, the last column: the output ramp's factor, in [0, 1], never falling in a steady
        // press (no trip, no pause)
        const double gain = std::stod(line.substr(gainComma + 1));
        EXPECT_GE(gain, 0.0);
        EXPECT_LE(gain, 1.0);
        EXPECT_GE(gain, lastGain);
        lastGain = gain;
    }
    EXPECT_NEAR(lastPlayT, 1.499, 0.002);
    EXPECT_DOUBLE_EQ(lastGain, 1.0); // the force the log shows is the whole force
    EXPECT_EQ(rows, run.stats.renderedUpdates);
    std::remove(log.c_str());
    rmdir(dir);
}

// A force log that cannot be written whole (a full disk: /dev/full) is reported as lost output,
// and one that was written is not.
TEST(HapticTaskTest, aForceLogThatCannotBeWrittenIsReportedLost)
{
    EXPECT_TRUE(runStaticPress("/dev/full").stats.forceLogLost);
    char dir[] = "/tmp/dt-haptic-task-XXXXXX";
    ASSERT_NE(mkdtemp(dir), nullptr);
    const std::string log = std::string(dir) + "/force-log.csv";
    EXPECT_FALSE(runStaticPress(log).stats.forceLogLost);
    std::remove(log.c_str());
    rmdir(dir);
}

TEST(HapticTaskTest, closedLoopRunIsDeterministicUnderTheManualClock)
{
    const PressRun a = runStaticPress("");
    const PressRun b = runStaticPress("");
    EXPECT_EQ(a.force.x, b.force.x);
    EXPECT_EQ(a.force.y, b.force.y);
    EXPECT_EQ(a.force.z, b.force.z);
    EXPECT_EQ(a.hand.x, b.hand.x);
    EXPECT_EQ(a.hand.y, b.hand.y);
    EXPECT_EQ(a.hand.z, b.hand.z);
    EXPECT_EQ(a.stats.contactUpdates, b.stats.contactUpdates);
}

TEST(HapticTaskTest, simulatedHandFollowsAMovingSurface)
{
    // GIVEN a 30 fps depth video of a flat surface moving up and down 4 mm at 1 Hz, published by
    // this thread as the decoder does (pair (i, i+1) from the time of frame i)
    Rig rig;
    auto sim = makeSim(rig.clock(), "intent=press,force=2,z=0.02");
    const auto surfaceAt = [](double t) { return -0.01 + 0.004 * std::sin(2.0 * M_PI * t); };
    constexpr double kFps = 30.0;
    const auto pushFrame = [&](int i) {
        Frame16 f(kW, kH, i / kFps);
        f.fillFlat(surfaceAt(i / kFps));
        ASSERT_TRUE(rig.handoff().push(f.view()));
    };
    pushFrame(0);
    pushFrame(1);
    rig.start(*sim, Rig::baseConfig());
    int nextFrame = 2;
    double worstFollow = 0.0;
    double minForce = 1e9;
    double maxForce = 0.0;
    for (int ms = 1; ms <= 3000; ++ms) {
        const double t = ms * 1e-3;
        // Frame i+1 goes out when frame i is on screen.
        while ((nextFrame - 1) / kFps <= t + 1e-9)
            pushFrame(nextFrame++);
        rig.clock().advance(1ms);
        if (ms >= 1000 && ms % 5 == 0) {
            // THEN the hand rides the surface, 2 N / k below it, and the force stays near 2 N
            const double f = rig.task().lastForce().z;
            const double expected = surfaceAt(t) - 2.0 / 800.0;
            worstFollow = std::max(worstFollow, std::fabs(sim->position().z - expected));
            minForce = std::min(minForce, f);
            maxForce = std::max(maxForce, f);
        }
    }
    rig.finish();
    EXPECT_LT(worstFollow, 0.001);
    EXPECT_GT(minForce, 1.5);
    EXPECT_LT(maxForce, 2.5);
    const HapticStats s = rig.task().stats();
    EXPECT_EQ(s.safetyReleases, 0u);
    EXPECT_GT(s.contactUpdates, 2500u);
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

TEST(HapticTaskTest, missedDeadlinesZeroTheForceAndItRampsBack)
{
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock());
    SlowDevice slow(mock, rig.clock());
    HapticTaskConfig c = Rig::baseConfig();
    c.watchdogMissedDeadlines = 5;
    startPressingFlat(rig, mock, slow, c);
    ASSERT_NEAR(rig.task().lastForce().z, 4.0, 0.01);
    const HapticStats before = rig.task().stats();
    const platform::TimePoint from = rig.clock().now();
    // WHEN ten updates in a row take three periods each
    slow.makeSlow(10);
    rig.runMs(1);
    // THEN the watchdog commanded zero force
    EXPECT_EQ(rig.task().lastForce().z, 0.0);
    EXPECT_EQ(mock.lastForce(), hal::Vec3{});
    HapticStats s = rig.task().stats();
    EXPECT_EQ(s.watchdogTrips, 1u);
    EXPECT_GE(s.overruns, 10u);
    EXPECT_GE(s.missedPeriods, 20u);
    // AND once the deadlines are kept the force comes back over as long as it was gone (the ten
    // updates took 30 ms), not over the 100 ms enable ramp (smoothstep(0.35) of 4 N = 1.1 N)
    const double gone = platform::toSeconds(rig.clock().now() - from);
    ASSERT_GT(gone, 0.029);
    rig.runMs(10);
    const double early = rig.task().lastForce().z;
    EXPECT_GT(early, 0.0);
    EXPECT_LT(early, 4.0 * 0.75); // smoothstep(10 / 30) = 0.26 of it
    rig.runMs(25);
    EXPECT_NEAR(rig.task().lastForce().z, 4.0, 0.01);
    rig.runMs(135);
    EXPECT_NEAR(rig.task().lastForce().z, 4.0, 0.01);
    // AND every 1 ms period since was an update or a missed deadline: none lost, none counted
    // twice (the accounting a real-time run can only check within its wake-ups' lateness)
    s = rig.task().stats();
    const auto periods = static_cast<std::uint64_t>(
        std::llround(platform::toSeconds(rig.clock().now() - from) * 1000.0));
    EXPECT_EQ((s.updates - before.updates) + (s.missedPeriods - before.missedPeriods), periods);
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

// What a viewer feels of a stall: the simulated hand presses a flat surface with 3 N and the
// haptic thread loses 10 ms (three updates of three periods). The force comes back over those
// 10 ms; with the 250 ms enable ramp the hand, still pushing, sank about 20 mm through the surface
// before the force held it again.
TEST(HapticTaskTest, aHandPressingThroughAShortStallSinksLittleFurther)
{
    Rig rig;
    auto sim = makeSim(rig.clock(), "intent=press,force=3,x=0.005,y=-0.004,z=0.02");
    SlowDevice slow(*sim, rig.clock());
    rig.publishFlat(-0.01);
    HapticTaskConfig c = Rig::baseConfig();
    c.rampTime = 0.25; // the product's default
    const double k = c.renderer.stiffness;
    rig.start(slow, c);
    rig.runMs(1500);
    const double resting = -0.01 - sim->position().z;
    ASSERT_NEAR(resting, 3.0 / k, 0.5e-3); // F = k·depth
    // WHEN three updates in a row take three periods each
    slow.makeSlow(3);
    rig.runMs(1);
    ASSERT_EQ(rig.task().stats().watchdogTrips, 1u);
    double deepest = 0.0;
    for (int i = 0; i < 400; ++i) {
        rig.runMs(1);
        deepest = std::max(deepest, -0.01 - sim->position().z);
    }
    // THEN the hand sinks at most a millimetre and a half further, and rests again at 3 N
    EXPECT_LT(deepest, resting + 1.5e-3);
    EXPECT_NEAR(glm::length(rig.task().lastForce()), 3.0, 0.1);
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

// A stall in the middle of the enable ramp (the viewer just switched haptics on) gives back the
// force the ramp had reached, quickly, and the rest of the ramp goes on at its own pace: the fast
// resumption never makes the enable ramp shorter.
TEST(HapticTaskTest, aStallDuringTheEnableRampResumesOnlyToWhereTheRampWas)
{
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock());
    SlowDevice slow(mock, rig.clock());
    HapticTaskConfig c = Rig::baseConfig(); // rampTime 100 ms
    c.watchdogMissedDeadlines = 5;
    startPressingFlat(rig, mock, slow, c);
    ASSERT_NEAR(rig.task().lastForce().z, 4.0, 0.01);
    rig.task().setEnabled(false);
    rig.runMs(110);
    ASSERT_EQ(rig.task().lastForce().z, 0.0);
    rig.task().setEnabled(true);
    rig.runMs(30); // phase 0.3: smoothstep 0.216 of 4 N
    const double reached = rig.task().lastForce().z;
    ASSERT_NEAR(reached, 4.0 * 0.216, 0.05);
    // WHEN three updates in a row take three periods each (nine deadlines missed)
    slow.makeSlow(3);
    rig.runMs(1);
    ASSERT_EQ(rig.task().stats().watchdogTrips, 1u);
    ASSERT_EQ(rig.task().lastForce().z, 0.0);
    // THEN about 10 ms later the force is back near where the ramp was, and 20 ms later it has
    // gone on at the enable ramp's pace (phase 0.5: 2 N), not to the full 4 N
    rig.runMs(12);
    EXPECT_GT(rig.task().lastForce().z, reached);
    EXPECT_LT(rig.task().lastForce().z, 4.0 * 0.42);
    rig.runMs(20);
    EXPECT_GT(rig.task().lastForce().z, 4.0 * 0.3);
    EXPECT_LT(rig.task().lastForce().z, 4.0 * 0.7);
    rig.runMs(80);
    EXPECT_NEAR(rig.task().lastForce().z, 4.0, 0.01);
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

/// The time of a process that can be stopped: a ManualClock (Blocking) seen through an offset that
/// stopFor() moves, so a thread asleep wakes as late as the stop lasted, as after SIGSTOP and
/// SIGCONT (ManualClock::advance() alone wakes every sleeper at its own deadline).
class StoppableClock final : public platform::Clock {
public:
    explicit StoppableClock(ManualClock &inner) : inner_(inner) {}
    [[nodiscard]] platform::TimePoint now() const noexcept override
    {
        return inner_.now() + platform::Duration(offsetNs_.load());
    }
    bool sleepUntil(platform::TimePoint deadline) noexcept override
    {
        return inner_.sleepUntil(deadline - platform::Duration(offsetNs_.load()));
    }
    /// The process is stopped for \a d: the time jumps by \a d for every sleeper at once.
    void stopFor(platform::Duration d) { offsetNs_.fetch_add(d.count()); }

private:
    ManualClock &inner_;
    std::atomic<std::int64_t> offsetNs_{0};
};

TEST(HapticTaskTest, aWakeUpSecondsLateCommandsNoForce)
{
    // GIVEN a task pressing a flat surface with 4 N at 1 kHz
    ManualClock manual(ManualClock::Mode::Blocking, platform::TimePoint(10s));
    StoppableClock clock(manual);
    auto handoff = DepthHandoff::create(kW, kH, scene::SampleFormat::Gray16);
    ASSERT_TRUE(handoff);
    drivers::MockHapticDevice mock(clock);
    SlowDevice device(mock, manual);
    pressScript(mock, clock.now());
    Frame16 flat(kW, kH, 0.0);
    flat.fillFlat(0.0);
    ASSERT_TRUE((*handoff)->push(flat.view()));
    (*handoff)->setMediaOrigin(clock.now());
    auto task = HapticTask::create(Rig::baseConfig(), device, **handoff, clock);
    ASSERT_TRUE(task);
    ASSERT_TRUE((*task)->start());
    ASSERT_TRUE(manual.waitForSleepers(1));
    for (int i = 0; i < 300; ++i)
        manual.advance(1ms);
    ASSERT_NEAR((*task)->lastForce().z, 4.0, 0.01);
    // WHEN the process is stopped for 3 s while the haptic thread sleeps (SIGSTOP, then SIGCONT):
    // it wakes 3 s after its deadline, without an overrun
    device.markCommands();
    clock.stopFor(3s);
    manual.advance(1ms);
    // THEN no update after the wake-up commands a force (the first one commanded 3-4 N before; the
    // watchdog zeroed the force only at the next), and the watchdog counts one trip
    EXPECT_EQ(device.largestCommand(), 0.0);
    EXPECT_EQ((*task)->stats().watchdogTrips, 1u);
    // AND the force ramps back once the deadlines are kept, over rampTime (100 ms), not over the
    // 3 s it was gone nor faster: at 20 ms it is smoothstep(0.2) of 4 N = 0.42 N
    for (int i = 0; i < 20; ++i)
        manual.advance(1ms);
    EXPECT_GT((*task)->lastForce().z, 0.2);
    EXPECT_LT((*task)->lastForce().z, 1.0);
    for (int i = 0; i < 180; ++i)
        manual.advance(1ms);
    EXPECT_NEAR((*task)->lastForce().z, 4.0, 0.01);
    (*task)->requestStop();
    manual.release();
    (*task)->stop();
}

TEST(HapticTaskTest, statsGiveTheLongestDeviceCall)
{
    // GIVEN a task pressing a flat surface through a device whose calls take no simulated time
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock());
    SlowDevice slow(mock, rig.clock());
    startPressingFlat(rig, mock, slow);
    EXPECT_EQ(rig.task().stats().deviceCallMaxUs, 0.0);
    // WHEN one read takes 3 ms
    slow.makeSlow(1);
    rig.runMs(10);
    // THEN the stats give that call as the longest, in the JSON too (bench rt prints it)
    const HapticStats s = rig.task().stats();
    EXPECT_DOUBLE_EQ(s.deviceCallMaxUs, 3000.0);
    EXPECT_NE(s.toJson().find("\"device_call_max_us\": 3000"), std::string::npos) << s.toJson();
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

/// A device whose every read writes to a page of memory it never touched before: one page fault
/// (minor: an anonymous page, no I/O) on the haptic thread per update. Delegates everything else.
class FaultingDevice final : public test::DelegatingDevice {
public:
    explicit FaultingDevice(hal::HapticDevice &inner) : DelegatingDevice(inner)
    {
        void *m = mmap(nullptr, kPages * kPage, PROT_READ | PROT_WRITE,
                       MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
        if (m != MAP_FAILED) {
            pages_ = static_cast<volatile unsigned char *>(m);
            // One fault per page: no transparent huge page may bring 512 pages in at once.
            (void)madvise(m, kPages * kPage, MADV_NOHUGEPAGE);
        }
    }
    ~FaultingDevice() override
    {
        if (pages_ != nullptr)
            munmap(const_cast<unsigned char *>(pages_), kPages * kPage);
    }
    FaultingDevice(const FaultingDevice &) = delete;
    FaultingDevice &operator=(const FaultingDevice &) = delete;
    Result<void> read(hal::HapticState &out) noexcept override
    {
        const std::uint64_t n = reads_.fetch_add(1);
        if (pages_ != nullptr && n < kPages)
            pages_[n * kPage] = 1;
        return DelegatingDevice::read(out);
    }

    [[nodiscard]] bool mapped() const { return pages_ != nullptr; }
    [[nodiscard]] std::uint64_t reads() const { return reads_.load(); }

private:
    static constexpr std::size_t kPage = 4096;
    static constexpr std::uint64_t kPages = 1024;
    volatile unsigned char *pages_ = nullptr;
    std::atomic<std::uint64_t> reads_{0};
};

TEST(HapticTaskTest, pageFaultsAfterTheWarmupAreReadEvery256Updates)
{
    // GIVEN a task (memory not locked) on a device that takes one new page fault in every read
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock());
    FaultingDevice faulting(mock);
    ASSERT_TRUE(faulting.mapped());
    pressScript(mock, rig.clock().now());
    rig.publishFlat(0.0);
    rig.start(faulting, Rig::baseConfig());
    // WHEN 255 updates have run
    rig.runMs(255);
    ASSERT_EQ(faulting.reads(), 255u);
    // THEN no count was read yet (HapticStats: the thread reads its faults every 256 updates)
    EXPECT_EQ(rig.task().stats().pageFaultsMinor, 0u);
    // WHEN the 256th update has run
    rig.runMs(1);
    ASSERT_EQ(faulting.reads(), 256u);
    // THEN the count covers every update after the warm-up: at least one fault in each of
    // updates kWarmupUpdates + 1 .. 256
    const std::uint64_t at256 = rig.task().stats().pageFaultsMinor;
    EXPECT_GE(at256, 256u - HapticTask::kWarmupUpdates);
    // AND it is not read again until the 512th update, then with the faults since
    rig.runMs(255);
    EXPECT_EQ(rig.task().stats().pageFaultsMinor, at256);
    rig.runMs(1);
    ASSERT_EQ(faulting.reads(), 512u);
    EXPECT_GE(rig.task().stats().pageFaultsMinor, at256 + 256u);
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

/// Presses 5 mm into a flat surface, then restarts the media clock onto the same content (a loop
/// or a seek) with \a clockRestart, or re-seats (\a clockRestart false, the old seek handling);
/// \return the smallest force over the 200 ms after it, N.
double forceAfterLoop(bool clockRestart)
{
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock());
    startPressingFlat(rig, mock, mock);
    EXPECT_NEAR(rig.task().lastForce().z, 4.0, 0.01);
    // WHEN the clip loops: the same first frame again, the media time back to zero
    rig.handoff().setMediaOrigin(rig.clock().now());
    rig.publishFlat(0.0);
    if (clockRestart)
        rig.task().requestClockRestart();
    else
        rig.task().requestReseat();
    double least = 1e9;
    for (int i = 0; i < 200; ++i) {
        rig.runMs(1);
        least = std::min(least, rig.task().lastForce().z);
    }
    rig.finish();
    return least;
}

TEST(HapticTaskTest, loopOntoContinuousContentKeepsTheSupport)
{
    // THEN the finger stays supported: the force never falls under half of the 4 N it was
    const double kept = forceAfterLoop(true);
    EXPECT_GT(kept, 2.0);
    // (the re-seat, which a loop used to do, ramps the force in from zero)
    const double reseated = forceAfterLoop(false);
    EXPECT_LT(reseated, 1.0);
    std::printf("least force after a loop: %.2f N kept, %.2f N re-seated\n", kept, reseated);
}

TEST(HapticTaskTest, unplugZeroesTheForceAtOnceAndReconnectResumesWithTheRamp)
{
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock());
    startPressingFlat(rig, mock, mock);
    ASSERT_NEAR(mock.lastForce().z, 4.0, 0.01);
    ASSERT_TRUE(rig.task().deviceConnected());
    // WHEN the device is unplugged mid-play
    mock.disconnect();
    rig.runMs(1);
    // THEN zero force on the very next update, and the task keeps running without it
    EXPECT_EQ(rig.task().lastForce().z, 0.0);
    EXPECT_EQ(mock.lastForce(), hal::Vec3{});
    EXPECT_FALSE(rig.task().deviceConnected());
    const std::uint64_t before = rig.task().updates();
    rig.runMs(50);
    EXPECT_EQ(rig.task().updates(), before + 50);
    EXPECT_EQ(rig.task().lastForce().z, 0.0);
    // WHEN it comes back  THEN the telemetry thread reopens it and the force ramps in
    mock.reconnect();
    rig.runUntil([&] { return rig.task().deviceConnected(); });
    rig.runMs(2);
    const double first = rig.task().lastForce().z;
    EXPECT_GT(first, 0.0);
    EXPECT_LT(first, 0.1);
    rig.runMs(150);
    EXPECT_NEAR(mock.lastForce().z, 4.0, 0.01);
    const HapticStats s = rig.task().stats();
    EXPECT_EQ(s.deviceLosses, 1u);
    EXPECT_EQ(s.reconnects, 1u);
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

TEST(HapticTaskTest, everyLossOfTheDeviceIsLoggedOnce)
{
    // GIVEN a log sink counting the warnings an operator reads
    static std::atomic<int> lostLines{0};
    lostLines = 0;
    platform::setLogSink(
        [](void *, platform::LogLevel level, const char *, const char *message) {
            if (level == platform::LogLevel::Warning &&
                std::string(message).find("Haptic device lost") != std::string::npos)
                ++lostLines;
        },
        nullptr);
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock());
    startPressingFlat(rig, mock, mock);
    // WHEN the device is unplugged and comes back, twice: the second time at once after it came
    // back, before the service thread's next look finds it in use (as a loaded machine delays it)
    for (int i = 0; i < 2; ++i) {
        mock.disconnect();
        rig.runMs(50);
        mock.reconnect();
        rig.runUntil([&] { return rig.task().deviceConnected(); });
    }
    rig.runMs(20);
    const HapticStats s = rig.task().stats();
    rig.finish();
    platform::setLogSink(nullptr, nullptr);
    // THEN each loss was said once (not once a telemetry interval, nor only the first)
    EXPECT_EQ(s.deviceLosses, 2u);
    EXPECT_EQ(s.reconnects, 2u);
    EXPECT_EQ(lostLines.load(), 2);
}

TEST(HapticTaskTest, deviceThatStopsAnsweringTripsTheWatchdog)
{
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock());
    HapticTaskConfig c = Rig::baseConfig();
    c.watchdogDeviceTimeouts = 5;
    startPressingFlat(rig, mock, mock, c);
    mock.setStalled(true);
    rig.runMs(5);
    EXPECT_NEAR(rig.task().lastForce().z, 4.0, 0.01) << "a few time-outs are tolerated";
    rig.runMs(1);
    EXPECT_EQ(rig.task().lastForce().z, 0.0);
    EXPECT_EQ(rig.task().stats().watchdogTrips, 1u);
    mock.setStalled(false);
    rig.runMs(150);
    EXPECT_NEAR(rig.task().lastForce().z, 4.0, 0.01);
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

TEST(HapticTaskTest, disableAndEnableRampTheForceSmoothly)
{
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock());
    startPressingFlat(rig, mock, mock); // ramp 100 ms = 100 updates
    const double full = rig.task().lastForce().z;
    ASSERT_NEAR(full, 4.0, 0.01);
    for (const bool enable : {false, true}) {
        rig.task().setEnabled(enable);
        std::vector<double> f;
        for (int i = 0; i < 110; ++i) {
            rig.runMs(1);
            f.push_back(rig.task().lastForce().z);
        }
        // THEN a monotonic smoothstep: slow start, half way at 50 updates, done at 100
        for (std::size_t i = 1; i < f.size(); ++i) {
            if (enable) {
                EXPECT_GE(f[i], f[i - 1] - 1e-12) << i;
            } else {
                EXPECT_LE(f[i], f[i - 1] + 1e-12) << i;
            }
        }
        const double firstStep = std::fabs(f[0] - (enable ? 0.0 : full));
        EXPECT_LT(firstStep, 0.1 * full / 100.0) << "the ramp starts with zero slope";
        EXPECT_NEAR(f[49], 0.5 * full, 0.01 * full);
        EXPECT_NEAR(f[99], enable ? full : 0.0, 1e-9);
        EXPECT_NEAR(rig.task().gain(), enable ? 1.0 : 0.0, 1e-12);
    }
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

// The renderer's let-go at the device maximum watches the force sent, after the task's gain: a hand
// that sinks 12 mm into the surface while the force is off (disabled, or the watchdog's zero) is
// held, not let go for a command the device was never sent (it would fall through the surface as
// the force came back); once the ramp brings the force sent to the maximum, it is let go.
TEST(HapticTaskTest, theLetGoAtTheDeviceMaximumWatchesTheForceSent)
{
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock());
    startPressingFlat(rig, mock, mock); // 5 mm, 4 N
    ASSERT_NEAR(rig.task().lastForce().z, 4.0, 0.01);
    rig.task().setEnabled(false);
    rig.runMs(110); // the ramp (100 ms) to zero force
    const platform::TimePoint now = rig.clock().now();
    mock.setWaypoints({{now, {0.0, 0.0, -0.005}, 0}, {now + 70ms, {0.0, 0.0, -0.012}, 0}});
    const std::uint64_t before = rig.task().stats().safetyReleases;
    rig.runMs(200); // k·12 mm = 9.6 N: the renderer's command at the 8.5 N maximum, none sent
    EXPECT_EQ(rig.task().lastForce().z, 0.0);
    EXPECT_EQ(rig.task().stats().safetyReleases, before);
    rig.task().setEnabled(true);
    rig.runMs(90); // the ramp part-way: the force sent rises toward the maximum
    EXPECT_GT(rig.task().lastForce().z, 4.0);
    EXPECT_EQ(rig.task().stats().safetyReleases, before);
    rig.runMs(30); // at the maximum for more than kFingerSaturationTime: let go
    EXPECT_GT(rig.task().stats().safetyReleases, before);
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

TEST(HapticTaskTest, forceRateIsLimitedAndForceIsClampedToTheDeviceMaximum)
{
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock()); // maximum 8.5 N
    // HIP jumps 30 mm into the surface: 24 N unclamped.
    pressScript(mock, rig.clock().now(), 0.03);
    rig.publishFlat(0.0);
    HapticTaskConfig c = Rig::baseConfig();
    c.renderer.safety = false; // the jump would trip force-jump safety (IV.C)
    c.renderer.maxForce = 20.0;
    c.maxForceRate = 100.0; // N/s: 0.1 N per update
    rig.start(mock, c);
    std::vector<double> f;
    for (int i = 0; i < 200; ++i) {
        rig.runMs(1);
        f.push_back(hal::norm(mock.lastForce()));
    }
    double largestStep = 0.0;
    for (std::size_t i = 1; i < f.size(); ++i)
        largestStep = std::max(std::fabs(f[i] - f[i - 1]), largestStep);
    EXPECT_LE(largestStep, 0.1 + 1e-9);
    EXPECT_GT(largestStep, 0.09) << "the limit was reached";
    EXPECT_NEAR(f.back(), 8.5, 1e-9) << "clamped to the device maximum";
    EXPECT_LE(rig.task().stats().maxForce, 8.5 + 1e-9);
    EXPECT_EQ(mock.clampCount(), 0u) << "the task clamps before the device has to";
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

HapticTask *gSignalTask = nullptr;
void onSignal(int)
{
    gSignalTask->requestStop();
}

TEST(HapticTaskTest, signalHandlerStopsTheTaskWithZeroForce)
{
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock());
    startPressingFlat(rig, mock, mock);
    ASSERT_NEAR(mock.lastForce().z, 4.0, 0.01);
    gSignalTask = &rig.task();
    struct sigaction sa = {};
    struct sigaction old = {};
    sa.sa_handler = &onSignal;
    ASSERT_EQ(sigaction(SIGUSR1, &sa, &old), 0);
    ASSERT_EQ(raise(SIGUSR1), 0);
    sigaction(SIGUSR1, &old, nullptr);
    EXPECT_TRUE(rig.task().stopRequested());
    // THEN at its next wake-up the loop commands zero force and returns, before finish() (whose
    // stop() would zero the force itself): the device outputs nothing, the loop no longer sleeps
    // on the clock, and further periods run no update
    rig.runMs(1);
    EXPECT_EQ(mock.lastForce(), hal::Vec3{});
    EXPECT_EQ(rig.task().lastForce(), glm::dvec3{});
    EXPECT_EQ(rig.clock().sleepers(), 0) << "the haptic loop is still waiting for its next period";
    const std::uint64_t updates = rig.task().updates();
    rig.runMs(5);
    EXPECT_EQ(rig.task().updates(), updates);
    rig.finish();
    EXPECT_EQ(mock.lastForce(), hal::Vec3{});
    EXPECT_TRUE(mock.isConnected()) << "stop() leaves the device open";
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

TEST(HapticTaskTest, devicePresentLaterIsPickedUp)
{
    // GIVEN a device absent at start  THEN start() succeeds and the task polls for it
    Rig rig;
    drivers::MockHapticDevice mock(rig.clock());
    pressScript(mock, rig.clock().now());
    mock.disconnect();
    rig.publishFlat(0.0);
    rig.start(mock, Rig::baseConfig());
    rig.runMs(10);
    EXPECT_FALSE(rig.task().deviceConnected());
    mock.reconnect();
    rig.runUntil([&] { return rig.task().deviceConnected(); });
    rig.runMs(300);
    EXPECT_NEAR(mock.lastForce().z, 4.0, 0.01);
    rig.finish(); // the haptic thread stops before the devices declared after the rig go
}

TEST(HapticTaskTest, badConfigIsRejected)
{
    platform::ManualClock clock;
    drivers::MockHapticDevice mock(clock);
    auto handoff = DepthHandoff::create(kW, kH, scene::SampleFormat::Gray16);
    ASSERT_TRUE(handoff);
    const auto rejects = [&](auto change) {
        HapticTaskConfig c = Rig::baseConfig();
        change(c);
        auto t = HapticTask::create(c, mock, **handoff, clock);
        return !t && t.error().code == Errc::InvalidArgument;
    };
    EXPECT_TRUE(rejects([](HapticTaskConfig &c) { c.servoRateHz = 50.0; }));
    EXPECT_TRUE(rejects([](HapticTaskConfig &c) { c.servoRateHz = 20000.0; }));
    EXPECT_TRUE(rejects([](HapticTaskConfig &c) { c.maxForceRate = 0.0; }));
    EXPECT_TRUE(rejects([](HapticTaskConfig &c) { c.mapping.scale = -1.0; }));
    EXPECT_TRUE(rejects([](HapticTaskConfig &c) { c.watchdogMissedDeadlines = 0; }));
    EXPECT_TRUE(rejects([](HapticTaskConfig &c) { c.rampTime = 0.0; }));
    EXPECT_TRUE(rejects([](HapticTaskConfig &c) { c.renderer.stiffness = -5.0; }));
    EXPECT_FALSE(rejects([](HapticTaskConfig &c) { c.servoRateHz = 4000.0; }));
}

} // namespace
} // namespace depthtouch::haptic_task
