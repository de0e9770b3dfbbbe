#include "depthtouch/haptics/haptics_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "depthtouch/haptics/finger_renderer.h"
#include "depthtouch/haptics/mesh_bvh.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/haptics/renderer_table.h"
#include "depthtouch/haptics/spectrum.h"
#include "depthtouch/haptics/wave_scenario.h"
#include "depthtouch/platform/gnuplot.h"
#include "depthtouch/scene/material.h"
#include "depthtouch/platform/percentile.h"
#include "depthtouch/platform/report_file.h"

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

bool endsWith(const std::string &s, const char *suffix)
{
    const std::string tail(suffix);
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

OneRun runOnce(const std::string &method, const WaveScenario &scene, double speed,
               std::size_t updates)
{
    const int w = scene.width();
    const int h = scene.height();
    const bool materials = endsWith(method, "-materials");
    const std::vector<std::uint8_t> material =
        materials ? benchMaterial(w, h) : std::vector<std::uint8_t>{};
    const scene::MaterialView materialView{materials ? material.data() : nullptr,
                                           static_cast<std::size_t>(w) * 3};
    RendererConfig cfg;
    std::unique_ptr<HapticRenderer> r;
    ProxyGraphRenderer *grid = nullptr;
    FingerRenderer *finger = nullptr;
    if (method == "mesh-bvh") {
        cfg = RendererConfig::forMethod(Method::MeshBvh);
        r = std::make_unique<MeshBvhRenderer>(cfg, w, h);
    } else if (method == "finger" || method == "finger-friction" || method == "finger-materials") {
        cfg = RendererConfig::forMethod(Method::Finger);
        if (method == "finger-friction") {
            cfg.staticFriction = kBenchStaticFriction;
            cfg.dynamicFriction = kBenchDynamicFriction;
        }
        auto f = std::make_unique<FingerRenderer>(cfg);
        finger = f.get();
        r = std::move(f);
    } else {
        cfg = RendererConfig::forMethod(method == "proxy-graph" ? Method::ProxyGraph
                                                                : Method::Modified);
        if (method == "modified-hold")
            cfg.interpolation = false;
        if (method == "modified-friction") {
            cfg.staticFriction = kBenchStaticFriction;
            cfg.dynamicFriction = kBenchDynamicFriction;
        }
        auto g = std::make_unique<ProxyGraphRenderer>(cfg);
        grid = g.get();
        r = std::move(g);
    }
    HeightField held(cfg.box); // the mesh-bvh's surface (current frame) for the pop-through check
    std::vector<double> frameTimes;
    OneRun out{};
    out.times.reserve(updates);
    out.forces.reserve(updates);
    double errSq = 0.0;
    std::size_t errN = 0;
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
        errSq += glm::dot(d, d);
        ++errN;
        out.forces.push_back(glm::length(o.force));
        const HeightField &surf =
            grid != nullptr ? grid->surface() : (finger != nullptr ? finger->surface() : held);
        // The finger's surface is a plane fit held within r/4 of the samples: it counts a
        // pop-through only deeper than that.
        const double slack = finger != nullptr ? 0.25 * finger->radius() : 1e-6 * surf.spacing();
        if (surf.contains(o.proxy.x, o.proxy.y) &&
            o.proxy.z < surf.heightAt(o.proxy.x, o.proxy.y) - slack)
            ++out.pops;
    }
    out.medianNs = percentile(out.times, 0.5);
    out.p99Ns = percentile(out.times, 0.99);
    out.p999Ns = percentile(out.times, 0.999);
    out.maxNs = *std::max_element(out.times.begin(), out.times.end());
    // The first hand-over of a run includes first-touch effects; use the median of all.
    out.frameNs = median(frameTimes);
    out.rms = errN ? std::sqrt(errSq / static_cast<double>(errN)) : 0.0;
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

/// The PSD figure as text: "n/a" when not measured (moving HIP), "no force" when |F| had no power.
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
                "frame %11.0f ns  rms %.4f N  pops %ld  psd@30Hz %s  |  per-update min "
                "of %d runs: median %6.0f  p99.9 %7.0f\n",
                row.method.c_str(), row.width, row.height, row.motion.c_str(), row.medianNs,
                row.p99Ns, row.p999Ns, row.maxNs, row.frameCostNs, row.forceRmsError,
                row.popThroughs, psdText(row.psdFrameRateDb, " dB").c_str(), row.runsTimed,
                row.minOfRunsMedianNs, row.minOfRunsP999Ns);
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
    return report;
}

namespace {

/// haptics_bench.csv: a row per renderer, size and motion. \return false (\a error set) when the
/// file could not be written.
bool writeRowsCsv(const BenchReport &report, const std::filesystem::path &base, std::string &error)
{
    {
        platform::TextReportFile csv((base / "haptics_bench.csv").string(), error);
        csv << "method,width,height,motion,updates,median_ns,p99_ns,p999_ns,max_ns,frame_cost_ns,"
               "force_rms_error_n,pop_throughs,psd_frame_rate_db,runs,min_of_runs_median_ns,"
               "min_of_runs_p99_ns,min_of_runs_p999_ns\n";
        for (const BenchRow &r : report.rows) {
            char line[512];
            std::snprintf(
                line, sizeof line,
                "%s,%d,%d,%s,%zu,%.1f,%.1f,%.1f,%.1f,%.1f,%.6f,%ld,%s,%d,%.1f,%.1f,%.1f\n",
                r.method.c_str(), r.width, r.height, r.motion.c_str(), r.updates, r.medianNs,
                r.p99Ns, r.p999Ns, r.maxNs, r.frameCostNs, r.forceRmsError, r.popThroughs,
                psdText(r.psdFrameRateDb, "").c_str(), r.runsTimed, r.minOfRunsMedianNs,
                r.minOfRunsP99Ns, r.minOfRunsP999Ns);
            csv << line;
        }
        if (!csv.close())
            return false;
    }
    return true;
}

/// haptics_bench.json: the rows and the goal figures. \return false (\a error set) when the file
/// could not be written.
bool writeReportJson(const BenchReport &report, const std::filesystem::path &base,
                     std::string &error)
{
    {
        // NaN (not measured) and −infinity (no power at all) have no JSON number: null.
        auto number = [](double v) {
            return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
        };
        nlohmann::json rows = nlohmann::json::array();
        for (const BenchRow &r : report.rows)
            rows.push_back({{"method", r.method},
                            {"width", r.width},
                            {"height", r.height},
                            {"motion", r.motion},
                            {"updates", r.updates},
                            {"median_ns", r.medianNs},
                            {"p99_ns", r.p99Ns},
                            {"p999_ns", r.p999Ns},
                            {"max_ns", r.maxNs},
                            {"frame_cost_ns", r.frameCostNs},
                            {"force_rms_error_n", r.forceRmsError},
                            {"pop_throughs", r.popThroughs},
                            {"psd_frame_rate_db", number(r.psdFrameRateDb)},
                            {"runs", r.runsTimed},
                            {"min_of_runs_median_ns", r.minOfRunsMedianNs},
                            {"min_of_runs_p99_ns", r.minOfRunsP99Ns},
                            {"min_of_runs_p999_ns", r.minOfRunsP999Ns}});
        const nlohmann::json doc = {
            {"rows", rows},
            {"goals",
             {{"modified_p999_ns_720x486_1mps", report.modifiedP999At720Fast},
              {"goal_p999_ns", 2000},
              {"modified_min_of_runs_p999_ns_720x486_1mps", report.modifiedMinOfRunsP999At720Fast},
              {"runs_720x486_1mps", report.runsAt720Fast},
              {"goal_min_of_runs_p999_ns", 2000},
              {"median_ratio_3840x2160_over_720x486", report.resolutionRatio},
              {"goal_ratio", 1.5},
              {"min_of_runs_median_ratio_3840x2160_over_720x486", report.minOfRunsResolutionRatio},
              {"goal_min_of_runs_ratio", 1.5},
              {"rebuild_ratio_meshbvh_over_modified", report.rebuildRatio},
              {"goal_rebuild_ratio", 1000},
              {"finger_p999_ns_720x486_1mps", report.fingerP999At720Fast},
              {"finger_min_of_runs_p999_ns_720x486_1mps", report.fingerMinOfRunsP999At720Fast},
              {"finger_min_of_runs_median_ratio_3840x2160_over_720x486",
               report.fingerMinOfRunsResolutionRatio},
              {"finger_friction_median_ratio_720x486", report.fingerFrictionRatio},
              {"finger_friction_min_of_runs_median_ratio_720x486",
               report.fingerFrictionMinOfRunsRatio},
              {"modified_friction_median_ratio_720x486", report.modifiedFrictionRatio},
              {"modified_friction_min_of_runs_median_ratio_720x486",
               report.modifiedFrictionMinOfRunsRatio},
              {"finger_materials_median_ratio_720x486", report.fingerMaterialsRatio},
              {"finger_materials_min_of_runs_median_ratio_720x486",
               report.fingerMaterialsMinOfRunsRatio},
              {"modified_materials_median_ratio_720x486", report.modifiedMaterialsRatio},
              {"modified_materials_min_of_runs_median_ratio_720x486",
               report.modifiedMaterialsMinOfRunsRatio},
              {"finger_materials_p999_ns_720x486_1mps", report.fingerMaterialsP999At720Fast},
              {"finger_materials_min_of_runs_p999_ns_720x486_1mps",
               report.fingerMaterialsMinOfRunsP999At720Fast}}}};
        platform::TextReportFile js((base / "haptics_bench.json").string(), error);
        js << doc.dump(2) << '\n';
        if (!js.close())
            return false;
    }
    return true;
}

/// psd.csv, speed_vs_accuracy.dat and the gnuplot script charts.gp of the two charts.
/// \return false (\a error set) when a file could not be written.
bool writeChartData(const BenchReport &report, const std::filesystem::path &base,
                    std::string &error)
{
    {
        platform::TextReportFile p((base / "psd.csv").string(), error);
        p << "hz,interpolated_db,sample_and_hold_db\n";
        const std::size_t n = std::min(report.psd.interpolatedDb.size(), report.psd.holdDb.size());
        for (std::size_t k = 1; k < n; ++k)
            p << static_cast<double>(k) * report.psd.binHz << ',' << report.psd.interpolatedDb[k]
              << ',' << report.psd.holdDb[k] << '\n';
    }
    {
        // one data block per method for the speed-vs-accuracy scatter
        platform::TextReportFile d((base / "speed_vs_accuracy.dat").string(), error);
        std::vector<std::string> series;
        for (const RendererEntry &e : rendererTable()) {
            series.emplace_back(e.name);
            if (e.method == Method::Modified)
                series.emplace_back("modified-hold");
        }
        for (const std::string &m : series) {
            d << "# " << m << "\n";
            for (const BenchRow &r : report.rows)
                if (r.method == m)
                    d << r.medianNs / 1000.0 << ' ' << std::max(r.forceRmsError, 1e-6) << " \""
                      << r.width << 'x' << r.height << ' ' << r.motion << "\"\n";
            d << "\n\n";
        }
    }
    {
        platform::TextReportFile g((base / "charts.gp").string(), error);
        g << "set terminal pngcairo size 1100,700 noenhanced\n"
             "set output '"
          << (base / "speed_vs_accuracy.png").string()
          << "'\n"
             "set title \"Haptic renderers: update time vs force error\\n(moving sinusoid, 30 fps "
             "video, 1 kHz; one point per resolution and HIP motion: haptics_bench.csv)\"\n"
             "set logscale xy\nset xlabel 'median update time (us)'\nset ylabel 'force RMS error "
             "vs analytic truth (N)'\n"
             "set key outside right\nset grid\n"
             "plot for [i=0:4] '"
          << (base / "speed_vs_accuracy.dat").string()
          << "' index i using 1:2 with points pt 7 ps 1.5 title word('finger modified "
             "modified-hold proxy-graph mesh-bvh', i+1)\n"
             "set output '"
          << (base / "psd.png").string()
          << "'\n"
             "unset logscale\nset title 'PSD of |F|, HIP still, 720x486 (cf. paper Fig. 12)'\n"
             "set xlabel 'frequency (Hz)'\nset ylabel 'PSD (dB re 1 N^2/Hz)'\nset xrange [0:100]\n"
             "set datafile separator ','\n"
             "plot '"
          << (base / "psd.csv").string()
          << "' using 1:3 with lines title 'sample-and-hold', '' using 1:2 with lines title "
             "'interpolated (Eq. 1)'\n";
    }
    return error.empty();
}

} // namespace

bool writeBenchOutputs(const BenchReport &report, const std::string &dir, std::string &error,
                       std::string &note)
{
    if (!platform::createReportFolder(dir, "Failed to create '" + dir + "'", error))
        return false;
    const std::filesystem::path base(dir);
    if (!writeRowsCsv(report, base, error) || !writeReportJson(report, base, error))
        return false;
    if (!writeChartData(report, base, error))
        return false;
    // Charts with gnuplot, when it is installed.
    const platform::PlotStatus plot = platform::runGnuplot((base / "charts.gp").string());
    if (plot != platform::PlotStatus::Drawn)
        note = std::string(platform::plotStatusNote(plot)) + "; CSV and JSON written";
    return true;
}

} // namespace depthtouch::haptics::bench
