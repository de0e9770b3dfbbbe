#pragma once
/// \file
/// \brief HapticTaskConfig: the parameters of the haptic task (HapticTask::create()), with the
/// device mapping. Units: docs/architecture.md §3 (metres, seconds, newtons). Plain values, copied
/// into the task at create(); validate() is defined with the task (haptic_task.cpp).

#include <string>

#include <glm/vec3.hpp>

#include "depthtouch/haptics/renderer.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/result.h"

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
    /// skipped by the re-sync) command zero force at once; once the loop keeps its deadlines the
    /// force ramps back to where it was over as long as it was gone (at least a period, at most
    /// rampTime), then on at the enable ramp's rate. ≥ 1.
    int watchdogMissedDeadlines = 5;
    /// Watchdog: more than this many consecutive device time-outs (Errc::Timeout) command zero
    /// force; it ramps back in once the device answers. ≥ 1.
    int watchdogDeviceTimeouts = 5;
    /// Duration of the smooth force ramp of setEnabled(), of a reconnect and of a re-seat, and the
    /// longest resumption after the deadline watchdog, s (> 0). The gain follows smoothstep(phase),
    /// phase moving linearly.
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
    /// the C/C++ runtime and libusb (docs/memory.md); All is mlockall(MCL_CURRENT), the earlier
    /// behaviour (for `bench rt`).
    platform::MemoryLockMode memoryLock = platform::MemoryLockMode::Owned;
    int cpu = -1; ///< CPU to pin the haptic thread to, −1: none.
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

} // namespace depthtouch::haptic_task
