/// \file
/// \brief The files of `depthtouch bench haptics`: haptics_bench.csv, haptics_bench.json, psd.csv
/// and the gnuplot charts speed_vs_accuracy.png and psd.png (see haptics_bench.h).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "depthtouch/haptics/haptics_bench.h"
#include "depthtouch/haptics/renderer_table.h"
#include "depthtouch/haptics/wave_scenario.h"
#include "depthtouch/platform/gnuplot.h"
#include "depthtouch/platform/report_file.h"
#include "haptics_bench_internal.h"

namespace depthtouch::haptics::bench {

namespace {

/// The goal of docs/benchmarks.md on the haptic update time: p99.9 ≤ 2 µs.
constexpr double kGoalP999Us = 2.0;

/// The spread between the runs of \a r: highest over lowest of the runs' p99.9 (1 for one run).
double p999SpreadRatio(const BenchRow &r)
{
    return r.p999MinOverRunsNs > 0.0 ? r.p999MaxOverRunsNs / r.p999MinOverRunsNs : 1.0;
}

/// haptics_bench.csv: a row per renderer, size and motion. \return false (\a error set) when the
/// file could not be written.
bool writeRowsCsv(const BenchReport &report, const std::filesystem::path &base, std::string &error)
{
    platform::TextReportFile csv((base / "haptics_bench.csv").string(), error);
    csv << "method,width,height,motion,updates,median_ns,p99_ns,p999_ns,max_ns,frame_cost_ns,"
           "force_rms_error_n,pop_throughs,psd_frame_rate_db,runs,min_of_runs_median_ns,"
           "min_of_runs_p99_ns,min_of_runs_p999_ns,force_error_p50_n,force_error_p95_n,"
           "force_error_p99_n,force_error_max_n,p999_min_over_runs_ns,p999_max_over_runs_ns,"
           "p999_spread_ratio,amortised_frame_cost_ns,median_plus_frame_ns\n";
    for (const BenchRow &r : report.rows) {
        char line[1024];
        std::snprintf(line, sizeof line,
                      "%s,%d,%d,%s,%zu,%.1f,%.1f,%.1f,%.1f,%.1f,%.6f,%ld,%s,%d,%.1f,%.1f,%.1f,"
                      "%.6f,%.6f,%.6f,%.6f,%.1f,%.1f,%.3f,%.1f,%.1f\n",
                      r.method.c_str(), r.width, r.height, r.motion.c_str(), r.updates, r.medianNs,
                      r.p99Ns, r.p999Ns, r.maxNs, r.frameCostNs, r.forceRmsError, r.popThroughs,
                      psdText(r.psdFrameRateDb, "").c_str(), r.runsTimed, r.minOfRunsMedianNs,
                      r.minOfRunsP99Ns, r.minOfRunsP999Ns, r.forceErrorP50, r.forceErrorP95,
                      r.forceErrorP99, r.forceErrorMax, r.p999MinOverRunsNs, r.p999MaxOverRunsNs,
                      p999SpreadRatio(r), amortisedFrameCostNs(r),
                      r.medianNs + amortisedFrameCostNs(r));
        csv << line;
    }
    return csv.close();
}

/// A JSON number, or null for NaN (not measured) and ±infinity (no power at all).
nlohmann::json number(double v)
{
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

/// One row of haptics_bench.json (the keys are the CSV's columns).
nlohmann::json rowJson(const BenchRow &r)
{
    return {{"method", r.method},
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
            {"min_of_runs_p999_ns", r.minOfRunsP999Ns},
            {"force_error_p50_n", r.forceErrorP50},
            {"force_error_p95_n", r.forceErrorP95},
            {"force_error_p99_n", r.forceErrorP99},
            {"force_error_max_n", r.forceErrorMax},
            {"p999_min_over_runs_ns", r.p999MinOverRunsNs},
            {"p999_max_over_runs_ns", r.p999MaxOverRunsNs},
            {"p999_spread_ratio", p999SpreadRatio(r)},
            {"amortised_frame_cost_ns", amortisedFrameCostNs(r)},
            {"median_plus_frame_ns", r.medianNs + amortisedFrameCostNs(r)}};
}

/// The "goals" object of haptics_bench.json.
nlohmann::json goalsJson(const BenchReport &report)
{
    return {
        {"modified_p999_ns_720x486_1mps", report.modifiedP999At720Fast},
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
        {"finger_friction_min_of_runs_median_ratio_720x486", report.fingerFrictionMinOfRunsRatio},
        {"modified_friction_median_ratio_720x486", report.modifiedFrictionRatio},
        {"modified_friction_min_of_runs_median_ratio_720x486",
         report.modifiedFrictionMinOfRunsRatio},
        {"finger_materials_median_ratio_720x486", report.fingerMaterialsRatio},
        {"finger_materials_min_of_runs_median_ratio_720x486", report.fingerMaterialsMinOfRunsRatio},
        {"modified_materials_median_ratio_720x486", report.modifiedMaterialsRatio},
        {"modified_materials_min_of_runs_median_ratio_720x486",
         report.modifiedMaterialsMinOfRunsRatio},
        {"finger_materials_p999_ns_720x486_1mps", report.fingerMaterialsP999At720Fast},
        {"finger_materials_min_of_runs_p999_ns_720x486_1mps",
         report.fingerMaterialsMinOfRunsP999At720Fast}};
}

/// haptics_bench.json: the rows, the goal figures and the machine's load. \return false (\a error
/// set) when the file could not be written.
bool writeReportJson(const BenchReport &report, const std::filesystem::path &base,
                     std::string &error)
{
    nlohmann::json rows = nlohmann::json::array();
    for (const BenchRow &r : report.rows)
        rows.push_back(rowJson(r));
    // A load or steal share that could not be read (−1) is null.
    auto load = [](double v) { return v >= 0.0 ? nlohmann::json(v) : nlohmann::json(); };
    const nlohmann::json machine = {{"load_1min_start", load(report.loadAtStart)},
                                    {"load_1min_end", load(report.loadAtEnd)},
                                    {"steal_percent", load(report.stealPercent)},
                                    {"cpus", report.cpus},
                                    {"loaded", loadedMachine(report)}};
    const nlohmann::json doc = {{"rows", rows}, {"goals", goalsJson(report)}, {"machine", machine}};
    platform::TextReportFile js((base / "haptics_bench.json").string(), error);
    js << doc.dump(2) << '\n';
    return js.close();
}

/// psd.csv: the PSD of |F| of `modified` and `modified-hold` at 720×486, HIP still.
void writePsdCsv(const BenchReport &report, const std::filesystem::path &base, std::string &error)
{
    platform::TextReportFile p((base / "psd.csv").string(), error);
    p << "hz,interpolated_db,sample_and_hold_db\n";
    const std::size_t n = std::min(report.psd.interpolatedDb.size(), report.psd.holdDb.size());
    for (std::size_t k = 1; k < n; ++k)
        p << static_cast<double>(k) * report.psd.binHz << ',' << report.psd.interpolatedDb[k] << ','
          << report.psd.holdDb[k] << '\n';
}

/// A series of the speed-vs-accuracy chart: the rows of one method, in one colour.
struct Series {
    std::string method;
    std::string colour; ///< gnuplot "#rrggbb"
};

/// The chart's series: the renderer table's rows and the sample-and-hold `modified-hold`.
std::vector<Series> chartSeries()
{
    static const char *const kPalette[] = {"#1f77b4", "#2ca02c", "#17becf", "#ff7f0e",
                                           "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"};
    std::vector<Series> out;
    for (const RendererEntry &e : rendererTable()) {
        out.push_back({e.name, ""});
        if (e.method == Method::Modified)
            out.push_back({"modified-hold", ""});
    }
    for (std::size_t i = 0; i < out.size(); ++i)
        out[i].colour = kPalette[i % std::size(kPalette)];
    return out;
}

/// The filled gnuplot point type of a depth width: circle 720, square 1920, triangle 3840. The
/// open shape of the same kind is this minus one.
int pointType(int width)
{
    return width <= 720 ? 7 : (width <= 1920 ? 5 : 9);
}

/// The motions of the rows, in panel order, with the panels' titles.
constexpr const char *kMotions[3][2] = {{"still", "HIP still"},
                                        {"0.1 m/s", "HIP stroking at 0.1 m/s"},
                                        {"1 m/s", "HIP stroking at 1 m/s"}};

/// The extent of the points of the speed-vs-accuracy chart: µs on x, N on y.
struct ChartRange {
    double xlo = kGoalP999Us, xhi = kGoalP999Us; ///< starts at the goal line, which is always drawn
    double ylo = 1e9, yhi = 1e-9;
};

/// The data block of \a s at the motion kMotions[\a m] for speed_vs_accuracy.dat: a line per row
/// with the p99.9 update time (µs; with \a amortised, plus amortisedFrameCostNs()), the force RMS
/// error (N), the point type (open with \a amortised) and the update-only time (µs). Empty when
/// the method has no row at that motion; \a range grows to its points.
std::string scatterBlock(const BenchReport &report, const Series &s, int m, bool amortised,
                         ChartRange &range)
{
    std::ostringstream pts;
    for (const BenchRow &r : report.rows) {
        if (r.method != s.method || r.motion != kMotions[m][0])
            continue;
        const double raw = r.p999Ns / 1000.0;
        const double x = amortised ? raw + amortisedFrameCostNs(r) / 1000.0 : raw;
        const double y = std::max(r.forceRmsError, 1e-6);
        pts << x << ' ' << y << ' ' << pointType(r.width) - (amortised ? 1 : 0) << ' ' << raw
            << '\n';
        range.xlo = std::min(range.xlo, raw);
        range.xhi = std::max(range.xhi, x);
        range.ylo = std::min(range.ylo, y);
        range.yhi = std::max(range.yhi, y);
    }
    return pts.str();
}

/// Into \a gp, the key panel of the speed-vs-accuracy chart: every colour, shape and line of the
/// three motion panels, named.
void writeKeyPanel(const std::vector<Series> &series, std::ostream &gp)
{
    gp << "unset arrow\nunset logscale\nunset border\nunset tics\nunset grid\nunset xlabel\n"
          "unset ylabel\nunset title\nset xrange [0:1]\nset yrange [0:1]\n"
          "set key center center box Left reverse spacing 1.4 title 'colour: renderer; shape: "
          "depth size; "
          "panel: HIP motion'\nplot NaN notitle";
    for (const Series &s : series) {
        gp << ", keyentry with points pt 7 ps 1.8 lc rgb '" << s.colour << "' title '" << s.method
           << "'";
        if (s.method == "mesh-bvh")
            gp << ", keyentry with points pt 6 ps 1.8 lw 2 lc rgb '" << s.colour
               << "' title 'mesh-bvh + rebuild amortised (open)', keyentry with lines dt 3 lc rgb '"
               << s.colour << "' title '  + its per-frame tree rebuild x 30 fps / 1 kHz'";
    }
    gp << ", keyentry with points pt 7 ps 1.8 lc rgb 'black' title 'circle: 720x486 depth'"
          ", keyentry with points pt 5 ps 1.8 lc rgb 'black' title 'square: 1920x1080 depth'"
          ", keyentry with points pt 9 ps 1.8 lc rgb 'black' title 'triangle: 3840x2160 depth'"
          ", keyentry with lines dt 2 lw 2 lc rgb '#d62728' title 'goal: update p99.9 <= 2 us "
          "(docs/benchmarks.md)'\nunset multiplot\n";
}

/// speed_vs_accuracy.dat (scatterBlock(): a block per method and motion, and for mesh-bvh one
/// more with its rebuild amortised) and, into \a gp, the multiplot drawing it: a panel per HIP
/// motion, a colour per method, a shape per depth resolution, the goal line, and a key panel.
void writeSpeedChart(const BenchReport &report, const std::filesystem::path &base,
                     std::string &error, std::ostream &gp)
{
    const std::string dat = (base / "speed_vs_accuracy.dat").string();
    platform::TextReportFile d(dat, error);
    const std::vector<Series> series = chartSeries();
    ChartRange range;
    std::string panels[3];
    int block = 0; // gnuplot's index counts the blocks with data: empty ones are not written
    for (int m = 0; m < 3; ++m)
        for (const Series &s : series)
            for (const bool amortised : {false, true}) {
                if (amortised && s.method != "mesh-bvh")
                    continue;
                const std::string pts = scatterBlock(report, s, m, amortised, range);
                if (pts.empty())
                    continue;
                d << "# " << s.method << (amortised ? " + rebuild amortised, " : ", ")
                  << kMotions[m][0] << '\n'
                  << pts << "\n\n";
                std::string &p = panels[m];
                const std::string idx = "'" + dat + "' index " + std::to_string(block++);
                if (amortised)
                    p += (p.empty() ? "" : ", ") + idx +
                         " using 4:2:($1-$4):(0) with vectors dt 3 lc rgb '" + s.colour +
                         "' notitle";
                p += (p.empty() ? "" : ", ") + idx +
                     " using 1:2:3 with points pt variable ps 1.8 lw 2 lc rgb '" + s.colour +
                     "' notitle";
            }
    if (range.ylo > range.yhi)
        range.ylo = range.yhi = 1.0;
    char head[1024];
    std::snprintf(
        head, sizeof head,
        "set terminal pngcairo size 1500,1050 noenhanced\nset output '%s'\n"
        "set multiplot layout 2,2 title \"Haptic renderers: update time vs force error (moving "
        "sinusoid, 30 fps depth video, 1 kHz servo; haptics_bench.csv)%s\"\n"
        "set logscale xy\nset xrange [%g:%g]\nset yrange [%g:%g]\nset grid\nunset key\n"
        "set xlabel 'update time p99.9 (us; median over the runs)'\n"
        "set ylabel 'force RMS error vs analytic truth (N)'\n"
        "set arrow 1 from %g, graph 0 to %g, graph 1 nohead dt 2 lw 2 lc rgb '#d62728'\n",
        (base / "speed_vs_accuracy.png").string().c_str(),
        loadedMachine(report) ? "\\nTIMED ON A LOADED MACHINE (see haptics_bench.json: machine)"
                              : "",
        range.xlo / 1.6, range.xhi * 1.6, range.ylo / 1.6, range.yhi * 1.6, kGoalP999Us,
        kGoalP999Us);
    gp << head;
    for (int m = 0; m < 3; ++m) {
        gp << "set title '" << kMotions[m][1] << "'\n";
        gp << (panels[m].empty() ? "plot NaN notitle" : "plot " + panels[m]) << '\n';
    }
    writeKeyPanel(series, gp);
}

/// Into \a gp, the PSD chart: |F| of the modified renderer at 720×486, HIP still, with
/// interpolated frames and with sample-and-hold ones.
void writePsdChart(const std::filesystem::path &base, std::ostream &gp)
{
    gp << "reset\nset terminal pngcairo size 1100,700 noenhanced\nset output '"
       << (base / "psd.png").string()
       << "'\nset title \"PSD of |F|: the modified renderer (proxy graph with the paper's fixes), "
          "720x486 depth, HIP still\\n(30 fps video, 1 kHz servo): interpolated frames vs "
          "sample-and-hold; cf. paper Fig. 12\"\n"
          "set xlabel 'frequency (Hz)'\nset ylabel 'PSD (dB re 1 N^2/Hz)'\nset xrange [0:100]\n"
          "set grid\nset datafile separator ','\nplot '"
       << (base / "psd.csv").string()
       << "' using 1:3 with lines lw 2 title 'modified-hold: sample-and-hold frames', '' using "
          "1:2 with lines lw 2 title 'modified: interpolated frames (Eq. 1)'\n";
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
    writePsdCsv(report, base, error);
    {
        platform::TextReportFile g((base / "charts.gp").string(), error);
        writeSpeedChart(report, base, error, g);
        writePsdChart(base, g);
    }
    if (!error.empty())
        return false;
    // Charts with gnuplot, when it is installed.
    const platform::PlotStatus plot = platform::runGnuplot((base / "charts.gp").string());
    if (plot != platform::PlotStatus::Drawn)
        note = std::string(platform::plotStatusNote(plot)) + "; CSV and JSON written";
    return true;
}

} // namespace depthtouch::haptics::bench
