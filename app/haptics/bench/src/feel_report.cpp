/// \file
/// \brief `depthtouch bench feel`'s outputs: the table and goals on stdout, CSV, JSON and the
/// gnuplot chart (see feel_bench.h).

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "depthtouch/haptics/feel_bench.h"
#include "depthtouch/platform/gnuplot.h"
#include "depthtouch/platform/report_file.h"

namespace depthtouch::haptics::bench {

namespace {

void printRow(const FeelRow &r)
{
    const FeelFigures &f = r.total;
    std::printf(
        "%-18s %-17s %3zu %7.2f %6.2f %8.1f %8.1f %7.2f %7.1f %7.3f %6.1f %6.2f %6.2f %7.2f\n",
        r.scene.c_str(), r.setting.c_str(), r.strokes, f.falseTripsPerSecond, r.realTripsPerSecond,
        f.popThroughMs, f.phantomMs, f.spikesPerSecond, r.worstSpikesPerSecond, f.rippleRms,
        100.0 * f.rippleRelative, f.maxForce, f.updateP50 * 1e6, f.updateP999 * 1e6);
}

const char *verdict(bool ok) { return ok ? "met" : "NOT met"; }

struct GoalCheck {
    bool falseTrips, pop, phantom, spikes, worst, force;
    [[nodiscard]] bool all() const
    {
        return falseTrips && pop && phantom && spikes && worst && force;
    }
};

GoalCheck check(const FeelRow &r, const FeelGoals &g)
{
    const FeelFigures &f = r.total;
    return {f.falseTrips == 0,
            f.popThroughMs <= g.maxPopThroughMs,
            f.phantomMs <= g.maxPhantomMs,
            f.spikesPerSecond <= g.maxSpikesPerSecond,
            r.worstSpikesPerSecond <= g.maxStrokeSpikesPerSecond,
            f.maxForce <= g.deviceMaxForce * (1.0 + 1e-9)};
}

nlohmann::json rowJson(const FeelRow &r)
{
    const FeelFigures &f = r.total;
    return {{"scene", r.scene},
            {"setting", r.setting},
            {"strokes", r.strokes},
            {"seconds", f.seconds},
            {"sliding_seconds", f.slidingSeconds},
            {"updates", f.updates},
            {"trips", f.trips},
            {"real_cut_trips", f.realCutTrips},
            {"false_trips", f.falseTrips},
            {"false_trips_per_s", f.falseTripsPerSecond},
            {"real_trips_per_s", r.realTripsPerSecond},
            {"pop_through_ms", f.popThroughMs},
            {"phantom_ms", f.phantomMs},
            {"spikes", f.spikes},
            {"spikes_per_s", f.spikesPerSecond},
            {"worst_stroke_spikes_per_s", r.worstSpikesPerSecond},
            {"worst_stroke", r.worstStroke},
            {"ripple_rms_n", f.rippleRms},
            {"ripple_relative", f.rippleRelative},
            {"max_force_n", f.maxForce},
            {"update_p50_us", f.updateP50 * 1e6},
            {"update_p999_us", f.updateP999 * 1e6}};
}

void writeRowsCsv(std::ofstream &c, const std::vector<FeelRow> &rows)
{
    for (const FeelRow &r : rows) {
        const FeelFigures &f = r.total;
        c << r.scene << ',' << r.setting << ',' << r.strokes << ',' << f.seconds << ','
          << f.slidingSeconds << ',' << f.trips << ',' << f.realCutTrips << ',' << f.falseTrips
          << ',' << f.falseTripsPerSecond << ',' << r.realTripsPerSecond << ',' << f.popThroughMs
          << ',' << f.phantomMs << ',' << f.spikes << ',' << f.spikesPerSecond << ','
          << r.worstSpikesPerSecond << ',' << f.rippleRms << ',' << f.rippleRelative << ','
          << f.maxForce << ',' << f.updateP50 * 1e6 << ',' << f.updateP999 * 1e6 << '\n';
    }
}

/// The chart: six panels of feel against the p99.9 update time, one point per setting (all scenes),
/// one colour per setting, the key below the panels; zero is drawn at the bottom of the log axes.
void writeChartScript(const FeelReport &report, const std::filesystem::path &base)
{
    {
        std::ofstream d(base / "feel_chart.dat");
        for (const FeelRow &r : report.totals) {
            const FeelFigures &f = r.total;
            d << "# " << r.setting << '\n'
              << std::max(f.updateP999 * 1e6, 1e-3) << ' ' << f.falseTripsPerSecond << ' '
              << f.popThroughMs << ' ' << f.phantomMs << ' ' << f.spikesPerSecond << ' '
              << r.worstSpikesPerSecond << ' ' << 100.0 * f.rippleRelative << "\n\n\n";
        }
    }
    std::string names;
    for (const FeelRow &r : report.totals)
        names += (names.empty() ? "" : " ") + r.setting;
    const std::string dat = (base / "feel_chart.dat").string();
    const FeelGoals &g = report.goals;
    std::ofstream s(base / "feel.gp");
    s << "set terminal pngcairo size 1500,1000 font ',11'\n"
      << "set output '" << (base / "feel_vs_speed.png").string() << "'\n"
      << "names = '" << names << "'\nn = words(names)\nfloor = 0.01\n"
      << "set multiplot layout 2,3 title 'bench feel: feel against update time, all scenes and "
         "strokes "
         "(one point per renderer setting; dashed: goal; lower is better; 0 drawn at the bottom)' "
         "margins 0.06,0.98,0.21,0.91 spacing 0.07,0.13\n"
      << "set logscale xy\nset grid\nset xlabel 'update time p99.9 (us)'\nset format y '%g'\n"
      << "set ytics add ('0' floor)\nset yrange [floor / 2:*]\nset offsets graph 0.1, graph 0.1, "
         "graph 0.1, 0\n"
      << "unset key\n";
    const struct {
        int col;
        const char *title;
        double goal;
    } panels[] = {{2, "false safety trips per s of sliding", 0.0},
                  {3, "pop-through (ms, summed)", g.maxPopThroughMs},
                  {4, "phantom force (ms, summed)", g.maxPhantomMs},
                  {5, "force spikes per s of sliding (mean)", g.maxSpikesPerSecond},
                  {6, "force spikes per s, worst stroke", g.maxStrokeSpikesPerSecond},
                  {7, "ripple while held (% of mean |F|, no goal)", -1.0}};
    bool first = true;
    for (const auto &p : panels) {
        s << "set title '" << p.title << "'\n";
        if (first)
            s << "set key at screen 0.5, screen 0.075 center center horizontal maxcols 8 maxrows 1 "
                 "box samplen 1 width 1\n";
        s << "plot for [i=0:n-1] '" << dat
          << "' index i using 1:($" << p.col << " > floor ? $" << p.col
          << " : floor) with points pt 7 ps 2.2 lc i+1 title word(names, i+1)";
        if (p.goal >= 0.0)
            s << ", " << std::max(p.goal, 0.01) << " with lines dt 2 lc 'black' notitle";
        s << '\n';
        if (first) {
            s << "unset key\n";
            first = false;
        }
    }
    s << "unset multiplot\n";
}

} // namespace

void printFeelReport(const FeelReport &report)
{
    std::printf("%-18s %-17s %3s %7s %6s %8s %8s %7s %7s %7s %6s %6s %6s %7s\n", "scene", "setting",
                "n", "false/s", "real/s", "pop ms", "phan ms", "spk/s", "worst", "ripl N", "ripl%",
                "max|F|", "p50us", "p99.9us");
    std::string scene;
    for (const FeelRow &r : report.rows) {
        if (!scene.empty() && r.scene != scene)
            std::printf("\n");
        scene = r.scene;
        printRow(r);
    }
    std::printf("\n");
    for (const FeelRow &r : report.totals)
        printRow(r);
    for (const std::string &n : report.notes)
        std::printf("note: %s\n", n.c_str());
    const FeelGoals &g = report.goals;
    std::printf(
        "\ngoals (all scenes; pop-through and phantom each summed over all strokes): 0 false "
        "trips, "
        "pop-through <= %.0f ms, phantom <= %.0f ms, <= %.0f spikes/s mean and <= %.0f on any "
        "stroke, max |F| <= %.1f N\n",
        g.maxPopThroughMs, g.maxPhantomMs, g.maxSpikesPerSecond, g.maxStrokeSpikesPerSecond,
        g.deviceMaxForce);
    for (const FeelRow &r : report.totals) {
        const GoalCheck c = check(r, g);
        const FeelFigures &f = r.total;
        std::printf("  %-17s false trips %zu: %s | pop-through %.1f ms: %s | phantom %.1f ms: %s | "
                    "spikes %.2f/s: %s"
                    " | worst stroke %.1f/s: %s | max |F| %.2f N: %s => %s\n",
                    r.setting.c_str(), f.falseTrips, verdict(c.falseTrips), f.popThroughMs,
                    verdict(c.pop), f.phantomMs, verdict(c.phantom), f.spikesPerSecond,
                    verdict(c.spikes), r.worstSpikesPerSecond, verdict(c.worst), f.maxForce,
                    verdict(c.force), c.all() ? "ALL MET" : "not all met");
    }
}

bool writeFeelOutputs(const FeelReport &report, const std::string &dir, std::string &error,
                      std::string &note)
{
    namespace fs = std::filesystem;
    const fs::path base(dir);
    if (!platform::createReportFolder(dir, "cannot create " + dir, error))
        return false;
    {
        std::ofstream c(base / "feel.csv");
        c << "scene,setting,strokes,seconds,sliding_s,trips,real_cut_trips,false_trips,false_trips_"
             "per_s,"
             "real_trips_per_s,pop_through_ms,phantom_ms,spikes,spikes_per_s,worst_stroke_spikes_"
             "per_s,"
             "ripple_rms_n,ripple_relative,max_force_n,update_p50_us,update_p999_us\n";
        writeRowsCsv(c, report.rows);
        writeRowsCsv(c, report.totals);
        std::ofstream k(base / "feel_strokes.csv");
        k << "scene,setting,stroke,kind,trips,real_cut_trips,pop_through_ms,phantom_ms,spikes,"
             "spikes_per_s,"
             "ripple_rms_n,max_force_n,update_p999_us\n";
        for (const FeelStrokeResult &r : report.strokes) {
            const FeelFigures &f = r.figures;
            k << r.scene << ',' << r.setting << ",\"" << r.stroke << "\"," << strokeKindName(r.kind)
              << ',' << f.trips << ',' << f.realCutTrips << ',' << f.popThroughMs << ','
              << f.phantomMs << ',' << f.spikes << ',' << f.spikesPerSecond << ',' << f.rippleRms
              << ',' << f.maxForce << ',' << f.updateP999 * 1e6 << '\n';
        }
        if (!c || !k) {
            error = "failed to write feel.csv or feel_strokes.csv in " + dir;
            return false;
        }
    }
    {
        nlohmann::json rows = nlohmann::json::array();
        nlohmann::json totals = nlohmann::json::array();
        for (const FeelRow &r : report.rows)
            rows.push_back(rowJson(r));
        for (const FeelRow &r : report.totals) {
            nlohmann::json j = rowJson(r);
            const GoalCheck c = check(r, report.goals);
            j["goals_met"] = {{"false_trips", c.falseTrips},
                              {"pop_through", c.pop},
                              {"phantom", c.phantom},
                              {"spikes", c.spikes},
                              {"worst_stroke", c.worst},
                              {"max_force", c.force},
                              {"all", c.all()}};
            totals.push_back(j);
        }
        const FeelGoals &g = report.goals;
        const nlohmann::json doc = {{"rows", rows},
                                    {"totals", totals},
                                    {"notes", report.notes},
                                    {"replay_seconds", report.seconds},
                                    {"goals",
                                     {{"false_trips", 0},
                                      {"pop_through_ms", g.maxPopThroughMs},
                                      {"phantom_ms", g.maxPhantomMs},
                                      {"spikes_per_s", g.maxSpikesPerSecond},
                                      {"worst_stroke_spikes_per_s", g.maxStrokeSpikesPerSecond},
                                      {"max_force_n", g.deviceMaxForce}}}};
        std::ofstream js(base / "feel.json");
        js << doc.dump(2) << '\n';
        if (!js) {
            error = "failed to write feel.json in " + dir;
            return false;
        }
    }
    writeChartScript(report, base);
    const platform::PlotStatus plot = platform::runGnuplot((base / "feel.gp").string());
    if (plot != platform::PlotStatus::Drawn)
        note = std::string(platform::plotStatusNote(plot)) + "; CSV and JSON written";
    return true;
}

} // namespace depthtouch::haptics::bench
