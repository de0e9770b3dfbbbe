#pragma once
/// \file
/// \brief `depthtouch bench haptics`: speed and accuracy of the haptic renderers
/// (docs/benchmarks.md).
///
/// For each row of the renderer table (renderer_table.h) and its variants, depth resolution
/// (720×486, 1920×1080, 3840×2160) and HIP motion (still, stroking at 0.1 m/s and at 1 m/s) it
/// replays a moving analytic surface (a travelling sinusoid, 30 fps video, 1 kHz haptics) and
/// measures the per-update time distribution, the cost per new depth frame, the force RMS error
/// against the analytic ground truth (k × the true penetration along the true normal),
/// pop-throughs, and the PSD of |F| at the frame rate. Uses std::chrono::steady_clock (bench
/// program only). Thread-safety: call from one thread.

#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "depthtouch/haptics/renderer.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::haptics::bench {

/// Friction of the `-friction` settings (friction.h): μs and μd.
inline constexpr double kBenchStaticFriction = 0.5;
inline constexpr double kBenchDynamicFriction = 0.4;

/// \brief The renderer of the bench setting \a setting (BenchRow::method) at \a width ×
/// \a height: a row of the renderer table by name (renderer_table.h, made by makeRenderer()),
/// "<row>-friction" (μs kBenchStaticFriction, μd kBenchDynamicFriction), "<row>-materials" (the
/// row as it is; the bench's frames carry a material track) or "modified-hold" (the paper's
/// method on sample-and-hold frames: no Eq. 1). Sets \a config to its configuration.
/// \throw std::bad_alloc where the renderer cannot be made (mesh-bvh's memory, the only error of
/// a table row with its own configuration); std::invalid_argument for a name that is none of
/// these (the bench's settings are built from the table: a bug, not an input).
std::unique_ptr<HapticRenderer> benchRenderer(std::string_view setting, int width, int height,
                                              RendererConfig &config);

/// \brief Options of one benchmark run.
struct BenchOptions {
    bool quick = false;  ///< Fewer updates and repetitions.
    int runs = 3;        ///< Repetitions per setting; statistics are medians over runs.
    int updates = 20000; ///< Haptic updates per run (modified, proxy-graph).
    bool verbose = true; ///< Print progress and the table to stdout.
};

/// \brief One (method, resolution, motion) setting.
struct BenchRow {
    /// A renderer table row's name, or a variant of one (benchRenderer()): <row>-friction and
    /// <row>-materials for the rows with the paper's fixes and friction (at 720×486 only, μs =
    /// kBenchStaticFriction, μd = kBenchDynamicFriction; a material track of friction bands, see
    /// haptics_bench.cpp), and modified-hold.
    std::string method;
    int width = 0;
    int height = 0;
    std::string motion;      ///< still | 0.1 m/s | 1 m/s
    std::size_t updates = 0; ///< Updates per run.
    double medianNs = 0.0;   ///< Per-update time, ns (median over runs of each statistic).
    double p99Ns = 0.0;
    double p999Ns = 0.0;
    double maxNs = 0.0;
    /// Interference-filtered tail: every run replays identical updates, so the per-update minimum
    /// over the runs strips interrupts, preemption and steal time but keeps an update that is slow
    /// by itself. Median, p99 and p99.9 of that minimum, ns (the raw figures of the run when runs
    /// == 1).
    double minOfRunsMedianNs = 0.0;
    double minOfRunsP99Ns = 0.0;
    double minOfRunsP999Ns = 0.0;
    int runsTimed = 1;          ///< Runs the minimum is taken over.
    double frameCostNs = 0.0;   ///< Median cost of handing one new depth frame to the renderer, ns.
    double forceRmsError = 0.0; ///< N, against the analytic ground truth.
    /// |F − F_ideal| over the timed updates, N: 50th, 95th, 99th percentile (nearest rank) and
    /// maximum (median over the runs of each run's figure, as the RMS).
    double forceErrorP50 = 0.0;
    double forceErrorP95 = 0.0;
    double forceErrorP99 = 0.0;
    double forceErrorMax = 0.0;
    /// Spread between the runs: the lowest and highest of the runs' own p99.9 update times, ns
    /// (equal when runs == 1).
    double p999MinOverRunsNs = 0.0;
    double p999MaxOverRunsNs = 0.0;
    long popThroughs = 0; ///< Updates ending with the proxy below the renderer's surface.
    /// PSD of |F| at 30 Hz, dB re 1 N²/Hz: measured on still runs (NaN otherwise); −infinity when
    /// the force was constant (e.g. zero: contact lost).
    double psdFrameRateDb = std::numeric_limits<double>::quiet_NaN();
};

/// \brief Cost of handing the renderer a new depth frame spread over the haptic updates of one
/// frame: frameCostNs × kVideoFps / kHapticRate, ns per update (mesh-bvh: its tree rebuild).
double amortisedFrameCostNs(const BenchRow &row);

/// \brief The PSD curves for the Fig. 12-like chart (720×486, HIP still).
struct PsdCurves {
    double binHz = 0.0;
    std::vector<double> interpolatedDb; ///< modified
    std::vector<double> holdDb;         ///< modified with interpolation off (sample-and-hold)
};

/// \brief Everything one run produced, plus the goals of docs/benchmarks.md evaluated on it.
struct BenchReport {
    std::vector<BenchRow> rows;
    PsdCurves psd;
    double modifiedP999At720Fast = 0.0; ///< ns, raw (median over runs); goal ≤ 2000
    double modifiedMinOfRunsP999At720Fast =
        0.0;                      ///< ns, p99.9 of the per-update minimum; goal ≤ 2000
    int runsAt720Fast = 0;        ///< runs behind the minimum above
    double resolutionRatio = 0.0; ///< modified median 3840×2160 / 720×486, worst motion; goal ≤ 1.5
    double minOfRunsResolutionRatio = 0.0; ///< the same with minOfRunsMedianNs; goal ≤ 1.5
    double rebuildRatio =
        0.0; ///< mesh-bvh frame cost / modified frame cost at 720×486; goal ≥ 1000
    /// The same goals for the finger renderer (the player's default): p99.9 at 720×486, 1 m/s, raw
    /// and interference-filtered (goal ≤ 2000 ns), and the filtered 3840×2160 / 720×486 median
    /// ratio.
    double fingerP999At720Fast = 0.0;
    double fingerMinOfRunsP999At720Fast = 0.0;
    double fingerMinOfRunsResolutionRatio = 0.0;
    /// Cost of friction on the proxy (docs/materials.md): the worst median ratio over the motions
    /// at 720×486 of `finger-friction` / `finger` and `modified-friction` / `modified`, measured in
    /// the same run, raw and interference-filtered.
    double fingerFrictionRatio = 0.0;
    double fingerFrictionMinOfRunsRatio = 0.0;
    double modifiedFrictionRatio = 0.0;
    double modifiedFrictionMinOfRunsRatio = 0.0;
    /// Cost of per-pixel materials (a material track read under the proxy every update, Eq. 1
    /// included): `finger-materials` / `finger` and `modified-materials` / `modified`, as above;
    /// and the finger's p99.9 at 720×486, 1 m/s with materials (goal ≤ 2000 ns filtered).
    double fingerMaterialsRatio = 0.0;
    double fingerMaterialsMinOfRunsRatio = 0.0;
    double modifiedMaterialsRatio = 0.0;
    double modifiedMaterialsMinOfRunsRatio = 0.0;
    double fingerMaterialsP999At720Fast = 0.0;
    double fingerMaterialsMinOfRunsP999At720Fast = 0.0;
    /// The machine's 1-minute load average (/proc/loadavg) when the run started and when it ended;
    /// −1 when it could not be read.
    double loadAtStart = -1.0;
    double loadAtEnd = -1.0;
    /// The share of the CPUs' time stolen while the run lasted (a hypervisor running other
    /// guests: /proc/stat's steal, stealPercent()), %; −1 when it could not be read.
    double stealPercent = -1.0;
    int cpus = 0; ///< CPUs online (std::thread::hardware_concurrency; 0 when unknown).
};

/// A run with more steal than this (BenchReport::stealPercent, %) was timed on a loaded machine.
inline constexpr double kLoadedStealPercent = 5.0;

/// \brief Whether \a report was timed on a loaded machine: the 1-minute load at its start or end
/// above the number of CPUs minus one (one CPU left for the timed thread), or more than
/// kLoadedStealPercent of the CPU time stolen during it.
bool loadedMachine(const BenchReport &report);

/// \brief The share of the CPU time that passed between two readings of /proc/stat's first line
/// ("cpu  user nice system idle iowait irq softirq steal ...", clock ticks) that was stolen, %.
/// \return −1 when a line is not such a line (fewer than 8 numbers) or no time passed.
double stealPercent(std::string_view statAtStart, std::string_view statAtEnd);

/// \brief Runs the benchmark. Allocates freely (not real-time).
BenchReport runHapticsBenchmark(const BenchOptions &options);

/// \brief Runs the benchmark on a timing thread, as the servo loop runs its updates: SCHED_FIFO at
/// the haptic thread's priority when \a fifo (so other processes on a shared machine do not preempt
/// the timed updates; normal scheduling, with a note, when the kernel refuses), else a normal
/// thread; prints the thread's scheduling on stdout. \return the report, or the error of a thread
/// that could not start.
Result<BenchReport> runHapticsBenchmarkTimed(const BenchOptions &options, bool fifo);

/// \brief Prints the goals of \a report on stdout, each with "met" or "NOT met", then the machine's
/// load during the run, and a line saying so when the machine was loaded (loadedMachine()).
void printBenchGoals(const BenchReport &report);

/// \brief Writes haptics_bench.csv, haptics_bench.json, psd.csv and (with gnuplot)
/// speed_vs_accuracy.png and psd.png into \a dir (created). \return false and a message in \a error
/// on I/O failure; a missing gnuplot is reported in \a note, not an error.
bool writeBenchOutputs(const BenchReport &report, const std::string &dir, std::string &error,
                       std::string &note);

} // namespace depthtouch::haptics::bench
