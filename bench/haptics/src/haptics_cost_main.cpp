/// \file
/// \brief `haptics_cost`: replays one modified-renderer setting of `depthtouch bench haptics` (same
/// wave, same HIP trajectory, same approach) without timing it, for instruction counts under
/// valgrind's callgrind, which are free of the noise of a shared machine.
///
/// Usage: `haptics_cost [--method finger|ball|modified] [--friction] WIDTH HEIGHT SPEED [UPDATES
/// [REPEATS]]` (`--friction`: friction on the proxy, μs kBenchStaticFriction and μd
/// kBenchDynamicFriction of haptics_bench.h; SPEED in m/s, 0 = still; UPDATES default 3000; the
/// method defaults to modified). With REPEATS, the setting is replayed that many times, each update
/// timed with
/// steady_clock, and the median and p99.9 of the per-update minimum over the repeats are printed
/// (wall-clock figures with most interference stripped, for A/B comparisons on a busy machine).
/// Under callgrind only the timed updates' update() calls are collected (the
/// program toggles collection around them), so with
/// `valgrind --tool=callgrind --collect-atstart=no --instr-atstart=no haptics_cost ...` the total
/// Ir divided by UPDATES is the instructions per update. Frame generation runs uninstrumented.
/// Prints the work counters (cells, steps) and the accuracy (force RMS error against the analytic
/// truth, pop-throughs), a force checksum and a hash of the bits of every proxy and force, so
/// variants can be checked to compute the same thing (bits equal: identical; checksum close:
/// rounding). Exit code 2 on bad arguments.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/haptics_bench.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/haptics/renderer_table.h"
#include "depthtouch/haptics/wave_scenario.h"
#include "depthtouch/platform/percentile.h"

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define DT_CG_START() CALLGRIND_START_INSTRUMENTATION
#define DT_CG_TOGGLE() CALLGRIND_TOGGLE_COLLECT
#else
#define DT_CG_START() ((void)0)
#define DT_CG_TOGGLE() ((void)0)
#endif

using namespace depthtouch::haptics;
using namespace depthtouch::haptics::bench;

namespace {

/// The command line, checked.
struct CostArgs {
    Method method = Method::Modified;
    int w = 0;
    int h = 0;
    double speed = 0.0;
    long updates = 3000;
    long repeats = 0;
    bool friction = false; ///< --friction: μs kBenchStaticFriction, μd kBenchDynamicFriction
};

/// \return the names of the renderer table's rows with the paper's fixes, "finger or modified"
/// (or joined by \a separator alone).
std::string fixedMethods(const char *separator = nullptr)
{
    std::string out;
    std::vector<const char *> names;
    for (const RendererEntry &e : rendererTable())
        if (e.fixes)
            names.push_back(e.name);
    for (std::size_t i = 0; i < names.size(); ++i) {
        if (i > 0)
            out += separator != nullptr ? separator : (i + 1 == names.size() ? " or " : ", ");
        out += names[i];
    }
    return out;
}

/// Parses the command line; prints what is wrong and returns nothing on bad arguments.
std::optional<CostArgs> parseArgs(int argc, char **argv)
{
    CostArgs args;
    if (argc >= 3 && std::string_view(argv[1]) == "--method") {
        // The renderers of depth video (the table's rows with the paper's fixes), not baselines.
        const auto m = parseMethod(argv[2]);
        if (!m || !rendererEntry(*m).fixes) {
            std::fprintf(stderr, "haptics_cost: --method must be %s\n", fixedMethods().c_str());
            return std::nullopt;
        }
        args.method = *m;
        argc -= 2;
        argv += 2;
    }
    if (argc >= 2 && std::string_view(argv[1]) == "--friction") {
        args.friction = true;
        argc -= 1;
        argv += 1;
    }
    if (argc < 4 || argc > 6) {
        std::fprintf(stderr,
                     "usage: haptics_cost [--method %s] [--friction] WIDTH HEIGHT SPEED_M_PER_S "
                     "[UPDATES [REPEATS]]\n",
                     fixedMethods("|").c_str());
        return std::nullopt;
    }
    args.w = std::atoi(argv[1]);
    args.h = std::atoi(argv[2]);
    args.speed = std::atof(argv[3]);
    args.updates = argc >= 5 ? std::atol(argv[4]) : 3000;
    args.repeats = argc == 6 ? std::atol(argv[5]) : 0;
    if (args.w < 2 || args.h < 2 || args.w > 16384 || args.h > 16384 || !(args.speed >= 0.0) ||
        args.updates < 1 || args.repeats < 0) {
        std::fprintf(stderr, "haptics_cost: bad arguments\n");
        return std::nullopt;
    }
    return args;
}

/// Shows the renderer the frame pair around time \p t when it is not the one it holds.
void showFrames(HapticRenderer &renderer, const WaveScenario &scene, double t, int &current)
{
    const int fi = WaveScenario::frameIndexAt(t);
    if (fi == current)
        return;
    current = fi;
    const DepthFrameView a = scene.frame(fi);
    const DepthFrameView b = scene.frame(fi + 1);
    (void)renderer.setFrames(a, &b);
}

/// What the counted replay adds up over its timed updates.
struct Tally {
    double errSq = 0.0;
    double checksum = 0.0;
    std::uint64_t hash = 1469598103934665603ull; // FNV-1a over the bits of every proxy and force
    long pops = 0;
    long contacts = 0;
    long visited = 0;
    long tested = 0;
    long steps = 0;
    int maxVisited = 0;
    int maxSteps = 0;

    void mix(const glm::dvec3 &v)
    {
        for (int k = 0; k < 3; ++k) {
            std::uint64_t bits = 0;
            std::memcpy(&bits, &v[k], sizeof bits);
            hash = (hash ^ bits) * 1099511628211ull;
        }
    }
};

/// Adds one timed update's output to the tally.
void count(Tally &tally, const HapticRenderer &renderer, const HapticOutput &o,
           const glm::dvec3 &hip, double t, const RendererConfig &cfg)
{
    const glm::dvec3 d = o.force - WaveScenario::trueForce(hip, t, cfg);
    tally.errSq += glm::dot(d, d);
    tally.checksum += o.force.x + 3.0 * o.force.y + 7.0 * o.force.z;
    tally.mix(o.proxy);
    tally.mix(o.force);
    tally.contacts += o.contact ? 1 : 0;
    tally.visited += o.cellsVisited;
    tally.tested += o.cellsTested;
    tally.steps += o.proxySteps;
    tally.maxVisited = std::max(tally.maxVisited, o.cellsVisited);
    tally.maxSteps = std::max(tally.maxSteps, o.proxySteps);
    if (poppedThrough(renderer, o.proxy))
        ++tally.pops;
}

/// Replays the setting once, collecting (under callgrind) and counting only the timed updates.
Tally replayCounted(const CostArgs &args, const RendererConfig &cfg, const WaveScenario &scene,
                    HapticRenderer &renderer)
{
    const std::size_t settle = kSettleUpdates;
    const std::size_t total = settle + static_cast<std::size_t>(args.updates);
    renderer.reset(WaveScenario::hipAtUpdate(args.speed, 0, settle));
    Tally tally;
    int current = -1;
    DT_CG_START();
    for (std::size_t n = 0; n < total; ++n) {
        const double t = WaveScenario::timeAt(n);
        showFrames(renderer, scene, t, current);
        const glm::dvec3 hip = WaveScenario::hipAtUpdate(args.speed, n, settle);
        const bool timed = n >= settle;
        if (timed)
            DT_CG_TOGGLE();
        const HapticOutput o = renderer.update(hip, t);
        if (timed)
            DT_CG_TOGGLE();
        if (!timed)
            continue;
        count(tally, renderer, o, hip, t, cfg);
    }
    return tally;
}

/// Replays the setting REPEATS times on fresh renderers and keeps each timed update's minimum wall
/// clock in ns; nothing when a renderer cannot be made.
std::optional<std::vector<double>> replayTimed(const CostArgs &args, const RendererConfig &cfg,
                                               const WaveScenario &scene)
{
    const std::size_t settle = kSettleUpdates;
    const std::size_t total = settle + static_cast<std::size_t>(args.updates);
    std::vector<double> best(static_cast<std::size_t>(args.updates),
                             std::numeric_limits<double>::infinity());
    for (long k = 0; k < args.repeats; ++k) {
        auto again = makeRenderer(args.method, cfg, args.w, args.h);
        if (!again)
            return std::nullopt;
        HapticRenderer &timed = **again;
        timed.reset(WaveScenario::hipAtUpdate(args.speed, 0, settle));
        int shown = -1;
        for (std::size_t i = 0; i < total; ++i) {
            const double t = WaveScenario::timeAt(i);
            showFrames(timed, scene, t, shown);
            const glm::dvec3 hip = WaveScenario::hipAtUpdate(args.speed, i, settle);
            const auto t0 = std::chrono::steady_clock::now();
            (void)timed.update(hip, t);
            const auto t1 = std::chrono::steady_clock::now();
            if (i >= settle) {
                double &b = best[i - settle];
                b = std::min(b, std::chrono::duration<double, std::nano>(t1 - t0).count());
            }
        }
    }
    return best;
}

/// Prints the setting's counters, accuracy, checksum and bits.
void report(const CostArgs &args, const Tally &tally)
{
    const double n = static_cast<double>(args.updates);
    std::printf("setting %dx%d %g m/s: updates %ld contact %ld rms %.6f N pops %ld checksum %.9e "
                "bits %016llx\n",
                args.w, args.h, args.speed, args.updates, tally.contacts,
                std::sqrt(tally.errSq / n), tally.pops, tally.checksum,
                static_cast<unsigned long long>(tally.hash));
    std::printf(
        "  per update: cells visited %.2f (max %d) tested %.2f, proxy steps %.2f (max %d)\n",
        static_cast<double>(tally.visited) / n, tally.maxVisited,
        static_cast<double>(tally.tested) / n, static_cast<double>(tally.steps) / n,
        tally.maxSteps);
}

} // namespace

int main(int argc, char **argv)
{
    const auto args = parseArgs(argc, argv);
    if (!args)
        return 2;
    RendererConfig cfg = RendererConfig::forMethod(args->method);
    if (args->friction) {
        cfg.staticFriction = kBenchStaticFriction;
        cfg.dynamicFriction = kBenchDynamicFriction;
    }
    const WaveScenario scene(args->w, args->h, cfg.box);
    auto made = makeRenderer(args->method, cfg, args->w, args->h);
    if (!made) {
        std::fprintf(stderr, "haptics_cost: %s\n", made.error().what);
        return 2;
    }
    const Tally tally = replayCounted(*args, cfg, scene, **made);
    if (args->repeats > 0) {
        const auto best = replayTimed(*args, cfg, scene);
        if (!best)
            return 2;
        std::printf("  wall clock, per-update minimum over %ld repeats: median %.0f ns p99 %.0f ns "
                    "p99.9 %.0f ns\n",
                    args->repeats, depthtouch::platform::percentile(*best, 0.5),
                    depthtouch::platform::percentile(*best, 0.99),
                    depthtouch::platform::percentile(*best, 0.999));
    }
    report(*args, tally);
    return 0;
}
