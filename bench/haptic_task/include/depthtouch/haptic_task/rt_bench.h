#pragma once
/// \file
/// \brief `depthtouch bench rt`: wake latency (wake time − deadline) and period error of the haptic
/// servo loop at 1 kHz and 4 kHz, for a bare PeriodicTimer loop and for the full HapticTask (device
/// read, renderer on a moving depth video, force command, telemetry), SCHED_FIFO against
/// SCHED_OTHER and the owned memory lock (Owned) against mlockall(MCL_CURRENT) (All),
/// alternating in the same run, idle and optionally while other threads load the CPUs. Writes CSV
/// and a PNG chart.
///
/// Not real-time itself: runs the cases one after the other on the calling thread's behalf.
/// Thread-safety: reentrant functions.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "depthtouch/hal/haptic_device.h"
#include "depthtouch/haptic_task/latency_histogram.h"
#include "depthtouch/platform/memory_lock.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/platform/thread_config.h"

namespace depthtouch::haptic_task::bench {

/// Creates a fresh haptic device on the steady clock for one task case (e.g. the `sim` hand).
using DeviceFactory = std::function<Result<std::unique_ptr<hal::HapticDevice>>()>;

struct RtBenchOptions {
    double secondsPerCase = 5.0;                 ///< Duration of each case, s (> 0).
    std::vector<double> ratesHz{1000.0, 4000.0}; ///< Servo rates.
    std::vector<platform::SchedPolicy> policies{platform::SchedPolicy::Fifo,
                                                platform::SchedPolicy::Other};
    /// Memory locks compared, in this order for every rate and policy (alternating in the same
    /// run): MemoryLockMode::Owned (the default lock) and All
    /// (mlockall(MCL_CURRENT), the one before), undone with munlockall() after each case. Not
    /// empty.
    std::vector<platform::MemoryLockMode> lockModes{platform::MemoryLockMode::Owned,
                                                    platform::MemoryLockMode::All};
    bool load = false;        ///< Also run every case while loadThreads threads decode-like work.
    int loadThreads = 2;      ///< Threads of the load (≥ 1).
    /// The load instead of the decode-like threads, e.g. the player decoding and rendering real
    /// content in this process: started before the loaded cases, stopped when the returned object
    /// is destroyed. Empty: the decode-like threads.
    std::function<std::shared_ptr<void>()> makeLoad;
    DeviceFactory makeDevice; ///< Device for the task cases; none: only the bare loop runs.
    /// Called after each case with a one-line summary (progress output); may be empty.
    std::function<void(const std::string &)> progress;
};

/// One measured case.
struct RtCase {
    std::string loop; ///< "bare" or "task".
    double rateHz = 0.0;
    platform::SchedPolicy policy = platform::SchedPolicy::Fifo;
    bool loaded = false;
    bool fifoRefused = false; ///< SCHED_FIFO was asked for and the kernel refused it.
    platform::MemoryLockMode lockMode = platform::MemoryLockMode::Owned; ///< The lock asked for.
    bool lockRefused = false; ///< The kernel refused the lock (the case ran unlocked).
    double lockedMiB = 0.0;   ///< The process's locked memory (VmLck) at the end of the case, MiB.
    double residentMiB = 0.0; ///< Its resident memory (VmRSS) then, MiB.
    double seconds = 0.0;     ///< Measured duration, s.
    std::uint64_t cycles = 0;
    std::uint64_t overruns = 0;
    LatencySummary wake;          ///< Wake time − deadline.
    LatencySummary periodError;   ///< |wake_k − wake_{k−1} − period| over on-time cycles.
    LatencySummary update;        ///< Task only: wake-up to force command.
    double deviceCallMaxUs = 0.0; ///< Task only: longest device call (read or command), µs.
    [[nodiscard]] double overrunsPerMinute() const noexcept
    {
        return seconds > 0.0 ? static_cast<double>(overruns) * 60.0 / seconds : 0.0;
    }
    [[nodiscard]] std::string label() const; ///< e.g. "task 1k FIFO owned load".
};

struct RtBenchReport {
    std::vector<RtCase> cases;
    std::string taskError; ///< Why the task cases did not run (empty when they did).
};

/// Runs every case (rates × policies × {bare, task} × {idle, loaded}). \return the report; the
/// cases that could not run are left out (taskError says why for the task ones).
RtBenchReport runRtBenchmark(const RtBenchOptions &options);

/// One goal check of a run: a ratio of two wake-latency figures measured in the same run.
struct RtGoalRatio {
    std::string label; ///< e.g. "task 1k FIFO task/bare wake p99".
    double ratio = 0.0;
    double goal = 0.0; ///< Met when ratio <= goal.
};

/// \return the goal ratios of \a report: task/bare wake p50 and p99 (goal 1.10) per case,
/// loaded/idle wake p99 (goal 1.20) per loaded case, and owned/all wake p99 (goal 1.00: the owned
/// lock no worse than mlockall) per case measured with both.
std::vector<RtGoalRatio> rtGoalRatios(const RtBenchReport &report);

/// \brief Prints the table and the goal checks (task within 10 % of the bare loop; load moving p99
/// by at most 20 %) to stdout.
void printRtReport(const RtBenchReport &report);

/// \brief Runs every case \a runs times (runRtBenchmark()), printing each run's report (a
/// "--- run i of n ---" line before each when more than one) and, over several runs, each goal's
/// median ratio with its range and whether it is met (rtGoalRatios()).
/// \return every run's cases, and the first run's task error.
RtBenchReport runRtBenchmarkRuns(const RtBenchOptions &options, int runs);

/// \brief Writes rt_bench.csv, rt_bench.gp and rt_bench.png (gnuplot, when installed) into \a dir.
/// \return false with \a error set when a file cannot be written; \a note explains a missing chart.
bool writeRtBenchOutputs(const RtBenchReport &report, const std::string &dir, std::string &error,
                         std::string &note);

} // namespace depthtouch::haptic_task::bench
