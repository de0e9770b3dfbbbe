#pragma once
/// \file
/// \brief HapticTask: the real-time haptic servo loop of the receiver (docs/architecture.md §1,
/// §5): a SCHED_FIFO thread that reads the haptic device, maps its position into the scene box,
/// runs the modified proxy graph renderer (paper IV) against the depth frames of a DepthHandoff,
/// clamps and rate-limits the force, commands it and pushes one telemetry sample per update; plus
/// the non-real-time telemetry thread (force log CSV, counters, percentiles) and the device
/// watchdog with hot-plug recovery.
///
/// Units and frames: docs/architecture.md §3 (metres, seconds, newtons; scene box x right, y up, z
/// toward the viewer). The device frame has the same axes (hal/haptic_device.h); the mapping is
/// `HIP = scale·p_device + offset`, and the force is sent to the device unchanged (newtons).

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>

#include <glm/vec3.hpp>

#include "depthtouch/hal/haptic_device.h"
#include "depthtouch/haptic_task/depth_handoff.h"
#include "depthtouch/haptic_task/latency_histogram.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/periodic_timer.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/platform/seqlock.h"
#include "depthtouch/platform/spsc_ring.h"

namespace depthtouch::haptic_task {

/// \brief Device frame → scene-box frame: `HIP = scale·p_device + offset`.
struct DeviceMapping {
    double scale = 1.0;  ///< Scene metres per device metre (> 0).
    glm::dvec3 offset{}; ///< Scene position of the device origin, m.
    /// Device button (bit index) that clutches: while it is held the HIP stays where it was and the
    /// force goes to zero; on release the offset changes so the HIP continues from there, which
    /// re-centres the handle in its workspace. −1: no clutch.
    int clutchButton = -1;
};

/// \brief Parameters of the haptic task. Defaults are the player's.
struct HapticTaskConfig {
    double servoRateHz = 1000.0; ///< Updates per second, 100 .. 10000 (4 kHz and more supported).
    /// Renderer: method and parameters (stiffness N/m, damping N·s/m, maxForce N, scene box, fixes
    /// of paper IV, static and dynamic friction on the proxy), handed to the renderer as given.
    /// The renderer's maxForce is lowered to the device's maximum when that is less.
    haptics::Method method = haptics::Method::Finger;
    haptics::RendererConfig renderer = haptics::RendererConfig::forMethod(haptics::Method::Finger);
    /// Force rate limit, N/s (> 0): the commanded force moves by at most maxForceRate·Δt per
    /// update. Safety zeroing (watchdog, unplug, stop) is not rate-limited. Default: 0 → 8.5 N
    /// in 4.25 ms.
    double maxForceRate = 2000.0;
    DeviceMapping mapping{};
    /// Watchdog: more than this many consecutive missed deadlines (overruns, counting the periods
    /// skipped by the re-sync) command zero force at once; the force then ramps back in (rampTime)
    /// while the loop keeps its deadlines. ≥ 1.
    int watchdogMissedDeadlines = 5;
    /// Watchdog: more than this many consecutive device time-outs (Errc::Timeout) command zero
    /// force; it ramps back in once the device answers. ≥ 1.
    int watchdogDeviceTimeouts = 5;
    /// Duration of the smooth force ramp of setEnabled() and of every resumption (watchdog,
    /// reconnect), s (> 0). The gain follows smoothstep(phase), phase moving linearly.
    double rampTime = 0.25;
    bool startEnabled = true; ///< Haptics on at start (else setEnabled(true) ramps them in).

    /// \name The haptic thread
    ///@{
    /// SCHED_FIFO (the default: the highest priority of the table, kHapticThread) or SCHED_OTHER
    /// (for comparison in `depthtouch bench rt`).
    platform::SchedPolicy policy = platform::SchedPolicy::Fifo;
    bool requireRt = false; ///< Fail start() when SCHED_FIFO or the memory lock is refused.
    /// Keep the haptic path resident before the thread starts (RealtimeThread, memoryLock).
    bool lockMemory = true;
    /// How: Owned (the default) mlock()s the haptic thread's stack, the task, its telemetry ring,
    /// the renderer, the device object, the hand-off and its pixels, and the code of the program,
    /// the C/C++ runtime and libusb (docs/memory.md); All is mlockall(MCL_CURRENT), the behaviour
    /// before issue #21 (for `bench rt`).
    platform::MemoryLockMode memoryLock = platform::MemoryLockMode::Owned;
    int cpu = -1;           ///< CPU to pin the haptic thread to, −1: none.
    /// Instrumentation: called on the haptic thread once, before its first update (e.g. a debug
    /// hook that makes malloc fail loudly on that thread, docs/style.md §4.7). Must be real-time
    /// safe.
    void (*threadHook)(void *user) = nullptr;
    void *threadHookUser = nullptr;
    ///@}

    /// \name The telemetry thread (SCHED_OTHER, kTelemetryThread; not real-time)
    ///@{
    /// Force log CSV (docs/architecture.md §4) written as the telemetry drains; empty: none.
    std::string forceLogPath;
    /// How often the telemetry thread drains the ring and checks the device, ms (1 .. 1000).
    int telemetryIntervalMs = 5;
    /// How often a lost device is closed and opened again, ms (≥ 1).
    int reconnectIntervalMs = 100;
    ///@}

    /// \return Errc::InvalidArgument with a static message when a value is out of range.
    [[nodiscard]] Result<void> validate() const noexcept;
};

/// \brief One haptic update as pushed into the telemetry ring (no allocation, trivially copyable).
struct TelemetrySample {
    enum Flags : std::uint16_t {
        Rendered = 1u << 0,      ///< Device read and frames present: t, hip, proxy are meaningful.
        Contact = 1u << 1,       ///< Proxy held on the surface.
        Released = 1u << 2,      ///< Renderer force-jump safety released the proxy (paper IV.C).
        Overrun = 1u << 3,       ///< This cycle started late.
        WatchdogTrip = 1u << 4,  ///< The watchdog zeroed the force on this cycle.
        DeviceLost = 1u << 5,    ///< The device is unplugged or being reconnected.
        DeviceTimeout = 1u << 6, ///< The device did not answer this cycle.
        Clutched = 1u << 7,      ///< The clutch button is held.
        NoFrames = 1u << 8,      ///< No depth frame published yet.
    };
    double t = 0.0;                  ///< Haptic time, s (clock time − media origin).
    glm::dvec3 hip{};                ///< HIP, m, scene box.
    glm::dvec3 proxy{};              ///< Proxy after the update, m.
    glm::dvec3 force{};              ///< Force commanded to the device, N.
    std::int64_t wakeNs = 0;         ///< Clock time of the wake-up, ns since the clock's epoch.
    std::int32_t wakeLatencyNs = 0;  ///< Wake time − deadline, ns.
    std::int32_t updateNs = 0;       ///< Time from the wake-up to the command, ns.
    std::uint64_t cycle = 0;         ///< Cycle number, 1-based (gaps: samples lost to a full ring).
    std::uint32_t missedPeriods = 0; ///< Deadlines skipped by an overrun's re-sync.
    float gain = 0.0f;               ///< Enable/ramp gain in [0, 1].
    std::uint16_t flags = 0;
};

/// \brief Counters and percentiles of a run (the haptic part of the stats JSON,
/// docs/architecture.md §4).
struct HapticStats {
    double servoRateHz = 0.0;
    std::uint64_t updates = 0; ///< Cycles of the haptic loop.
    /// Time from the first to the last update drained, s: updates ≈ runSeconds · servoRateHz + 1
    /// when no period was missed.
    double runSeconds = 0.0;
    std::uint64_t renderedUpdates = 0; ///< Cycles that ran the renderer.
    std::uint64_t contactUpdates = 0;  ///< Rendered cycles with the proxy on the surface.
    std::uint64_t overruns = 0;        ///< Cycles that started after their deadline.
    std::uint64_t missedPeriods = 0;   ///< Deadlines skipped by the re-syncs.
    std::uint64_t safetyReleases = 0;  ///< Renderer releases (IV.C) + watchdog trips.
    std::uint64_t watchdogTrips = 0;   ///< Zero-force trips of the watchdog (deadlines, time-outs).
    std::uint64_t deviceLosses = 0;    ///< Times the device disappeared.
    std::uint64_t reconnects = 0;      ///< Times it came back.
    std::uint64_t telemetryDropped = 0; ///< Samples lost to a full ring (not in the percentiles).
    double maxForce = 0.0;              ///< Largest commanded force magnitude, N.
    /// The force log could not be written whole (a write or its close failed: a full disk); the
    /// run's output is lost.
    bool forceLogLost = false;
    double deviceMaxForce = 0.0; ///< The device's maximum, N.
    /// Longest single device call (read() or commandForce()) on the haptic thread, µs: bounded by
    /// every backend whatever its options (docs/devices.md "Time of a device call").
    double deviceCallMaxUs = 0.0;
    LatencySummary wakeLatency; ///< Wake time − deadline.
    LatencySummary updateTime;  ///< Wake-up to force command.
    LatencySummary periodError; ///< |wake_k − wake_{k−1} − period| over on-time pairs.
    std::string thread;         ///< What the haptic thread got (RealtimeThreadReport).
    /// Page faults the haptic thread took after its warm-up (the first kWarmupUpdates updates;
    /// getrusage(RUSAGE_THREAD) read by the thread itself every 256 updates and at its end). With
    /// the memory locked: 0, also under memory pressure.
    std::uint64_t pageFaultsMinor = 0;
    std::uint64_t pageFaultsMajor = 0;  ///< As pageFaultsMinor, faults that needed I/O.
    std::uint64_t pageFaultsWarmup = 0; ///< Minor + major faults of the warm-up.
    double lockedMiB = 0.0; ///< Memory the haptic thread's start locked (Owned mode), MiB.

    /// \return a JSON object: haptic_updates, haptic_run_s, haptic_rate_hz, rendered_updates,
    /// contact_updates, overruns, missed_periods, wake_latency_us / update_time_us /
    /// period_error_us {p50, p90, p99, p999, max, mean}, safety_releases, watchdog_trips,
    /// device_losses, reconnects, telemetry_dropped, max_force_n, device_max_force_n,
    /// device_call_max_us,
    /// force_log_lost, haptic_thread, haptic_page_faults {minor, major, warmup},
    /// haptic_locked_mib.
    [[nodiscard]] std::string toJson(int indent = 2) const;
};

/// \brief The haptic servo loop and its telemetry.
///
/// Per update, on the haptic thread (nothing else): take the newest depth pair from the handoff;
/// read the device; map to the scene; renderer update; gain (enable ramp), clamp to the device
/// maximum, force-rate limit; commandForce(); push one TelemetrySample. It never allocates, locks,
/// logs, writes files or throws after start() (checked by a test that interposes malloc,
/// pthread_mutex_lock and write on that thread). Every buffer is allocated by create().
///
/// Safety: the force is always clamped to min(renderer maxForce, device maxForce) and
/// rate-limited. Zero force, at once: after more than watchdogMissedDeadlines consecutive missed
/// deadlines or a wake-up as late (a process stopped and continued), after more than
/// watchdogDeviceTimeouts consecutive device time-outs, when the device is unplugged
/// (Errc::NoDevice: the task keeps running and its telemetry thread closes and opens the device
/// every reconnectIntervalMs until it answers; haptics then ramp back in), at stop() and after
/// requestStop() (signal-safe, for the stop signals' handlers).
///
/// Thread-safety: create(), start(), stop() and the destructor on one owner thread. requestStop(),
/// setEnabled() and every observer are thread-safe; requestStop() and setEnabled() are also
/// async-signal-safe. The device must not be used by anyone else between start() and stop().
class HapticTask {
public:
    /// Capacity of the telemetry ring: 8 s at 1 kHz, drained every few milliseconds.
    static constexpr std::size_t kTelemetryCapacity = 8192;
    /// Updates of the warm-up: the first pass over the haptic path (lazy symbol bindings resolved,
    /// every buffer touched once) before the page faults are counted (HapticStats).
    static constexpr std::uint64_t kWarmupUpdates = 32;

    /// \brief Validates \a config, creates the renderer for the handoff's frame size and allocates
    /// the telemetry ring. \a device, \a handoff and \a clock must outlive the task.
    /// \return the task, or Errc::InvalidArgument (bad config), Errc::OutOfResources.
    static Result<std::unique_ptr<HapticTask>> create(const HapticTaskConfig &config,
                                                      hal::HapticDevice &device,
                                                      DepthHandoff &handoff,
                                                      platform::Clock &clock);
    /// stop().
    ~HapticTask();

    /// \brief Opens the device if it is Closed (a device that is absent is polled for, not an
    /// error), opens the force log, starts the telemetry thread, then the haptic thread.
    /// \return Errc::InvalidState (started before), Errc::Io (force log), the device's open() error
    /// other than NoDevice, or RealtimeThread::start()'s error (PermissionDenied with requireRt).
    [[nodiscard]] Result<void> start();
    /// \brief Commands zero force, stops and joins both threads, drains the telemetry and closes
    /// the force log. Leaves the device open. Idempotent.
    void stop() noexcept;
    /// \brief Asks the haptic loop to command zero force and return; stop() then joins.
    /// Async-signal-safe (one lock-free atomic store): call it from a SIGINT/SIGTERM handler.
    void requestStop() noexcept;
    /// \return true once requestStop() or stop() was called. Async-signal-safe.
    [[nodiscard]] bool stopRequested() const noexcept
    {
        return stopRequested_.load(std::memory_order_acquire);
    }

    /// \brief Switches haptics on or off at run time; the force ramps over rampTime.
    /// Async-signal-safe.
    void setEnabled(bool enabled) noexcept { enabled_.store(enabled, std::memory_order_release); }
    [[nodiscard]] bool enabled() const noexcept { return enabled_.load(std::memory_order_acquire); }

    /// \brief Changes the surface stiffness at run time, N/m (> 0; other values are ignored).
    /// The haptic thread hands it to the renderer at its next update
    /// (haptics::HapticRenderer::setStiffness()): the renderer's force-jump safety and slew limit
    /// act on the force at the new stiffness, and with the force-rate limit after them a change
    /// is felt within a few milliseconds and never as a step. The damping b stays as configured.
    /// Async-signal-safe.
    void setStiffness(double newtonsPerMetre) noexcept
    {
        if (newtonsPerMetre > 0.0 && newtonsPerMetre < 1e6)
            stiffness_.store(newtonsPerMetre, std::memory_order_release);
    }
    /// \return the stiffness in use, N/m.
    [[nodiscard]] double stiffness() const noexcept
    {
        return stiffness_.load(std::memory_order_acquire);
    }
    /// \brief Re-seats the proxy on the surface above the HIP at the next update and ramps the
    /// force in from zero (rampTime), and restarts the haptic time: for a seek (the media time
    /// jumps, possibly backwards) and for "recenter". No force kick. Async-signal-safe.
    void requestReseat() noexcept { reseatRequests_.fetch_add(1, std::memory_order_acq_rel); }
    /// \brief Restarts the haptic time at the next update (a seek or a loop: the media time jumps,
    /// possibly backwards) and keeps the proxy and the force, so content that continues under the
    /// finger keeps its support; a surface that changed under the proxy is a cut for the renderer's
    /// safety (HapticRenderer::restartClock()). Async-signal-safe.
    void requestClockRestart() noexcept { clockRestarts_.fetch_add(1, std::memory_order_acq_rel); }

    /// \name Observers (thread-safe)
    ///@{
    /// \return cycles of the haptic loop so far.
    [[nodiscard]] std::uint64_t updates() const noexcept
    {
        return updates_.load(std::memory_order_acquire);
    }
    /// \return true while the haptic thread owns a connected device (false while it is lost).
    [[nodiscard]] bool deviceConnected() const noexcept
    {
        return owner_.load(std::memory_order_acquire) == kRtOwns && !deviceFailed_.load();
    }
    /// \return the current ramp gain in [0, 1].
    [[nodiscard]] double gain() const noexcept { return gain_.load(std::memory_order_relaxed); }
    /// \return the last force commanded, N (zero while the device is lost).
    [[nodiscard]] glm::dvec3 lastForce() const noexcept;
    /// \brief The HIP and the proxy of the last rendered update, m, scene box (the avatar the
    /// graphic renderer draws). \return false before the first rendered update.
    bool lastPose(glm::dvec3 &hip, glm::dvec3 &proxy) const noexcept;
    /// \return counters and percentiles of the samples drained so far (drains first).
    [[nodiscard]] HapticStats stats();
    /// \return what the haptic thread obtained from the kernel (valid after start()).
    [[nodiscard]] const platform::RealtimeThreadReport &threadReport() const noexcept;
    ///@}

    /// \brief Drains the telemetry ring now (also done by the telemetry thread). Thread-safe.
    void drainTelemetry();

    [[nodiscard]] const HapticTaskConfig &config() const noexcept { return config_; }

private:
    using Ring = platform::SpscRing<TelemetrySample, kTelemetryCapacity>;
    static constexpr std::uint8_t kRtOwns = 0;   ///< The haptic thread uses the device.
    static constexpr std::uint8_t kLost = 1;     ///< The telemetry thread may close/open it.
    static constexpr std::uint8_t kRestored = 2; ///< Reopened; the haptic thread takes it back.

    HapticTask(const HapticTaskConfig &config, hal::HapticDevice &device, DepthHandoff &handoff,
               platform::Clock &clock, std::unique_ptr<haptics::HapticRenderer> renderer);
    DT_DISABLE_COPY_AND_MOVE(HapticTask)

    /// What the steps of one cycle hand on to each other (on the haptic thread's stack).
    struct CycleContext {
        platform::TimePoint begin; ///< Wake-up time of the cycle.
        TelemetrySample sample;    ///< The cycle's telemetry, pushed by finishCycle().
        bool late = false;         ///< The deadline watchdog holds the force at zero.
    };

    void run(platform::StopToken stop) noexcept;
    /// One cycle after the wait: the steps below, in order. Real-time safe.
    void cycle(const platform::PeriodicWait &wait) noexcept;
    /// \name The steps of cycle() (haptic thread only, real-time safe)
    ///@{
    /// \return the cycle's telemetry sample with its wake-up, latency, overrun and cycle number.
    TelemetrySample beginSample(const platform::PeriodicWait &wait) const noexcept;
    /// \return true when the loop missed more than watchdogMissedDeadlines deadlines in a row, or
    /// woke that late (a stopped process).
    bool watchDeadlines(const platform::PeriodicWait &wait) noexcept;
    /// Hands the newest depth pair of the handoff, if any, to the renderer.
    void takeFrames() noexcept;
    /// Takes a reopened device back. \return false while the device is lost.
    bool ownDevice(TelemetrySample &sample) noexcept;
    /// Keeps the longest device call (HapticStats::deviceCallMaxUs).
    void noteDeviceCall(platform::Duration took) noexcept;
    /// Reads the device; a time-out counts for the device watchdog, any other error loses the
    /// device. \return false when \a state was not read.
    bool readDevice(hal::HapticState &state, TelemetrySample &sample) noexcept;
    /// \return the HIP: the device position mapped to the scene, held while the clutch is.
    glm::dvec3 mapToScene(const hal::HapticState &state, TelemetrySample &sample) noexcept;
    /// Applies the clock restarts and re-seats asked for since the last cycle.
    void applyRestarts() noexcept;
    /// Runs the renderer at \a hip. \return its force at the run-time stiffness, N (zero without
    /// frames).
    glm::dvec3 render(const glm::dvec3 &hip, CycleContext &c) noexcept;
    /// Moves the enable ramp (zero when late). \return the gain in [0, 1].
    double rampGain(CycleContext &c) noexcept;
    /// \return \a target with the gain, zeroed by the clutch or a late loop, clamped to the
    /// maximum and rate-limited.
    glm::dvec3 shapeForce(glm::dvec3 target, double gain, const CycleContext &c) const noexcept;
    /// Commands \a force. \return false when the device was lost.
    bool command(const glm::dvec3 &force, CycleContext &c) noexcept;
    /// Publishes the commanded force and records it in the telemetry and the maximum.
    void recordForce(const glm::dvec3 &force, TelemetrySample &sample) noexcept;
    /// Pushes the telemetry sample and counts the cycle.
    void finishCycle(CycleContext &c) noexcept;
    ///@}
    void zeroForce() noexcept;
    /// Fills lockRegions_ (constructor).
    void collectLockRegions() noexcept;
    /// Stores the haptic thread's page faults since \a since. Real-time safe (one syscall).
    void countFaults(const platform::PageFaults &since) noexcept;
    /// The device went away (NoDevice) or was closed under the task: zero force, count it, and
    /// hand the device to the telemetry thread for reconnection. Real-time safe.
    void loseDevice(TelemetrySample &sample) noexcept;
    void publishForce(const glm::dvec3 &f) noexcept;
    void serviceLoop();
    void superviseDevice();
    void drainLocked();

    const HapticTaskConfig config_;
    hal::HapticDevice &device_;
    DepthHandoff &handoff_;
    platform::Clock &clock_;
    std::unique_ptr<haptics::HapticRenderer> renderer_;
    std::unique_ptr<Ring> ring_;
    std::unique_ptr<platform::RealtimeThread> thread_;
    platform::PeriodicTimer timer_;
    const double maxForce_; ///< min(renderer, device), N.
    const double period_;   ///< s.

    // Shared (atomics).
    std::atomic<bool> stopRequested_{false};
    std::atomic<bool> enabled_{true};
    std::atomic<std::uint8_t> owner_{kRtOwns};
    std::atomic<bool> deviceFailed_{false}; ///< Watchdog holding zero for device time-outs.
    std::atomic<std::uint64_t> updates_{0};
    // Counters written by the haptic thread only (plain load + store), read by anyone.
    std::atomic<std::uint64_t> rendered_{0};
    std::atomic<std::uint64_t> contacts_{0};
    std::atomic<std::uint64_t> releases_{0};
    std::atomic<std::uint64_t> watchdogTrips_{0};
    std::atomic<std::uint64_t> deviceLosses_{0};
    std::atomic<std::uint64_t> reconnects_{0}; ///< Written by the telemetry thread.
    std::atomic<double> maxForceSeen_{0.0};
    std::atomic<std::int64_t> deviceCallMaxNs_{0}; ///< Longest device call, ns.
    std::atomic<double> gain_{0.0};
    platform::SeqLockArray<3> force_; ///< Last commanded force, N (read by lastForce()).
    platform::SeqLockArray<7> pose_;  ///< HIP, proxy (m) and a valid flag (lastPose()).
    std::atomic<double> stiffness_;   ///< N/m (setStiffness()).
    double rendererStiffness_;        ///< The stiffness the renderer has, N/m (haptic thread).
    std::atomic<std::uint32_t> reseatRequests_{0};
    std::atomic<std::uint32_t> clockRestarts_{0};
    std::uint32_t clockRestartsDone_ = 0; ///< RT thread only.
    // Page faults of the haptic thread (written by it only; HapticStats::pageFaults*).
    std::atomic<std::uint64_t> faultsMinor_{0};
    std::atomic<std::uint64_t> faultsMajor_{0};
    std::atomic<std::uint64_t> faultsWarmup_{0};
    /// What the haptic thread's start locks (MemoryLockMode::Owned): filled by the constructor.
    platform::MemoryRegion lockRegions_[8];
    std::size_t lockRegionCount_ = 0;
    bool forceLogLost_ = false; ///< A force-log write or its close failed (under mutex_).

    // Haptic-thread state (written only by the haptic thread while it runs).
    bool haveFrames_ = false;
    double lastT_ = 0.0;
    double phase_ = 0.0; ///< Ramp phase in [0, 1]; gain = smoothstep(phase).
    glm::dvec3 prevForce_{};
    platform::TimePoint prevCommandTime_{};
    bool havePrevCommand_ = false;
    int missedInARow_ = 0;
    int timeoutsInARow_ = 0;
    bool clutched_ = false;
    glm::dvec3 offset_{};
    glm::dvec3 lastHip_{};
    glm::dvec3 frozenHip_{};
    bool needReset_ = true;
    std::uint32_t reseatsDone_ = 0;

    // Telemetry thread and its state; mutex_ guards everything below it.
    std::unique_ptr<platform::RealtimeThread> service_; ///< kTelemetryThread, from start().
    std::mutex mutex_;
    std::condition_variable wake_;
    bool serviceStop_ = false;
    bool started_ = false;
    bool stopped_ = false;
    /// The force log, under its temporary name until stop() renames it into place.
    platform::OutputFile forceLog_;
    std::unique_ptr<LatencyHistogram> wakeHist_;
    std::unique_ptr<LatencyHistogram> updateHist_;
    std::unique_ptr<LatencyHistogram> periodHist_;
    std::int64_t prevWakeNs_ = -1;
    std::int64_t firstWakeNs_ = -1;
    std::uint64_t prevCycle_ = 0;
    bool lostLogged_ = false;
    platform::TimePoint lastReconnectTry_{}; ///< On the steady clock.
};

} // namespace depthtouch::haptic_task
