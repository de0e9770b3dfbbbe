#pragma once
/// \file
/// \brief HapticTask: the real-time haptic servo loop of the receiver (docs/architecture.md §1,
/// §5): a SCHED_FIFO thread that reads the haptic device, maps its position into the scene box,
/// runs the modified proxy graph renderer (paper IV) against the depth frames of a DepthHandoff,
/// clamps and rate-limits the force, commands it and pushes one telemetry sample per update; plus
/// the non-real-time telemetry thread (force log CSV, counters, percentiles) and the device
/// watchdog with hot-plug recovery. Its parameters are HapticTaskConfig (haptic_task_config.h), its
/// per-update telemetry TelemetrySample (telemetry_sample.h), its results HapticStats
/// (haptic_stats.h); this header includes them.
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
#include "depthtouch/haptic_task/haptic_stats.h"
#include "depthtouch/haptic_task/haptic_task_config.h"
#include "depthtouch/haptic_task/latency_histogram.h"
#include "depthtouch/haptic_task/telemetry_sample.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/periodic_timer.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/platform/seqlock.h"
#include "depthtouch/platform/spsc_ring.h"

namespace depthtouch::haptic_task {

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
    static constexpr std::size_t kTelemetryCapacity = haptic_task::kTelemetryCapacity;
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
    using Ring = TelemetryRing;
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
