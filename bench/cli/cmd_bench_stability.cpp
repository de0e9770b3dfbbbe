/// \file
/// \brief `depthtouch bench stability`: closed-loop stability of the haptic renderers against the
/// stiffness k, each coupled to a simulated hand at 1 kHz and 500 Hz on a flat and a sloped plane
/// (stability_bench.h; simulated clock only); writes CSV and PNG charts into --out and prints the
/// largest k each method settles at beside the Colgate bound 2b/T.

#include <cstdio>
#include <string>
#include <vector>

#include "bench_options.h"
#include "commands.h"
#include "option_cli.h"
#include "output_paths.h"
#include "depthtouch/haptics/stability_bench.h"

namespace depthtouch::cli {

namespace {

struct BenchStabilityOptions {
    std::string out = "bench-out/stability";
    bool quick = false;
};

/// What `bench stability` measures (its line in `depthtouch bench --help`).
constexpr const char *kAbout =
    "Closed-loop stability vs stiffness against a simulated hand (Colgate bound); CSV/PNG";

/// The options of `bench stability`, in `--help` order.
const OptionRow<BenchStabilityOptions> kBenchStabilityRows[] = {
    benchOutRow<BenchStabilityOptions>(),
    {"quick", &BenchStabilityOptions::quick,
     "Short run (11 stiffnesses, hand damping 1 N s/m only)"},
};

int runBenchStability(const BenchStabilityOptions &o)
{
    if (const int rc = checkOutFolder("bench stability", o.out); rc != kExitOk)
        return rc;
    using namespace depthtouch::haptics::bench;
    StabilityOptions opt;
    if (o.quick) {
        opt.kSteps = 11;
        opt.dampings = {1.0};
    }
    const std::vector<StabilityRow> rows = runStabilitySweep(opt);
    const std::vector<StabilityLimit> limits = stabilityLimits(rows);
    std::printf("closed-loop stability: the largest stiffness each method settles at "
                "(simulated hand 0.1 kg, 300 N/m, pressing 1 N; %zu runs)\n",
                rows.size());
    printStabilityLimits(limits);
    std::string error;
    std::string note;
    if (!writeStabilityOutputs(rows, limits, o.out, error, note)) {
        std::fprintf(stderr, "depthtouch bench stability: %s\n", error.c_str());
        return kExitFailure;
    }
    if (!note.empty())
        std::printf("note: %s\n", note.c_str());
    std::printf("wrote %s/{stability.csv,stability_limits.csv,stability.png,"
                "stability_energy.png}\n",
                o.out.c_str());
    return kExitOk;
}

} // namespace

void registerBenchStabilityCommand(CLI::App &bench, int &exitCode)
{
    addTableCommand<BenchStabilityOptions>(bench, "stability", kAbout, kBenchStabilityRows,
                                           runBenchStability, exitCode);
}

} // namespace depthtouch::cli
