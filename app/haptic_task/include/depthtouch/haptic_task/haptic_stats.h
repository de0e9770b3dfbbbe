#pragma once
/// \file
/// \brief HapticStats: the counters and percentiles of a haptic task's run (HapticTask::stats()),
/// and their JSON (haptic_stats.cpp). Plain values, read after the fact.

#include <cstdint>
#include <string>

#include "depthtouch/haptic_task/latency_histogram.h"

namespace depthtouch::haptic_task {

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
    /// The haptic thread had the device, connected, when the stats were read (false: lost, or
    /// never plugged in since a start that waited for it, hal::BackendConfig::awaitDevice).
    bool deviceConnected = false;
    std::uint64_t telemetryDropped = 0; ///< Samples lost to a full ring (not in the percentiles).
    double maxForce = 0.0;              ///< Largest commanded force magnitude, N.
    /// Largest change of the commanded force from one command to the next, N: a knock the hand
    /// feels (`depthtouch demo`'s goal: no step over 1 N per update), the deadline watchdog's drop
    /// to zero on a late cycle included. After a lost device it is the step from zero.
    double maxForceStep = 0.0;
    /// Energy the commanded force put into the hand at the device's port over the run, J (the
    /// passivity observer of haptics/passivity.h on the device's own position, m, and the force
    /// commanded, held until the next command); > 0 is energy the renderer (or the moving
    /// picture) gave the hand.
    double energy = 0.0;
    double energyPeak = 0.0; ///< Its largest value at any time in the run, J (≥ 0).
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
    /// device_losses, reconnects, device_connected, telemetry_dropped, max_force_n,
    /// max_force_step_n, device_max_force_n, device_call_max_us, force_log_lost, haptic_thread,
    /// haptic_page_faults {minor, major, warmup}, haptic_locked_mib.
    [[nodiscard]] std::string toJson(int indent = 2) const;
};

} // namespace depthtouch::haptic_task
