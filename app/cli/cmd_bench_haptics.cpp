/// \file
/// \brief `depthtouch bench haptics`: per-update time distribution and accuracy of the haptic
/// renderers (modified proxy graph, proxy-graph, mesh-bvh) at 720×486, 1920×1080 and 3840×2160;
/// writes CSV, JSON and PNG charts (speed vs accuracy, PSD with and without interpolation) into
/// --out.

#include <cstdio>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "option_cli.h"
#include "output_paths.h"
#include "depthtouch/haptics/haptics_bench.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/thread_config.h"

namespace depthtouch::cli {

namespace {

struct BenchHapticsOptions {
    std::string out = "bench-out/haptics";
    bool quick = false;
    int runs = 3;
    int updates = 20000;
    bool fifo = true;
};

/// What `bench haptics` measures (its line in `depthtouch bench --help`).
constexpr const char *kAbout =
    "Haptic renderers: update-time percentiles, per-frame cost, force error, PSD; CSV/JSON/PNG";

/// The options of `bench haptics`, in `--help` order.
const OptionRow<BenchHapticsOptions> kBenchHapticsRows[] = {
    {"out", &BenchHapticsOptions::out, "Output directory"},
    {"quick", &BenchHapticsOptions::quick, "Short run (1 repetition, 3000 updates per setting)"},
    {"runs", &BenchHapticsOptions::runs, "Repetitions per setting (medians are reported)"},
    {"updates", &BenchHapticsOptions::updates, "Haptic updates per run"},
    {"no-fifo",
     &BenchHapticsOptions::fifo,
     "Time on a normal thread instead of a SCHED_FIFO one at the haptic priority",
     {},
     kNegated},
};

/// \return "met" or "NOT met" of a goal.
const char *metText(bool met)
{
    return met ? "met" : "NOT met";
}

/// Prints the goal line of an update time \a ns (p99.9, ns): at most 2000 ns.
void printTimeGoal(const std::string &what, double ns)
{
    std::printf("  %s: %.0f ns (goal <= 2000 ns): %s\n", what.c_str(), ns, metText(ns <= 2000.0));
}

/// Prints the goal line of the median update time at 3840x2160 over that at 720x486: at most 1.5.
void printRatioGoal(const char *what, double ratio)
{
    std::printf("  %s: %.2f (goal <= 1.5): %s\n", what, ratio, metText(ratio <= 1.5));
}

int runBenchHaptics(const BenchHapticsOptions &o)
{
    // An --out where nothing can be written fails now, not after the whole run.
    if (const int rc = checkOutFolder("bench haptics", o.out); rc != kExitOk)
        return rc;
    using namespace depthtouch::haptics::bench;
    if (o.runs < 1 || o.updates < 1000) {
        std::fprintf(stderr,
                     "depthtouch bench haptics: --runs must be >= 1 and --updates >= 1000\n");
        return kExitBadInput;
    }
    BenchOptions opt;
    opt.quick = o.quick;
    opt.runs = o.runs;
    opt.updates = o.updates;
    // Time the updates as the servo loop runs them: on a SCHED_FIFO thread (the haptic thread's
    // priority), so other processes on a shared machine do not preempt the timed updates. Falls
    // back to normal scheduling, with a note, when the kernel refuses.
    BenchReport report;
    platform::RealtimeThreadOptions rt;
    rt.lockMemory = false;
    const platform::ThreadConfig cfg{
        "dt-bench", o.fifo ? platform::SchedPolicy::Fifo : platform::SchedPolicy::Other,
        o.fifo ? platform::kHapticThread.relativePriority : 0, 8u << 20};
    platform::RealtimeThread worker(
        cfg, rt, [&](platform::StopToken) { report = runHapticsBenchmark(opt); });
    if (Result<void> started = worker.start(); !started) {
        std::fprintf(stderr, "depthtouch bench haptics: cannot start the bench thread: %s\n",
                     started.error().what);
        return kExitFailure;
    }
    char how[160];
    std::printf("timing thread: %s\n", worker.report().format(how, sizeof how));
    worker.join();
    std::printf("\ngoals (this run):\n");
    printTimeGoal("modified p99.9 at 720x486, 1 m/s", report.modifiedP999At720Fast);
    const std::string runs = std::to_string(report.runsAt720Fast);
    printTimeGoal(
        "modified p99.9 at 720x486, 1 m/s, interference-filtered (per-update minimum over " + runs +
            " runs)",
        report.modifiedMinOfRunsP999At720Fast);
    printRatioGoal("modified median 3840x2160 / 720x486 (worst motion)", report.resolutionRatio);
    printRatioGoal("modified median 3840x2160 / 720x486 (worst motion), interference-filtered "
                   "(median of the per-update minimum over the runs)",
                   report.minOfRunsResolutionRatio);
    std::printf("  finger p99.9 at 720x486, 1 m/s: %.0f ns raw, %.0f ns interference-filtered "
                "(goal <= 2000 ns): "
                "%s\n",
                report.fingerP999At720Fast, report.fingerMinOfRunsP999At720Fast,
                metText(report.fingerMinOfRunsP999At720Fast <= 2000.0));
    printRatioGoal("finger median 3840x2160 / 720x486 (worst motion), interference-filtered",
                   report.fingerMinOfRunsResolutionRatio);
    std::printf("  mesh-bvh per-frame rebuild / modified per-frame cost at 720x486: %.0fx (goal >= "
                "1000x): %s\n",
                report.rebuildRatio, metText(report.rebuildRatio >= 1000.0));
    std::printf("  friction on the proxy, cost per update with / without at 720x486 (worst motion, "
                "same run): finger %.2f (filtered %.2f), modified %.2f (filtered %.2f)\n",
                report.fingerFrictionRatio, report.fingerFrictionMinOfRunsRatio,
                report.modifiedFrictionRatio, report.modifiedFrictionMinOfRunsRatio);
    std::printf("  per-pixel materials, cost per update with / without at 720x486 (worst motion, "
                "same run): finger %.2f (filtered %.2f), modified %.2f (filtered %.2f); finger "
                "p99.9 at 1 m/s with materials %.0f ns raw, %.0f ns filtered (goal <= 2000 ns): "
                "%s\n",
                report.fingerMaterialsRatio, report.fingerMaterialsMinOfRunsRatio,
                report.modifiedMaterialsRatio, report.modifiedMaterialsMinOfRunsRatio,
                report.fingerMaterialsP999At720Fast, report.fingerMaterialsMinOfRunsP999At720Fast,
                metText(report.fingerMaterialsMinOfRunsP999At720Fast <= 2000.0));
    std::string error;
    std::string note;
    if (!writeBenchOutputs(report, o.out, error, note)) {
        std::fprintf(stderr, "depthtouch bench haptics: %s\n", error.c_str());
        return kExitFailure;
    }
    if (!note.empty())
        std::printf("note: %s\n", note.c_str());
    std::printf(
        "wrote %s/{haptics_bench.csv,haptics_bench.json,psd.csv,speed_vs_accuracy.png,psd.png}\n",
        o.out.c_str());
    return kExitOk;
}

} // namespace

void registerBenchHapticsCommand(CLI::App &bench, int &exitCode)
{
    addTableCommand<BenchHapticsOptions>(bench, "haptics", kAbout, kBenchHapticsRows,
                                         runBenchHaptics, exitCode);
}

} // namespace depthtouch::cli
