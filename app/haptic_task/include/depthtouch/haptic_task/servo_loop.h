#pragma once
/// \file
/// \brief ServoLoop: the body of the haptic task's real-time thread (kHapticThread, SCHED_FIFO;
/// docs/architecture.md §5): per period, take the newest depth pair, read the device, map it into
/// the scene box, run the renderer (the modified proxy graph algorithm, paper IV), shape the force
/// (enable ramp, clamp to the device maximum, rate limit), command it and push one telemetry
/// sample. Units: docs/architecture.md §3 (metres, seconds, newtons).

#include <cstdint>
#include <memory>

#include <glm/vec3.hpp>

#include "depthtouch/hal/haptic_device.h"
#include "depthtouch/haptic_task/depth_handoff.h"
#include "depthtouch/haptic_task/device_supervisor.h"
#include "depthtouch/haptic_task/haptic_controls.h"
#include "depthtouch/haptic_task/haptic_counters.h"
#include "depthtouch/haptic_task/haptic_task_config.h"
#include "depthtouch/haptic_task/telemetry_sample.h"
#include "depthtouch/haptics/passivity.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/memory_lock.h"
#include "depthtouch/platform/periodic_timer.h"
#include "depthtouch/platform/realtime_thread.h"

namespace depthtouch::haptic_task {

/// \brief The haptic servo loop and the state only the haptic thread touches (ramp phase, clutch
/// and mapping offset, previous force and command time, the renderer and its stiffness, re-seat and
/// clock-restart bookkeeping).
///
/// It reads the controls (HapticControls), publishes through HapticCounters, pushes into the
/// telemetry ring and asks the DeviceSupervisor who has the device. Safety: the force is clamped to
/// min(renderer maxForce, device maxForce) (the configuration's renderer maxForce, lowered by
/// HapticTask::create()) and rate-limited; the watchdogs, a lost device and the stop command zero
/// at once.
///
/// Thread-safety: run() on the haptic thread only; after it starts it never allocates, locks,
/// logs, writes files or throws. timer() and renderer() are for the owner (the timer's statistics
/// are thread-safe; the renderer's address is for the memory lock).
class ServoLoop {
public:
    /// Updates of the warm-up: the first pass over the haptic path (lazy symbol bindings resolved,
    /// every buffer touched once) before the page faults are counted (HapticStats).
    static constexpr std::uint64_t kWarmupUpdates = 32;

    /// Every reference must outlive the loop; \a config is the effective one (the renderer's
    /// maxForce already lowered to the device's).
    ServoLoop(const HapticTaskConfig &config, hal::HapticDevice &device, DepthHandoff &handoff,
              platform::Clock &clock, std::unique_ptr<haptics::HapticRenderer> renderer,
              TelemetryRing &ring, const HapticControls &controls, HapticCounters &counters,
              DeviceSupervisor &supervisor);
    DT_DISABLE_COPY_AND_MOVE(ServoLoop)

    /// The haptic thread's body: runs the updates until \a stop or HapticControls::requestStop(),
    /// then commands zero force. Real-time safe.
    void run(platform::StopToken stop) noexcept;

    /// \return the period timer (its overruns() and missedPeriods() are thread-safe).
    [[nodiscard]] const platform::PeriodicTimer &timer() const noexcept { return timer_; }
    /// \return the renderer (for the memory lock: the haptic thread alone uses it).
    [[nodiscard]] const haptics::HapticRenderer *renderer() const noexcept
    {
        return renderer_.get();
    }

private:
    /// What the steps of one cycle hand on to each other (on the haptic thread's stack).
    struct CycleContext {
        platform::TimePoint begin; ///< Wake-up time of the cycle.
        TelemetrySample sample;    ///< The cycle's telemetry, pushed by finishCycle().
        bool late = false;         ///< The deadline watchdog holds the force at zero.
        double gain = 1.0;         ///< This cycle's ramp gain, 0..1 (rampGain(), before render()).
    };

    [[nodiscard]] bool stopRequested() const noexcept { return controls_.stopRequested(); }
    /// One cycle after the wait: the steps below, in order. Real-time safe.
    void cycle(const platform::PeriodicWait &wait) noexcept;
    /// \name The steps of cycle() (haptic thread only, real-time safe)
    ///@{
    /// \return the cycle's telemetry sample with its wake-up, latency, overrun and cycle number.
    TelemetrySample beginSample(const platform::PeriodicWait &wait) const noexcept;
    /// Hands the newest depth pair of the handoff, if any, to the renderer.
    void takeFrames() noexcept;
    /// Takes a reopened device back. \return false while the device is lost.
    bool ownDevice(TelemetrySample &sample) noexcept;
    /// Reads the device; a time-out counts for the device watchdog, any other error loses the
    /// device. \return false when \a state was not read.
    bool readDevice(hal::HapticState &state, TelemetrySample &sample) noexcept;
    /// \return the HIP: the device position mapped to the scene, held while the clutch is.
    glm::dvec3 mapToScene(const hal::HapticState &state, TelemetrySample &sample) noexcept;
    /// Applies the clock restarts and re-seats asked for since the last cycle.
    void applyRestarts() noexcept;
    /// Runs the renderer at \a hip, telling it the cycle's ramp gain (its safety watches the force
    /// sent). \return its force at the run-time stiffness, N (zero without frames).
    glm::dvec3 render(const glm::dvec3 &hip, CycleContext &c) noexcept;
    /// Moves the enable ramp (zero when late; after the deadline watchdog's zero, back to the phase
    /// it had over as long as the force was gone, at most rampTime). \return the gain in [0, 1].
    double rampGain(CycleContext &c) noexcept;
    /// \return \a target with the gain, zeroed by the clutch or a late loop, clamped to the
    /// maximum and rate-limited.
    glm::dvec3 shapeForce(glm::dvec3 target, double gain, const CycleContext &c) const noexcept;
    /// Commands \a force. \return false when the device was lost.
    bool command(const glm::dvec3 &force, CycleContext &c) noexcept;
    /// Publishes the commanded force and records it in the telemetry, the maximum, the largest
    /// step from the last force recorded (lastRecorded_) and the passivity observer (with the
    /// device's own \a position, m).
    void recordForce(const glm::dvec3 &force, const glm::dvec3 &position,
                     TelemetrySample &sample) noexcept;
    /// Pushes the telemetry sample and counts the cycle.
    void finishCycle(CycleContext &c) noexcept;
    ///@}
    void zeroForce() noexcept;
    /// Stores the haptic thread's page faults since \a since. Real-time safe (one syscall).
    void countFaults(const platform::PageFaults &since) noexcept;
    /// The device went away (NoDevice) or was closed under the task: zero force, count it, and
    /// hand the device to the telemetry thread for reconnection. Real-time safe.
    void loseDevice(TelemetrySample &sample) noexcept;

    const HapticTaskConfig &config_;
    hal::HapticDevice &device_;
    DepthHandoff &handoff_;
    platform::Clock &clock_;
    std::unique_ptr<haptics::HapticRenderer> renderer_;
    TelemetryRing &ring_;
    const HapticControls &controls_;
    HapticCounters &counters_;
    DeviceSupervisor &supervisor_;
    platform::PeriodicTimer timer_;
    const double maxForce_; ///< min(renderer, device), N.
    const double period_;   ///< s.

    // Haptic-thread state (written only by the haptic thread while it runs).
    double rendererStiffness_;            ///< The stiffness the renderer has, N/m.
    std::uint32_t clockRestartsDone_ = 0; ///< Clock restarts applied.
    std::uint32_t reseatsDone_ = 0;       ///< Re-seats applied.
    bool haveFrames_ = false;
    double lastT_ = 0.0;
    double phase_ = 0.0; ///< Ramp phase in [0, 1]; gain = smoothstep(phase).
    /// The phase the deadline watchdog's zero interrupted, regained over resumeTime_ (0: none).
    double resumePhase_ = 0.0;
    double resumeTime_ = 0.0;          ///< s: how long the force was gone (rampGain()).
    bool stalled_ = false;             ///< The last cycle was late (the watchdog held zero).
    platform::TimePoint lastOnTime_{}; ///< Wake-up of the last cycle that was not late.
    glm::dvec3 prevForce_{};
    /// The last force recorded (recordForce()), N; zero where the device was zeroed
    /// (zeroForce()). HapticStats::maxForceStep is taken from it.
    glm::dvec3 lastRecorded_{};
    /// Energy into the hand at the device's port (HapticStats::energy); its path breaks where
    /// the force was zeroed (zeroForce()).
    haptics::PassivityObserver passivity_;
    platform::TimePoint prevCommandTime_{};
    bool havePrevCommand_ = false;
    bool clutched_ = false;
    glm::dvec3 offset_{};
    glm::dvec3 lastHip_{};
    glm::dvec3 frozenHip_{};
    bool needReset_ = true;
};

} // namespace depthtouch::haptic_task
