/// \file
/// \brief `haptics_cost`: replays one modified-renderer setting of `depthtouch bench haptics` (same
/// wave, same HIP trajectory, same approach) without timing it, for instruction counts under
/// valgrind's callgrind, which are free of the noise of a shared machine.
///
/// Usage: `haptics_cost [--method finger|modified] WIDTH HEIGHT SPEED [UPDATES [REPEATS]]` (SPEED in
/// m/s, 0 = still; UPDATES default 3000; the method defaults to modified). With REPEATS, the setting is replayed that many times, each update timed with
/// steady_clock, and the median and p99.9 of the per-update minimum over the repeats are printed
/// (wall-clock figures with most interference stripped, for A/B comparisons on a busy machine).
/// Under callgrind only the timed updates' update() calls are collected (the
/// program toggles collection around them), so with
/// `valgrind --tool=callgrind --collect-atstart=no --instr-atstart=no haptics_cost ...` the total
/// Ir divided by UPDATES is the instructions per update. Frame generation runs uninstrumented.
/// Prints the work counters (cells, steps) and the accuracy (force RMS error against the analytic
/// truth, pop-throughs), a force checksum and a hash of the bits of every proxy and force, so variants
/// can be checked to compute the same thing (bits equal: identical; checksum close: rounding).
/// Exit code 2 on bad arguments.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string_view>
#include <vector>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/finger_renderer.h"
#include "depthtouch/haptics/renderer.h"
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

int main(int argc, char **argv)
{
    Method method = Method::Modified;
    if (argc >= 3 && std::string_view(argv[1]) == "--method") {
        const auto m = parseMethod(argv[2]);
        if (!m || (*m != Method::Modified && *m != Method::Finger)) {
            std::fprintf(stderr, "haptics_cost: --method must be modified or finger\n");
            return 2;
        }
        method = *m;
        argc -= 2;
        argv += 2;
    }
    if (argc < 4 || argc > 6) {
        std::fprintf(stderr, "usage: haptics_cost [--method finger|modified] WIDTH HEIGHT SPEED_M_PER_S "
                             "[UPDATES [REPEATS]]\n");
        return 2;
    }
    const int w = std::atoi(argv[1]);
    const int h = std::atoi(argv[2]);
    const double speed = std::atof(argv[3]);
    const long updates = argc >= 5 ? std::atol(argv[4]) : 3000;
    const long repeats = argc == 6 ? std::atol(argv[5]) : 0;
    if (w < 2 || h < 2 || w > 16384 || h > 16384 || !(speed >= 0.0) || updates < 1 || repeats < 0) {
        std::fprintf(stderr, "haptics_cost: bad arguments\n");
        return 2;
    }
    const RendererConfig cfg = RendererConfig::forMethod(method);
    const WaveScenario scene(w, h, cfg.box);
    auto made = makeRenderer(method, cfg, w, h);
    if (!made) {
        std::fprintf(stderr, "haptics_cost: %s\n", made.error().what);
        return 2;
    }
    HapticRenderer &renderer = **made;
    const auto *grid = dynamic_cast<const ProxyGraphRenderer *>(&renderer);
    const auto *finger = dynamic_cast<const FingerRenderer *>(&renderer);
    const std::size_t settle = kSettleUpdates;
    const std::size_t total = settle + static_cast<std::size_t>(updates);
    renderer.reset(WaveScenario::hipAtUpdate(speed, 0, settle));
    double errSq = 0.0;
    double checksum = 0.0;
    std::uint64_t hash = 1469598103934665603ull; // FNV-1a over the bits of every proxy and force
    auto mix = [&hash](const glm::dvec3 &v) {
        for (int k = 0; k < 3; ++k) {
            std::uint64_t bits = 0;
            std::memcpy(&bits, &v[k], sizeof bits);
            hash = (hash ^ bits) * 1099511628211ull;
        }
    };
    long pops = 0;
    long contacts = 0;
    long visited = 0;
    long tested = 0;
    long steps = 0;
    int maxVisited = 0;
    int maxSteps = 0;
    int current = -1;
    DT_CG_START();
    for (std::size_t n = 0; n < total; ++n) {
        const double t = WaveScenario::timeAt(n);
        const int fi = WaveScenario::frameIndexAt(t);
        if (fi != current) {
            current = fi;
            const DepthFrameView a = scene.frame(fi);
            const DepthFrameView b = scene.frame(fi + 1);
            (void)renderer.setFrames(a, &b);
        }
        const glm::dvec3 hip = WaveScenario::hipAtUpdate(speed, n, settle);
        const bool timed = n >= settle;
        if (timed)
            DT_CG_TOGGLE();
        const HapticOutput o = renderer.update(hip, t);
        if (timed)
            DT_CG_TOGGLE();
        if (!timed)
            continue;
        const glm::dvec3 d = o.force - WaveScenario::trueForce(hip, t, cfg);
        errSq += glm::dot(d, d);
        checksum += o.force.x + 3.0 * o.force.y + 7.0 * o.force.z;
        mix(o.proxy);
        mix(o.force);
        contacts += o.contact ? 1 : 0;
        visited += o.cellsVisited;
        tested += o.cellsTested;
        steps += o.proxySteps;
        maxVisited = std::max(maxVisited, o.cellsVisited);
        maxSteps = std::max(maxSteps, o.proxySteps);
        // The finger's surface is a plane fit held within r/4 of the samples (as in the bench).
        const HeightField &surf = grid != nullptr ? grid->surface() : finger->surface();
        const double slack = finger != nullptr ? 0.25 * finger->radius() : 1e-6 * surf.spacing();
        if (surf.contains(o.proxy.x, o.proxy.y) && o.proxy.z < surf.heightAt(o.proxy.x, o.proxy.y) - slack)
            ++pops;
    }
    const double n = static_cast<double>(updates);
    if (repeats > 0) {
        std::vector<double> best(static_cast<std::size_t>(updates),
                                 std::numeric_limits<double>::infinity());
        for (long k = 0; k < repeats; ++k) {
            auto again = makeRenderer(method, cfg, w, h);
            if (!again)
                return 2;
            HapticRenderer &timed = **again;
            timed.reset(WaveScenario::hipAtUpdate(speed, 0, settle));
            int shown = -1;
            for (std::size_t i = 0; i < total; ++i) {
                const double t = WaveScenario::timeAt(i);
                const int fi = WaveScenario::frameIndexAt(t);
                if (fi != shown) {
                    shown = fi;
                    const DepthFrameView a = scene.frame(fi);
                    const DepthFrameView b = scene.frame(fi + 1);
                    (void)timed.setFrames(a, &b);
                }
                const glm::dvec3 hip = WaveScenario::hipAtUpdate(speed, i, settle);
                const auto t0 = std::chrono::steady_clock::now();
                (void)timed.update(hip, t);
                const auto t1 = std::chrono::steady_clock::now();
                if (i >= settle) {
                    double &b = best[i - settle];
                    b = std::min(b, std::chrono::duration<double, std::nano>(t1 - t0).count());
                }
            }
        }
        std::printf("  wall clock, per-update minimum over %ld repeats: median %.0f ns p99 %.0f ns "
                    "p99.9 %.0f ns\n",
                    repeats, depthtouch::platform::percentile(best, 0.5),
                    depthtouch::platform::percentile(best, 0.99),
                    depthtouch::platform::percentile(best, 0.999));
    }
    std::printf("setting %dx%d %g m/s: updates %ld contact %ld rms %.6f N pops %ld checksum %.9e "
                "bits %016llx\n",
                w, h, speed, updates, contacts, std::sqrt(errSq / n), pops, checksum,
                static_cast<unsigned long long>(hash));
    std::printf("  per update: cells visited %.2f (max %d) tested %.2f, proxy steps %.2f (max %d)\n",
                static_cast<double>(visited) / n, maxVisited, static_cast<double>(tested) / n,
                static_cast<double>(steps) / n, maxSteps);
    return 0;
}
