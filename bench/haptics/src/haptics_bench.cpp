#include "depthtouch/haptics/haptics_bench.h"

#include "haptics_bench_internal.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/renderer.h"
#include "depthtouch/haptics/renderer_table.h"
#include "depthtouch/haptics/spectrum.h"
#include "depthtouch/haptics/wave_scenario.h"
#include "depthtouch/scene/material.h"
#include "depthtouch/platform/percentile.h"

namespace depthtouch::haptics::bench {

using platform::percentile;

namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v)
{
    return percentile(v, 0.5);
}

struct OneRun {
    double medianNs, p99Ns, p999Ns, maxNs, frameNs, rms;
    double errP50, errP95, errP99, errMax; ///< |F − F_ideal| over the timed updates, N
    long pops;
    std::vector<double> forces;
    std::vector<double> times; ///< ns per timed update, in update order
};

/// The material track of the `-materials` settings: 16-pixel vertical bands alternating μs/μd
/// 0.5/0.4 and 0.3/0.2 at stiffness scale 1 (so the force error stays comparable with the
/// `-friction` rows), one RGB24 image for every frame. Every update reads it (Eq. 1 included).
std::vector<std::uint8_t> benchMaterial(int w, int h)
{
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) {
            const bool grip = (c / 16) % 2 == 0;
            scene::encodeMaterial(
                {1.0, grip ? kBenchStaticFriction : 0.3, grip ? kBenchDynamicFriction : 0.2},
                &rgb[(static_cast<std::size_t>(r) * static_cast<std::size_t>(w) +
                      static_cast<std::size_t>(c)) *
                     3]);
        }
    return rgb;
}

/// The force-error figures of \a out from the per-update |F − F_ideal| \a errors (N): RMS,
/// 50/95/99th percentiles (nearest rank) and maximum; 0 without updates.
void setForceErrors(OneRun &out, const std::vector<double> &errors)
{
    double sq = 0.0;
    for (double e : errors)
        sq += e * e;
    out.rms = errors.empty() ? 0.0 : std::sqrt(sq / static_cast<double>(errors.size()));
    out.errP50 = percentile(errors, 0.5);
    out.errP95 = percentile(errors, 0.95);
    out.errP99 = percentile(errors, 0.99);
    out.errMax = errors.empty() ? 0.0 : *std::max_element(errors.begin(), errors.end());
}

OneRun runOnce(const std::string &method, const WaveScenario &scene, double speed,
               std::size_t updates)
{
    const int w = scene.width();
    const int h = scene.height();
    const bool materials = method.ends_with("-materials");
    const std::vector<std::uint8_t> material =
        materials ? benchMaterial(w, h) : std::vector<std::uint8_t>{};
    const scene::MaterialView materialView{materials ? material.data() : nullptr,
                                           static_cast<std::size_t>(w) * 3};
    RendererConfig cfg;
    const std::unique_ptr<HapticRenderer> r = benchRenderer(method, w, h, cfg);
    HeightField held(cfg.box); // the mesh-bvh's surface (current frame) for the pop-through check
    std::vector<double> frameTimes;
    OneRun out{};
    out.times.reserve(updates);
    out.forces.reserve(updates);
    std::vector<double> errors; ///< |F − F_ideal| per timed update, N
    errors.reserve(updates);
    int current = -1;
    // Approach time before measuring; short for mesh-bvh, whose every frame costs a full rebuild.
    const std::size_t settle = method == "mesh-bvh" ? 40 : kSettleUpdates;
    r->reset(WaveScenario::hipAtUpdate(speed, 0, settle));
    for (std::size_t n = 0; n < updates + settle; ++n) {
        const double t = WaveScenario::timeAt(n);
        const int fi = WaveScenario::frameIndexAt(t);
        if (fi != current) {
            current = fi;
            DepthFrameView av = scene.frame(fi);
            DepthFrameView bv = scene.frame(fi + 1);
            av.material = materialView;
            bv.material = materialView;
            const auto t0 = Clock::now();
            (void)r->setFrames(av, &bv);
            const auto t1 = Clock::now();
            frameTimes.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
            (void)held.setFrames(av, nullptr);
        }
        const glm::dvec3 hip = WaveScenario::hipAtUpdate(speed, n, settle);
        const auto t0 = Clock::now();
        const HapticOutput o = r->update(hip, t);
        const auto t1 = Clock::now();
        if (n < settle)
            continue;
        out.times.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
        const glm::dvec3 truth = WaveScenario::trueForce(hip, t, cfg);
        const glm::dvec3 d = o.force - truth;
        errors.push_back(glm::length(d));
        out.forces.push_back(glm::length(o.force));
        if (poppedThrough(*r, o.proxy, &held))
            ++out.pops;
    }
    out.medianNs = percentile(out.times, 0.5);
    out.p99Ns = percentile(out.times, 0.99);
    out.p999Ns = percentile(out.times, 0.999);
    out.maxNs = *std::max_element(out.times.begin(), out.times.end());
    // The first hand-over of a run includes first-touch effects; use the median of all.
    out.frameNs = median(frameTimes);
    setForceErrors(out, errors);
    return out;
}

/// Per-update minimum over the runs: every run replays the same updates, so the minimum strips
/// interrupts, preemption and steal time while an update that is slow by itself stays slow.
std::vector<double> perUpdateMinimum(const std::vector<OneRun> &all)
{
    std::vector<double> best = all.front().times;
    for (const OneRun &o : all)
        for (std::size_t i = 0; i < best.size() && i < o.times.size(); ++i)
            best[i] = std::min(best[i], o.times[i]);
    return best;
}

} // namespace

std::string psdText(double db, const char *unit)
{
    if (std::isnan(db))
        return "n/a";
    if (std::isinf(db))
        return "no force";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f%s", db, unit);
    return buf;
}

double amortisedFrameCostNs(const BenchRow &row)
{
    return row.frameCostNs * kVideoFps / kHapticRate;
}

bool loadedMachine(const BenchReport &report)
{
    const double load = std::max(report.loadAtStart, report.loadAtEnd);
    return (report.cpus > 0 && load > static_cast<double>(report.cpus - 1)) ||
           report.stealPercent > kLoadedStealPercent;
}

namespace {

/// The steal ticks and all the ticks of /proc/stat's "cpu" line \a line; false when it is not one.
bool cpuTicks(std::string_view line, double &steal, double &total)
{
    if (line.substr(0, 4) != "cpu ")
        return false;
    const std::string text(line.substr(4));
    const char *p = text.c_str();
    total = 0.0;
    int n = 0;
    for (;; ++n) {
        char *end = nullptr;
        const double v = std::strtod(p, &end);
        if (end == p)
            break;
        // guest and guest_nice (the 9th and 10th) are counted in user and nice already
        if (n < 8)
            total += v;
        if (n == 7)
            steal = v;
        p = end;
    }
    return n >= 8;
}

} // namespace

double stealPercent(std::string_view statAtStart, std::string_view statAtEnd)
{
    double steal0 = 0.0, total0 = 0.0, steal1 = 0.0, total1 = 0.0;
    if (!cpuTicks(statAtStart, steal0, total0) || !cpuTicks(statAtEnd, steal1, total1) ||
        total1 <= total0 || steal1 < steal0)
        return -1.0;
    return 100.0 * (steal1 - steal0) / (total1 - total0);
}

namespace {

/// The first line of /proc/stat (the CPUs' time), or empty when it cannot be read.
std::string cpuStatLine()
{
    std::FILE *f = std::fopen("/proc/stat", "r");
    if (f == nullptr)
        return {};
    char buf[512];
    const bool read = std::fgets(buf, sizeof buf, f) != nullptr;
    std::fclose(f);
    return read ? std::string(buf) : std::string();
}

/// The machine's 1-minute load average (/proc/loadavg), or −1 when it cannot be read.
double loadAverage()
{
    double load = 0.0;
    return getloadavg(&load, 1) == 1 ? load : -1.0;
}

const char *motionName(double speed)
{
    return speed == 0.0 ? "still" : (speed < 0.5 ? "0.1 m/s" : "1 m/s");
}

/// Whether the bench measures \a method at width \a w with the HIP moving at \a speed.
bool measured(const std::string &method, int w, double speed, bool quick)
{
    if (method == "modified-hold" && speed != 0.0)
        return false;
    // A 3840×2160 tree rebuild takes tens of seconds here: still HIP only, and not in --quick.
    return !(method == "mesh-bvh" && w >= 3840 && (quick || speed != 0.0));
}

/// The median over the runs of one of their statistics.
double medianOver(const std::vector<OneRun> &all, double OneRun::*field)
{
    std::vector<double> v;
    for (const OneRun &o : all)
        v.push_back(o.*field);
    return median(v);
}

/// The timing and accuracy columns of \a row from its runs.
void fillFigures(BenchRow &row, const std::vector<OneRun> &all, int reps)
{
    row.medianNs = medianOver(all, &OneRun::medianNs);
    row.p99Ns = medianOver(all, &OneRun::p99Ns);
    row.p999Ns = medianOver(all, &OneRun::p999Ns);
    row.maxNs = medianOver(all, &OneRun::maxNs);
    {
        const std::vector<double> best = perUpdateMinimum(all);
        row.runsTimed = reps;
        row.minOfRunsMedianNs = percentile(best, 0.5);
        row.minOfRunsP99Ns = percentile(best, 0.99);
        row.minOfRunsP999Ns = percentile(best, 0.999);
    }
    row.frameCostNs = medianOver(all, &OneRun::frameNs);
    row.forceRmsError = medianOver(all, &OneRun::rms);
    row.forceErrorP50 = medianOver(all, &OneRun::errP50);
    row.forceErrorP95 = medianOver(all, &OneRun::errP95);
    row.forceErrorP99 = medianOver(all, &OneRun::errP99);
    row.forceErrorMax = medianOver(all, &OneRun::errMax);
    row.p999MinOverRunsNs = row.p999MaxOverRunsNs = all.front().p999Ns;
    for (const OneRun &o : all) {
        row.p999MinOverRunsNs = std::min(row.p999MinOverRunsNs, o.p999Ns);
        row.p999MaxOverRunsNs = std::max(row.p999MaxOverRunsNs, o.p999Ns);
    }
    row.popThroughs = all.front().pops;
}

/// The |F| spectrum of a still HIP: the tremor at the frame rate, and at 720×486 the curves of the
/// PSD chart.
void fillSpectrum(BenchRow &row, const OneRun &first, double speed, BenchReport &report)
{
    if (speed != 0.0 || first.forces.size() < 2000)
        return;
    const std::vector<double> &f = first.forces;
    const int segs = static_cast<int>(f.size() / 2000);
    const Psd psd = averagedPsd(f.data(), f.size(), segs, kHapticRate, 100.0);
    // Sample-and-hold puts the tremor at fs ± the motion frequency (1.875 Hz): look within ±2.5 Hz.
    row.psdFrameRateDb = psdPeakDb(psd, kVideoFps, 2.5);
    if (row.width == 720 && (row.method == "modified" || row.method == "modified-hold")) {
        report.psd.binHz = psd.binHz;
        std::vector<double> &dst =
            row.method == "modified" ? report.psd.interpolatedDb : report.psd.holdDb;
        dst.clear();
        for (double d : psd.density)
            dst.push_back(10.0 * std::log10(std::max(d, 1e-30)));
    }
}

/// The progress line of one measured row.
void printRow(const BenchRow &row)
{
    std::printf("  %-13s %4dx%-4d %-7s median %8.0f ns  p99 %8.0f  p99.9 %8.0f  max %9.0f  "
                "frame %11.0f ns  rms %.4f N (p99 %.4f, max %.4f)  pops %ld  psd@30Hz %s  |  "
                "per-update min of %d runs: median %6.0f  p99.9 %7.0f  (runs' p99.9 %.0f-%.0f)\n",
                row.method.c_str(), row.width, row.height, row.motion.c_str(), row.medianNs,
                row.p99Ns, row.p999Ns, row.maxNs, row.frameCostNs, row.forceRmsError,
                row.forceErrorP99, row.forceErrorMax, row.popThroughs,
                psdText(row.psdFrameRateDb, " dB").c_str(), row.runsTimed, row.minOfRunsMedianNs,
                row.minOfRunsP999Ns, row.p999MinOverRunsNs, row.p999MaxOverRunsNs);
}

/// Runs one setting (method, resolution, HIP motion) and makes its row.
BenchRow measureSetting(const std::string &method, const WaveScenario &scene, double speed,
                        std::size_t updates, int runs, bool quick, BenchReport &report)
{
    const int w = scene.width();
    const bool mesh = method == "mesh-bvh";
    // mesh-bvh rebuilds its tree on every frame (seconds at 4K): fewer updates, one run.
    const std::size_t n = mesh ? (w >= 3840 ? 40u : (quick ? 100u : 300u)) : updates;
    const int reps = mesh ? 1 : runs;
    std::vector<OneRun> all;
    for (int k = 0; k < reps; ++k)
        all.push_back(runOnce(method, scene, speed, n));
    BenchRow row;
    row.method = method;
    row.width = w;
    row.height = scene.height();
    row.motion = motionName(speed);
    row.updates = n;
    fillFigures(row, all, reps);
    fillSpectrum(row, all.front(), speed, report);
    return row;
}

/// The BenchRow of \a method at width \a w and \a motion, or nullptr.
const BenchRow *findRow(const BenchReport &report, const char *m, int w, const char *motion)
{
    for (const BenchRow &r : report.rows)
        if (r.method == m && r.width == w && r.motion == motion)
            return &r;
    return nullptr;
}

/// The worst 3840×2160 / 720×486 ratio over the motions of \a field for \a method.
double worstRatio(const BenchReport &report, const char *method, double BenchRow::*field)
{
    double worst = 0.0;
    for (const char *motion : {"still", "0.1 m/s", "1 m/s"}) {
        const BenchRow *a = findRow(report, method, 720, motion);
        const BenchRow *b = findRow(report, method, 3840, motion);
        if (a && b && a->*field > 0)
            worst = std::max(worst, b->*field / a->*field);
    }
    return worst;
}

/// The worst \a variant / \a plain ratio of \a field at 720×486 over the motions (same run).
double costRatio(const BenchReport &report, const char *plain, const char *variant,
                 double BenchRow::*field)
{
    double worst = 0.0;
    for (const char *motion : {"still", "0.1 m/s", "1 m/s"}) {
        const BenchRow *a = findRow(report, plain, 720, motion);
        const BenchRow *b = findRow(report, variant, 720, motion);
        if (a && b && a->*field > 0)
            worst = std::max(worst, b->*field / a->*field);
    }
    return worst;
}

/// The goal figures, from the rows of this run.
void setGoals(BenchReport &report)
{
    // The cost of friction and of materials beside the plain renderer: raw and filtered medians.
    struct Ratio {
        const char *plain;
        const char *variant;
        double BenchReport::*raw;
        double BenchReport::*filtered;
    };
    static constexpr Ratio kRatios[] = {
        {"finger", "finger-friction", &BenchReport::fingerFrictionRatio,
         &BenchReport::fingerFrictionMinOfRunsRatio},
        {"modified", "modified-friction", &BenchReport::modifiedFrictionRatio,
         &BenchReport::modifiedFrictionMinOfRunsRatio},
        {"finger", "finger-materials", &BenchReport::fingerMaterialsRatio,
         &BenchReport::fingerMaterialsMinOfRunsRatio},
        {"modified", "modified-materials", &BenchReport::modifiedMaterialsRatio,
         &BenchReport::modifiedMaterialsMinOfRunsRatio},
    };
    for (const Ratio &k : kRatios) {
        report.*k.raw = costRatio(report, k.plain, k.variant, &BenchRow::medianNs);
        report.*k.filtered = costRatio(report, k.plain, k.variant, &BenchRow::minOfRunsMedianNs);
    }
    if (const BenchRow *r = findRow(report, "finger-materials", 720, "1 m/s")) {
        report.fingerMaterialsP999At720Fast = r->p999Ns;
        report.fingerMaterialsMinOfRunsP999At720Fast = r->minOfRunsP999Ns;
    }
    if (const BenchRow *r = findRow(report, "finger", 720, "1 m/s")) {
        report.fingerP999At720Fast = r->p999Ns;
        report.fingerMinOfRunsP999At720Fast = r->minOfRunsP999Ns;
    }
    report.fingerMinOfRunsResolutionRatio =
        worstRatio(report, "finger", &BenchRow::minOfRunsMedianNs);
    if (const BenchRow *r = findRow(report, "modified", 720, "1 m/s")) {
        report.modifiedP999At720Fast = r->p999Ns;
        report.modifiedMinOfRunsP999At720Fast = r->minOfRunsP999Ns;
        report.runsAt720Fast = r->runsTimed;
    }
    report.resolutionRatio = worstRatio(report, "modified", &BenchRow::medianNs);
    report.minOfRunsResolutionRatio = worstRatio(report, "modified", &BenchRow::minOfRunsMedianNs);
    const BenchRow *mesh = findRow(report, "mesh-bvh", 720, "still");
    const BenchRow *mod = findRow(report, "modified", 720, "still");
    if (mesh && mod && mod->frameCostNs > 0)
        report.rebuildRatio = mesh->frameCostNs / mod->frameCostNs;
}

} // namespace

BenchReport runHapticsBenchmark(const BenchOptions &options)
{
    BenchReport report;
    if (options.verbose)
        std::setvbuf(stdout, nullptr, _IOLBF, 0); // progress lines appear as they are measured
    const int resolutions[3][2] = {{720, 486}, {1920, 1080}, {3840, 2160}};
    const double speeds[3] = {0.0, 0.1, 1.0};
    report.cpus = static_cast<int>(std::thread::hardware_concurrency());
    report.loadAtStart = loadAverage();
    const std::string statAtStart = cpuStatLine();
    const int runs = std::max(1, options.quick ? 1 : options.runs);
    const std::size_t updates =
        static_cast<std::size_t>(options.quick ? 3000 : std::max(1000, options.updates));
    const SceneBox box{};
    for (const auto &res : resolutions) {
        const int w = res[0];
        const int h = res[1];
        if (options.verbose)
            std::printf("haptics bench: %dx%d: generating the depth frames...\n", w, h);

        const WaveScenario scene(w, h, box);
        // The renderer table's rows. Friction on the proxy is timed beside its frictionless
        // renderer at 720×486 only, and so are per-pixel materials (a material track under the
        // proxy), for the rows with the paper's fixes that render them; the paper's method is
        // also timed on sample-and-hold frames there.
        std::vector<std::string> methods;
        for (const RendererEntry &e : rendererTable()) {
            const std::string name = e.name;
            if (w == 720 && e.method == Method::Modified)
                methods.push_back("modified-hold");
            methods.push_back(name);
            if (w == 720 && e.fixes && e.friction) {
                methods.push_back(name + "-friction");
                methods.push_back(name + "-materials");
            }
        }
        for (const std::string &method : methods) {
            for (double speed : speeds) {
                if (!measured(method, w, speed, options.quick))
                    continue;
                report.rows.push_back(
                    measureSetting(method, scene, speed, updates, runs, options.quick, report));
                if (options.verbose)
                    printRow(report.rows.back());
            }
        }
    }
    setGoals(report);
    report.loadAtEnd = loadAverage();
    report.stealPercent = stealPercent(statAtStart, cpuStatLine());
    return report;
}

std::unique_ptr<HapticRenderer> benchRenderer(std::string_view setting, int width, int height,
                                              RendererConfig &config)
{
    std::string_view row = setting;
    const bool friction = row.ends_with("-friction");
    const bool hold = row == "modified-hold";
    if (friction)
        row.remove_suffix(std::string_view("-friction").size());
    else if (row.ends_with("-materials"))
        row.remove_suffix(std::string_view("-materials").size());
    else if (hold)
        row = methodName(Method::Modified);
    const RendererEntry *entry = findRenderer(row);
    if (entry == nullptr)
        throw std::invalid_argument("bench haptics: no renderer table row for this setting");
    const Method method = entry->method;
    config = RendererConfig::forMethod(method);
    if (hold)
        config.interpolation = false;
    if (friction) {
        config.staticFriction = kBenchStaticFriction;
        config.dynamicFriction = kBenchDynamicFriction;
    }
    auto made = makeRenderer(method, config, width, height);
    if (!made)
        throw std::bad_alloc();
    return std::move(*made);
}

} // namespace depthtouch::haptics::bench
