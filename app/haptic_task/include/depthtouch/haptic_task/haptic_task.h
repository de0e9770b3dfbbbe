#pragma once
/// \file
/// \brief HapticTask: the real-time haptic servo loop of the receiver (docs/architecture.md §1,
/// §5): a SCHED_FIFO thread that reads the haptic device, maps its position into the scene box,
/// runs the modified proxy graph renderer (paper IV) against the depth frames of a DepthHandoff,
/// clamps and rate-limits the force, commands it and pushes one telemetry sample per update; plus
/// the non-real-time telemetry thread (force log CSV, counters, percentiles) and the device
/// watchdog with hot-plug recovery.
///
/// The task is split along its threads, one object each, all inside it: ServoLoop (the haptic
/// thread's loop and the state only it touches), HapticControls (the run-time controls: any thread
/// → haptic thread), HapticCounters (what the haptic thread publishes to the others),
/// DeviceSupervisor (the watchdogs, device loss and reconnection) and TelemetryService (the
/// telemetry thread: ring drain, histograms, force log). The parameters are HapticTaskConfig
/// (haptic_task_config.h), the per-update telemetry TelemetrySample (telemetry_sample.h), the
/// results HapticStats (haptic_stats.h); this header includes them all.
///
/// Units and frames: docs/architecture.md §3 (metres, seconds, newtons; scene box x right, y up, z
/// toward the viewer). The device frame has the same axes (hal/haptic_device.h); the mapping is
/// `HIP = scale·p_device + offset`, and the force is sent to the device unchanged (newtons).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>

#include <glm/vec3.hpp>

#include "depthtouch/hal/haptic_device.h"
#include "depthtouch/haptic_task/depth_handoff.h"
#include "depthtouch/haptic_task/device_supervisor.h"
#include "depthtouch/haptic_task/haptic_controls.h"
#include "depthtouch/haptic_task/haptic_counters.h"
#include "depthtouch/haptic_task/haptic_stats.h"
#include "depthtouch/haptic_task/haptic_task_config.h"
#include "depthtouch/haptic_task/latency_histogram.h"
#include "depthtouch/haptic_task/servo_loop.h"
#include "depthtouch/haptic_task/telemetry_sample.h"
#include "depthtouch/haptic_task/telemetry_service.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/memory_lock.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::haptic_task {

/// \brief The haptic servo loop and its telemetry.
///
/// Per update, on the haptic thread (nothing else): take the newest depth pair from the handoff;
/// read the device; map to the scene; gain (enable ramp, zero when late), told to the renderer
/// (HapticRenderer::setOutputGain(): its let-go at the device maximum watches the force sent);
/// renderer update; gain applied, clamp to the device maximum, force-rate limit; commandForce();
/// push one TelemetrySample. It never allocates, locks,
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
    static constexpr std::uint64_t kWarmupUpdates = ServoLoop::kWarmupUpdates;

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
    void requestStop() noexcept { controls_.requestStop(); }
    /// \return true once requestStop() or stop() was called. Async-signal-safe.
    [[nodiscard]] bool stopRequested() const noexcept { return controls_.stopRequested(); }

    /// \brief Switches haptics on or off at run time; the force ramps over rampTime.
    /// Async-signal-safe.
    void setEnabled(bool enabled) noexcept { controls_.setEnabled(enabled); }
    [[nodiscard]] bool enabled() const noexcept { return controls_.enabled(); }

    /// \brief Changes the surface stiffness at run time, N/m (scene::kMinStiffness..kMaxStiffness;
    /// other values are ignored).
    /// The haptic thread hands it to the renderer at its next update
    /// (haptics::HapticRenderer::setStiffness()): the renderer's force-jump safety and slew limit
    /// act on the force at the new stiffness, and with the force-rate limit after them a change
    /// is felt within a few milliseconds and never as a step. The damping b stays as configured.
    /// Async-signal-safe.
    void setStiffness(double newtonsPerMetre) noexcept { controls_.setStiffness(newtonsPerMetre); }
    /// \return the stiffness in use, N/m.
    [[nodiscard]] double stiffness() const noexcept { return controls_.stiffness(); }
    /// \brief Re-seats the proxy on the surface above the HIP at the next update and ramps the
    /// force in from zero (rampTime), and restarts the haptic time: for a seek (the media time
    /// jumps, possibly backwards) and for "recenter". No force kick. Async-signal-safe.
    void requestReseat() noexcept { controls_.requestReseat(); }
    /// \brief Restarts the haptic time at the next update (a seek or a loop: the media time jumps,
    /// possibly backwards) and keeps the proxy and the force, so content that continues under the
    /// finger keeps its support; a surface that changed under the proxy is a cut for the renderer's
    /// safety (HapticRenderer::restartClock()). Async-signal-safe.
    void requestClockRestart() noexcept { controls_.requestClockRestart(); }

    /// \name Observers (thread-safe)
    ///@{
    /// \return cycles of the haptic loop so far.
    [[nodiscard]] std::uint64_t updates() const noexcept { return counters_.updates(); }
    /// \return true while the haptic thread owns a connected device (false while it is lost).
    [[nodiscard]] bool deviceConnected() const noexcept { return supervisor_.connected(); }
    /// \return the current ramp gain in [0, 1].
    [[nodiscard]] double gain() const noexcept { return counters_.gain(); }
    /// \return the last force commanded, N (zero while the device is lost).
    [[nodiscard]] glm::dvec3 lastForce() const noexcept { return counters_.lastForce(); }
    /// \brief The HIP and the proxy of the last rendered update, m, scene box (the avatar the
    /// graphic renderer draws). \return false before the first rendered update.
    bool lastPose(glm::dvec3 &hip, glm::dvec3 &proxy) const noexcept
    {
        return counters_.lastPose(hip, proxy);
    }
    /// \return counters and percentiles of the samples drained so far (drains first).
    [[nodiscard]] HapticStats stats();
    /// \return what the haptic thread obtained from the kernel (valid after start()).
    [[nodiscard]] const platform::RealtimeThreadReport &threadReport() const noexcept;
    ///@}

    /// \brief Drains the telemetry ring now (also done by the telemetry thread). Thread-safe.
    void drainTelemetry() { service_.drain(); }

    [[nodiscard]] const HapticTaskConfig &config() const noexcept { return config_; }

private:
    HapticTask(const HapticTaskConfig &config, hal::HapticDevice &device, DepthHandoff &handoff,
               platform::Clock &clock, std::unique_ptr<haptics::HapticRenderer> renderer);
    DT_DISABLE_COPY_AND_MOVE(HapticTask)

    /// Fills lockRegions_ (constructor).
    void collectLockRegions() noexcept;

    const HapticTaskConfig config_;
    hal::HapticDevice &device_;
    DepthHandoff &handoff_;
    std::unique_ptr<TelemetryRing> ring_;
    // The objects of the threads, in the order they depend on each other (all inside this object,
    // so the memory lock of its bytes covers them).
    HapticControls controls_;
    HapticCounters counters_;
    DeviceSupervisor supervisor_;
    ServoLoop loop_;
    TelemetryService service_;
    std::unique_ptr<platform::RealtimeThread> thread_; ///< The haptic thread (runs loop_).
    /// What the haptic thread's start locks (MemoryLockMode::Owned): filled by the constructor.
    platform::MemoryRegion lockRegions_[8];
    std::size_t lockRegionCount_ = 0;

    // Owner-thread lifecycle; mutex_ guards it.
    std::mutex mutex_;
    bool started_ = false;
    bool stopped_ = false;
};

} // namespace depthtouch::haptic_task
