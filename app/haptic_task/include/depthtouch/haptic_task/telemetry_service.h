#pragma once
/// \file
/// \brief TelemetryService: the haptic task's telemetry thread (kTelemetryThread, SCHED_OTHER, not
/// real-time; docs/architecture.md §4, §5). Every telemetryIntervalMs it drains the telemetry ring
/// the haptic thread fills into the latency histograms and the force log CSV, and lets the
/// DeviceSupervisor reopen a lost device.

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>

#include "depthtouch/haptic_task/device_supervisor.h"
#include "depthtouch/haptic_task/haptic_stats.h"
#include "depthtouch/haptic_task/haptic_task_config.h"
#include "depthtouch/haptic_task/latency_histogram.h"
#include "depthtouch/haptic_task/telemetry_sample.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::haptic_task {

/// \brief The consumer side of the telemetry ring and the thread that runs it.
///
/// The force log (HapticTaskConfig::forceLogPath, columns in docs/architecture.md §4) is written
/// under a temporary name beside its path and renamed into place by finish() when complete; a
/// write or close that failed (a full disk) leaves nothing under its name and shows as
/// HapticStats::forceLogLost. The histograms: wake latency, update time, and the period error
/// |wake_k − wake_{k−1} − period| over consecutive on-time samples.
///
/// Thread-safety: openLog(), start(), halt(), abortLog() and finish() on the task's owner thread,
/// in that order; drain() and collect() from any thread. A mutex guards the log, the histograms
/// and the stop flag; the haptic thread never takes it (it only pushes into the ring).
class TelemetryService {
public:
    /// Allocates the histograms (throws std::bad_alloc). \a config, \a ring and \a supervisor
    /// must outlive it.
    TelemetryService(const HapticTaskConfig &config, TelemetryRing &ring,
                     DeviceSupervisor &supervisor);
    DT_DISABLE_COPY_AND_MOVE(TelemetryService)

    /// Creates the force log and writes its header (nothing without a forceLogPath).
    /// \return Errc::Io when it cannot be created.
    [[nodiscard]] Result<void> openLog();
    /// Starts the telemetry thread. \return RealtimeThread::start()'s error.
    [[nodiscard]] Result<void> start();
    /// Stops and joins the telemetry thread (nothing if it was never started). Idempotent.
    void halt() noexcept;
    /// Deletes the force log unfinished (a start that failed).
    void abortLog() noexcept;
    /// After the haptic thread and halt(): drains the ring a last time and commits the force log.
    void finish() noexcept;

    /// Drains the telemetry ring now. Thread-safe.
    void drain();
    /// Drains, then fills servoRateHz, forceLogLost, wakeLatency, updateTime, periodError and
    /// runSeconds of \a s. Thread-safe.
    void collect(HapticStats &s);

private:
    void serviceLoop();
    void drainLocked();

    const HapticTaskConfig &config_;
    TelemetryRing &ring_;
    DeviceSupervisor &supervisor_;
    std::unique_ptr<platform::RealtimeThread> service_; ///< kTelemetryThread, from start().

    // mutex_ guards everything below it.
    std::mutex mutex_;
    std::condition_variable wake_;
    bool serviceStop_ = false;
    /// The force log, under its temporary name until finish() renames it into place.
    platform::OutputFile forceLog_;
    bool forceLogLost_ = false; ///< A force-log write or its close failed.
    std::unique_ptr<LatencyHistogram> wakeHist_;
    std::unique_ptr<LatencyHistogram> updateHist_;
    std::unique_ptr<LatencyHistogram> periodHist_;
    std::int64_t prevWakeNs_ = -1;
    std::int64_t firstWakeNs_ = -1;
    std::uint64_t prevCycle_ = 0;
};

} // namespace depthtouch::haptic_task
