/// \file
/// \brief `depthtouch bench haptics`: per-update time distribution and accuracy of the haptic
/// renderers (modified proxy graph, proxy-graph, mesh-bvh) at 720×486, 1920×1080 and 3840×2160;
/// writes CSV, JSON and PNG charts (speed vs accuracy, PSD with and without interpolation) into
/// --out.

#include <cstdio>
#include <memory>
#include <string>

#include "bench_options.h"
#include "commands.h"
#include "option_cli.h"
#include "output_paths.h"
#include "depthtouch/haptics/haptics_bench.h"

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
    benchOutRow<BenchHapticsOptions>(),
    {"quick", &BenchHapticsOptions::quick, "Short run (1 repetition, 3000 updates per setting)"},
    {"runs", &BenchHapticsOptions::runs, "Repetitions per setting (medians are reported)"},
    {"updates", &BenchHapticsOptions::updates, "Haptic updates per run"},
    noFifoRow<BenchHapticsOptions>(),
};

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
    auto report = runHapticsBenchmarkTimed(opt, o.fifo);
    if (!report) {
        std::fprintf(stderr, "depthtouch bench haptics: cannot start the bench thread: %s\n",
                     report.error().what);
        return kExitFailure;
    }
    printBenchGoals(*report);
    std::string error;
    std::string note;
    if (!writeBenchOutputs(*report, o.out, error, note)) {
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
