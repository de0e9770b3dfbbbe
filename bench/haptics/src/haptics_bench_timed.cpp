/// \file
/// \brief `depthtouch bench haptics` on its timing thread, and the goals it prints: see
/// haptics_bench.h.

#include <cstdio>
#include <string>

#include "depthtouch/haptics/haptics_bench.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/thread_config.h"

namespace depthtouch::haptics::bench {

namespace {

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

/// Prints the machine's 1-minute load at the start and the end of the run and its CPUs, and one
/// line more when it was loaded (loadedMachine()): its timings read high.
void printMachineLoad(const BenchReport &report)
{
    std::printf("\nmachine: 1-minute load %.2f at the start, %.2f at the end; %d CPUs",
                report.loadAtStart, report.loadAtEnd, report.cpus);
    if (report.stealPercent >= 0.0)
        std::printf("; steal %.1f %% of the CPU time during the run", report.stealPercent);
    std::printf("\n");
    if (loadedMachine(report))
        std::printf("note: the timings were taken on a loaded machine (load above %d, the CPUs "
                    "minus one, or steal above %.0f %%): the update times read high; rerun on an "
                    "idle machine to quote them\n",
                    report.cpus - 1, kLoadedStealPercent);
}

} // namespace

Result<BenchReport> runHapticsBenchmarkTimed(const BenchOptions &opt, bool fifo)
{
    // Time the updates as the servo loop runs them: on a SCHED_FIFO thread (the haptic thread's
    // priority), so other processes on a shared machine do not preempt the timed updates. Falls
    // back to normal scheduling, with a note, when the kernel refuses.
    BenchReport report;
    platform::RealtimeThreadOptions rt;
    rt.lockMemory = false;
    const platform::ThreadConfig cfg{
        "dt-bench", fifo ? platform::SchedPolicy::Fifo : platform::SchedPolicy::Other,
        fifo ? platform::kHapticThread.relativePriority : 0, 8u << 20};
    platform::RealtimeThread worker(
        cfg, rt, [&](platform::StopToken) { report = runHapticsBenchmark(opt); });
    if (Result<void> started = worker.start(); !started)
        return unexpected(started.error());
    char how[160];
    std::printf("timing thread: %s\n", worker.report().format(how, sizeof how));
    worker.join();
    return report;
}

void printBenchGoals(const BenchReport &report)
{
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
    printMachineLoad(report);
}

} // namespace depthtouch::haptics::bench
