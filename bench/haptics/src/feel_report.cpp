/// \file
/// \brief `depthtouch bench feel`'s outputs: the table and goals on stdout, CSV, JSON and the
/// gnuplot chart (see feel_bench.h).

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
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

const char *verdict(bool ok)
{
    return ok ? "met" : "NOT met";
}

/// The figures new with the stroke families, per row (table, CSV and JSON share the order).
void printFamilyRow(const FeelRow &r)
{
    const FeelFigures &f = r.total;
    char regain[32] = "-";
    if (f.regainEvents > 0)
        std::snprintf(regain, sizeof regain, "%.0f(%zu/%zu)", f.regainMs, f.regainMissed,
                      f.regainEvents);
    std::printf("%-26s %-17s %-6s %3zu %4zu %8.1f %7.1f %4zu %6.2f %7.2f %7.2f %-12s %6.1f %6.2f "
                "%7.3f %7.3f %6.2f\n",
                r.scene.c_str(), r.setting.c_str(), r.family.c_str(), r.strokes, f.falseTrips,
                f.popThroughMs, f.phantomMs, f.longestAlternation, f.reversalSpikesPerSecond,
                f.pressedSpikesPerSecond, f.idealSpikesPerSecond, regain, f.atMaxMs, f.maxForce,
                f.energyExcessMj, f.energyMj, f.updateP999 * 1e6);
}

nlohmann::json figuresJson(const FeelFigures &f)
{
    const double ratio = f.spikeRatio();
    return {{"pressed_seconds", f.pressedSeconds},
            {"pressed_spikes", f.pressedSpikes},
            {"pressed_spikes_per_s", f.pressedSpikesPerSecond},
            {"ideal_spikes", f.idealSpikes},
            {"ideal_spikes_per_s", f.idealSpikesPerSecond},
            {"spikes_over_ideal", std::isnan(ratio) ? nlohmann::json() : nlohmann::json(ratio)},
            {"sign_reversal_spikes", f.reversalSpikes},
            {"sign_reversal_spikes_per_s", f.reversalSpikesPerSecond},
            {"longest_alternating_run", f.longestAlternation},
            {"ideal_longest_alternating_run", f.idealLongestAlternation},
            {"regain_events", f.regainEvents},
            {"regain_missed", f.regainMissed},
            {"regain_ms", f.regainMs},
            {"at_max_ms", f.atMaxMs},
            {"pull_down_ms", f.pullDownMs},
            {"arrival_trips", f.arrivalTrips},
            {"covered_ms", f.coveredMs},
            {"energy_mj", f.energyMj},
            {"ideal_energy_mj", f.idealEnergyMj},
            {"energy_excess_mj",
             std::isnan(f.energyExcessMj) ? nlohmann::json() : nlohmann::json(f.energyExcessMj)},
            {"energy_peak_mj", f.energyPeakMj},
            {"max_step_n", f.maxStepN}};
}

/// The CSV columns of figuresJson(), in order.
constexpr const char *kFamilyColumns =
    "pressed_s,pressed_spikes,pressed_spikes_per_s,ideal_spikes,ideal_spikes_per_s,"
    "spikes_over_ideal,sign_reversal_spikes,sign_reversal_spikes_per_s,longest_alternating_run,"
    "ideal_longest_alternating_run,regain_events,regain_missed,regain_ms,at_max_ms,pull_down_ms,"
    "arrival_trips,covered_ms,"
    "energy_mj,ideal_energy_mj,energy_excess_mj,energy_peak_mj,max_step_n";

void writeFamilyCsv(std::ostream &c, const FeelFigures &f)
{
    const double ratio = f.spikeRatio();
    c << f.pressedSeconds << ',' << f.pressedSpikes << ',' << f.pressedSpikesPerSecond << ','
      << f.idealSpikes << ',' << f.idealSpikesPerSecond << ',';
    if (!std::isnan(ratio))
        c << ratio;
    c << ',' << f.reversalSpikes << ',' << f.reversalSpikesPerSecond << ',' << f.longestAlternation
      << ',' << f.idealLongestAlternation << ',' << f.regainEvents << ',' << f.regainMissed << ','
      << f.regainMs << ',' << f.atMaxMs << ',' << f.pullDownMs << ',' << f.arrivalTrips << ','
      << f.coveredMs << ',' << f.energyMj << ',' << f.idealEnergyMj << ',';
    if (!std::isnan(f.energyExcessMj))
        c << f.energyExcessMj;
    c << ',' << f.energyPeakMj << ',' << f.maxStepN;
}

/// True for the scenes made from real captures (not "synthetic-...").
bool realScene(const std::string &scene)
{
    return scene.rfind("synthetic", 0) != 0;
}

/// The chart's figures of one setting.
struct ChartPoint {
    std::string setting;
    double cleanRms = 0.0; ///< N.
    /// Spikes per second pressed, the worst hold, tap or press family × scene row (the figure of
    /// the goal the panel draws; swipes, circles and traces have the ideal penalty's as theirs).
    double worstSpikes = 0.0;
    std::string spikesWhere;
    double worstPop = 0.0; ///< ms, the pop-through goal's worst row.
    double p999 = 0.0;     ///< µs.
    int goalsMet = 0;
    int goals = 0;
};

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

void writeRowsCsv(std::ostream &c, const std::vector<FeelRow> &rows)
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

/// The chart's points: one per setting; \a real says whether there is a real clip among the scenes.
std::vector<ChartPoint> chartPoints(const FeelReport &report, bool &real)
{
    real = false;
    for (const FeelRow &r : report.familyRows)
        real = real || realScene(r.scene);
    std::vector<ChartPoint> out;
    for (const FeelRow &t : report.totals) {
        ChartPoint p;
        p.setting = t.setting;
        p.cleanRms = std::nan("");
        for (const auto &[name, rms] : report.cleanRms)
            if (name == t.setting)
                p.cleanRms = rms;
        p.p999 = t.total.updateP999 * 1e6;
        // The robustness panels draw the figures the goals judge (their worst family x scene row
        // over every clip and synthetic scene), so that a point on or over a goal line is a goal
        // the printed verdicts say is not met.
        for (const GoalVerdict &v : judgeGoals(report.familyRows, t.setting, report.goals)) {
            ++p.goals;
            p.goalsMet += v.met ? 1 : 0;
            if (v.goal.rfind("spikes <=", 0) == 0) {
                p.worstSpikes = v.worst;
                p.spikesWhere = v.where;
            } else if (v.goal.rfind("pop-through", 0) == 0) {
                p.worstPop = v.worst;
            }
        }
        out.push_back(p);
    }
    return out;
}

const char *methodColor(const std::string &setting)
{
    if (setting.rfind("finger", 0) == 0)
        return "#1f5fbf";
    if (setting.rfind("modified", 0) == 0)
        return "#c8321e";
    if (setting.rfind("proxy-graph", 0) == 0)
        return "#2a9d3a";
    return "#7b3fa0";
}

/// One axis of a panel, mapped to graph coordinates [0, 1] (so that labels can be placed).
struct Axis {
    double lo = 0.0;
    double hi = 1.0;
    bool log = false;
    [[nodiscard]] double graph(double v) const
    {
        return log ? (std::log(v) - std::log(lo)) / (std::log(hi) - std::log(lo))
                   : (v - lo) / (hi - lo);
    }
};

Axis logAxis(std::vector<double> v, double floor, double goal)
{
    double lo = goal > 0.0 ? goal : (v.empty() ? floor : std::max(v.front(), floor));
    double hi = lo;
    for (double x : v) {
        x = std::max(x, floor);
        lo = std::min(lo, x);
        hi = std::max(hi, x);
    }
    return {lo / 2.5, hi * 2.5, true};
}

/// Places one label per point in graph coordinates so that no two labels, no label and point and
/// no label and the goal line's own label (left-aligned at graph x 0.01 just above \a goalY,
/// \a goalChars characters at 9 pt) overlap (greedy over candidate offsets, nearest first).
/// \return the label centres' left ends.
std::vector<std::pair<double, double>>
placeLabels(const std::vector<std::pair<double, double>> &pts, const std::vector<std::string> &text,
            double goalY, std::size_t goalChars)
{
    constexpr double kCharW = 0.017; // graph units per character (a 520 px panel, 10 pt font)
    constexpr double kH = 0.05;
    struct Box {
        double x0, y0, x1, y1;
    };
    std::vector<Box> taken;
    taken.push_back({0.0, goalY, 0.01 + 0.9 * kCharW * static_cast<double>(goalChars), goalY + kH});
    for (const auto &[x, y] : pts)
        taken.push_back({x - 0.012, y - 0.018, x + 0.012, y + 0.018});
    std::vector<std::pair<double, double>> out;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const double w = kCharW * static_cast<double>(text[i].size());
        const auto [px, py] = pts[i];
        Box best{};
        bool found = false;
        for (int ring = 0; ring < 12 && !found; ++ring) {
            const double dy = 0.035 + 0.05 * ring;
            for (const auto &[ox, oy] :
                 {std::pair{0.026, 0.0}, std::pair{-0.026 - w, 0.0}, std::pair{0.026, dy},
                  std::pair{0.026, -dy}, std::pair{-0.026 - w, dy}, std::pair{-0.026 - w, -dy}}) {
                if (ring > 0 && oy == 0.0)
                    continue;
                const Box b{px + ox, py + oy - 0.5 * kH, px + ox + w, py + oy + 0.5 * kH};
                if (b.x0 < 0.0 || b.x1 > 1.0 || b.y0 < 0.0 || b.y1 > 1.0)
                    continue;
                bool clear = true;
                for (const Box &t : taken)
                    clear = clear && (b.x1 <= t.x0 || b.x0 >= t.x1 || b.y1 <= t.y0 || b.y0 >= t.y1);
                if (clear) {
                    best = b;
                    found = true;
                    break;
                }
            }
        }
        if (!found)
            best = {px + 0.026, py - 0.5 * kH, px + 0.026 + w, py + 0.5 * kH};
        taken.push_back(best);
        out.emplace_back(best.x0, 0.5 * (best.y0 + best.y1));
    }
    return out;
}

/// One panel of the chart: a goal line and one labelled point per setting.
struct Panel {
    std::string title, ylabel, xlabel;
    Axis x, y;
    std::vector<double> xv, yv;
    double goal;
    std::string goalText;
    double floor;
};

/// Writes panel \a p of the chart of \a pts (\a maxP: the largest update p99.9) to \a s.
void writePanel(std::ostream &s, const Panel &p, const std::vector<ChartPoint> &pts, double maxP)
{
    s << "set title '" << p.title << "'\nset xlabel '" << p.xlabel << "'\nset ylabel '" << p.ylabel
      << "'\nunset label\nunset arrow\n";
    s << (p.x.log ? "set logscale x\n" : "unset logscale x\n")
      << (p.y.log ? "set logscale y\n" : "unset logscale y\n");
    s << "set xrange [" << p.x.lo << ':' << p.x.hi << "]\nset yrange [" << p.y.lo << ':' << p.y.hi
      << "]\n";
    if (p.y.log)
        s << "set ytics add ('0' " << p.floor << ")\n";
    else
        s << "set ytics 1\n";
    s << "set arrow from graph 0, first " << p.goal << " to graph 1, first " << p.goal
      << " nohead dt 2 lw 1.5 lc 'black'\n"
      << "set label '" << p.goalText << "' at graph 0.01, first " << p.goal
      << " offset 0,0.7 left font ',9'\n";
    std::vector<std::pair<double, double>> gp;
    std::vector<std::string> names;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        gp.emplace_back(p.x.graph(p.xv[i]), p.y.graph(p.yv[i]));
        names.push_back(pts[i].setting);
    }
    const auto labels = placeLabels(gp, names, p.y.graph(p.goal), p.goalText.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
        s << "set label '" << names[i] << "' at graph " << labels[i].first << ", graph "
          << labels[i].second << " left front tc rgb '" << methodColor(names[i]) << "'\n";
        s << "set arrow from graph " << gp[i].first << ", graph " << gp[i].second << " to graph "
          << (labels[i].first < gp[i].first
                  ? labels[i].first + 0.017 * static_cast<double>(names[i].size())
                  : labels[i].first)
          << ", graph " << labels[i].second << " nohead lw 0.5 lc rgb '#999999'\n";
    }
    s << "$pts << EOD\n";
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const double ps = 1.2 + 2.3 * std::sqrt(std::max(pts[i].p999, 0.0) / maxP);
        unsigned color = 0;
        std::sscanf(methodColor(pts[i].setting) + 1, "%x", &color);
        s << p.xv[i] << ' ' << p.yv[i] << ' ' << ps << ' ' << color << '\n';
    }
    s << "EOD\nplot $pts using 1:2:3:4 with points pt 7 ps variable lc rgb variable\n";
}

/// The chart: which renderer setting is both accurate and robust, and at what cost. Three panels,
/// one labelled point per setting, point size growing with the update's p99.9: force RMS error on
/// clean geometry against (1) the worst family × clip spikes per second on the real clips and (2)
/// the worst pop-through there; (3) goals met against the update time.
/// \return false (\a error set) when it could not be written.
bool writeChartScript(const FeelReport &report, const std::filesystem::path &base,
                      std::string &error)
{
    bool real = false;
    const std::vector<ChartPoint> pts = chartPoints(report, real);
    const FeelGoals &g = report.goals;
    platform::TextReportFile s((base / "feel.gp").string(), error);
    s << "set terminal pngcairo size 1800,720 font ',10'\n"
      << "set output '" << (base / "feel.png").string() << "'\n"
      << "set multiplot layout 1,3 title \"bench feel: accuracy on clean geometry against "
         "robustness "
      << (real ? "on the clips and synthetic scenes"
               : "on the synthetic scenes (no real clip found)")
      << ", and cost; one point per setting, its size the update p99.9; better: lower left, lower "
         "left, upper left\" font ',12' margins 0.05,0.98,0.12,0.9 spacing 0.06,0.1\n"
      << "set grid\nunset key\n";
    double maxP = 1e-3;
    for (const ChartPoint &p : pts)
        maxP = std::max(maxP, p.p999);
    std::vector<double> xs;
    std::vector<double> cost;
    for (const ChartPoint &p : pts) {
        xs.push_back(std::isnan(p.cleanRms) ? 1e-3 : p.cleanRms);
        cost.push_back(std::max(p.p999, 1e-2));
    }
    const Axis xClean = logAxis(xs, 1e-3, -1.0);
    std::vector<double> spikes;
    std::vector<double> pops;
    std::vector<double> met;
    for (const ChartPoint &p : pts) {
        spikes.push_back(std::max(p.worstSpikes, 0.1));
        pops.push_back(std::max(p.worstPop, 0.1));
        met.push_back(p.goalsMet);
    }
    const int goals = pts.empty() ? 9 : pts.front().goals;
    char goalSpikes[96];
    std::snprintf(goalSpikes, sizeof goalSpikes, "goal: <= %.0f spikes/s (holds, taps, presses)",
                  g.maxStillSpikesPerSecond);
    char goalPop[64];
    std::snprintf(goalPop, sizeof goalPop, "goal: pop-through <= %.0f ms", g.maxPopThroughMs);
    const std::vector<Panel> panels = {
        {"robustness: force spikes, worst hold, tap or press row (as the goal judges)",
         "spikes per s pressed (0 drawn at 0.1)", "force RMS error on clean synthetic surfaces (N)",
         xClean, logAxis(spikes, 0.1, g.maxStillSpikesPerSecond), xs, spikes,
         g.maxStillSpikesPerSecond, goalSpikes, 0.1},
        {"robustness: pop-through, worst family x scene row (as the goal judges)",
         "pop-through (ms, 0 drawn at 0.1)", "force RMS error on clean synthetic surfaces (N)",
         xClean, logAxis(pops, 0.1, g.maxPopThroughMs), xs, pops, g.maxPopThroughMs, goalPop, 0.1},
        {"cost: goals met against the update time", "goals met (of " + std::to_string(goals) + ")",
         "update time p99.9 (us)", logAxis(cost, 1e-2, -1.0), Axis{-0.5, goals + 0.7, false}, cost,
         met, static_cast<double>(goals), "all goals met", 0.0},
    };
    for (const Panel &p : panels)
        writePanel(s, p, pts, maxP);
    s << "set origin 0,0\nset size 1,1\nunset multiplot\n";
    return s.close();
}

/// feel.csv, feel_strokes.csv and feel_families.csv in \a base.
bool writeFeelCsvs(const FeelReport &report, const std::filesystem::path &base, std::string &error)
{
    platform::TextReportFile c((base / "feel.csv").string(), error);
    c << "scene,setting,strokes,seconds,sliding_s,trips,real_cut_trips,false_trips,false_trips_"
         "per_s,"
         "real_trips_per_s,pop_through_ms,phantom_ms,spikes,spikes_per_s,worst_stroke_spikes_"
         "per_s,"
         "ripple_rms_n,ripple_relative,max_force_n,update_p50_us,update_p999_us\n";
    writeRowsCsv(c, report.rows);
    writeRowsCsv(c, report.totals);
    platform::TextReportFile k((base / "feel_strokes.csv").string(), error);
    k << "scene,setting,stroke,kind,family,where,trips,real_cut_trips,pop_through_ms,"
         "phantom_ms,spikes,spikes_per_s,ripple_rms_n,max_force_n,update_p999_us,"
      << kFamilyColumns << '\n';
    for (const FeelStrokeResult &r : report.strokes) {
        const FeelFigures &f = r.figures;
        k << r.scene << ',' << r.setting << ",\"" << r.stroke << "\"," << strokeKindName(r.kind)
          << ',' << strokeFamilyName(r.family) << ',' << r.where << ',' << f.trips << ','
          << f.realCutTrips << ',' << f.popThroughMs << ',' << f.phantomMs << ',' << f.spikes << ','
          << f.spikesPerSecond << ',' << f.rippleRms << ',' << f.maxForce << ','
          << f.updateP999 * 1e6 << ',';
        writeFamilyCsv(k, f);
        k << '\n';
    }
    platform::TextReportFile fam((base / "feel_families.csv").string(), error);
    fam << "scene,setting,family,strokes,false_trips,pop_through_ms,phantom_ms,max_force_n,"
           "update_p50_us,update_p999_us,"
        << kFamilyColumns << '\n';
    for (const FeelRow &r : report.familyRows) {
        const FeelFigures &f = r.total;
        fam << r.scene << ',' << r.setting << ',' << r.family << ',' << r.strokes << ','
            << f.falseTrips << ',' << f.popThroughMs << ',' << f.phantomMs << ',' << f.maxForce
            << ',' << f.updateP50 * 1e6 << ',' << f.updateP999 * 1e6 << ',';
        writeFamilyCsv(fam, f);
        fam << '\n';
    }
    const bool written = c.close();
    return k.close() && fam.close() && written;
}

/// feel.json in \a base (the folder \a dir).
bool writeFeelJson(const FeelReport &report, const std::filesystem::path &base, std::string &error)
{
    nlohmann::json rows = nlohmann::json::array();
    nlohmann::json familyRows = nlohmann::json::array();
    nlohmann::json totals = nlohmann::json::array();
    for (const FeelRow &r : report.rows)
        rows.push_back(rowJson(r));
    for (const FeelRow &r : report.familyRows) {
        nlohmann::json j = rowJson(r);
        j["family"] = r.family;
        j.update(figuresJson(r.total));
        familyRows.push_back(j);
    }
    for (const FeelRow &r : report.totals) {
        nlohmann::json j = rowJson(r);
        j.update(figuresJson(r.total));
        nlohmann::json verdicts = nlohmann::json::array();
        bool all = true;
        for (const GoalVerdict &v : judgeGoals(report.familyRows, r.setting, report.goals)) {
            verdicts.push_back(
                {{"goal", v.goal}, {"worst", v.worst}, {"where", v.where}, {"met", v.met}});
            if (!std::isnan(v.ideal))
                verdicts.back()["ideal"] = v.ideal;
            all = all && v.met;
        }
        j["goals"] = verdicts;
        j["all_goals_met"] = all;
        for (const auto &[name, rms] : report.cleanRms)
            if (name == r.setting)
                j["clean_force_rms_n"] = std::isnan(rms) ? nlohmann::json() : nlohmann::json(rms);
        totals.push_back(j);
    }
    const FeelGoals &g = report.goals;
    const nlohmann::json doc = {{"rows", rows},
                                {"family_rows", familyRows},
                                {"totals", totals},
                                {"notes", report.notes},
                                {"replay_seconds", report.seconds},
                                {"goals",
                                 {{"false_trips", 0},
                                  {"pop_through_ms", g.maxPopThroughMs},
                                  {"phantom_ms", g.maxPhantomMs},
                                  {"longest_alternating_run", g.maxAlternation},
                                  {"sign_reversal_spikes_per_s", g.maxReversalsPerSecond},
                                  {"spikes_per_s_over_ideal", 0},
                                  {"spikes_per_s_holds_taps_presses", g.maxStillSpikesPerSecond},
                                  {"regain_ms", g.maxRegainMs},
                                  {"at_max_ms", g.maxAtMaxMs},
                                  {"pull_down_ms", g.maxPullDownMs},
                                  {"energy_excess_mj", g.maxExcessEnergyMj},
                                  {"device_max_force_n", g.deviceMaxForce}}}};
    platform::TextReportFile js((base / "feel.json").string(), error);
    js << doc.dump(2) << '\n';
    return js.close();
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
    if (!report.familyRows.empty()) {
        std::printf("\nper stroke family (pop, phantom: ms summed; alt: longest alternating run, "
                    "updates; rev/s: sign-reversal spikes; spk/s: spikes pressed; ideal/s: the "
                    "ideal penalty's on the same path; regain: ms (missed/events); atmax: ms at "
                    "%.1f N without a trip; +E mJ: energy put into the hand beyond the ideal "
                    "penalty's, worst stroke; E mJ: energy put into the hand, summed)\n",
                    report.goals.deviceMaxForce);
        std::printf("%-26s %-17s %-6s %3s %4s %8s %7s %4s %6s %7s %7s %-12s %6s %6s %7s %7s %6s\n",
                    "scene", "setting", "family", "n", "fals", "pop ms", "phan ms", "alt", "rev/s",
                    "spk/s", "ideal/s", "regain ms", "atmax", "max|F|", "+E mJ", "E mJ", "p999us");
        scene.clear();
        for (const FeelRow &r : report.familyRows) {
            if (!scene.empty() && r.scene != scene)
                std::printf("\n");
            scene = r.scene;
            printFamilyRow(r);
        }
    }
    for (const std::string &n : report.notes)
        std::printf("note: %s\n", n.c_str());
    if (!report.cleanRms.empty()) {
        std::printf("\nforce RMS error against the ideal god-object on clean synthetic surfaces:");
        for (const auto &[name, rms] : report.cleanRms)
            std::printf(" %s %.3f N;", name.c_str(), rms);
        std::printf("\n");
    }
    std::printf("\ngoals, each on the WORST family x scene row of a setting:\n");
    for (const FeelRow &t : report.totals) {
        const std::vector<GoalVerdict> v = judgeGoals(report.familyRows, t.setting, report.goals);
        std::size_t met = 0;
        for (const GoalVerdict &x : v)
            met += x.met ? 1u : 0u;
        std::printf("  %s: %zu of %zu goals met\n", t.setting.c_str(), met, v.size());
        for (const GoalVerdict &x : v) {
            char ideal[32] = "";
            if (!std::isnan(x.ideal))
                std::snprintf(ideal, sizeof ideal, " (ideal's %g)", x.ideal);
            std::printf("    %-40s worst %9.2f at %-36s %s%s\n", x.goal.c_str(), x.worst,
                        x.where.c_str(), verdict(x.met), ideal);
        }
    }
}

/// feel_dump/<key>.csv for every stroke with a kept log (see writeFeelOutputs()).
bool writeStrokeLogs(const FeelReport &report, const std::filesystem::path &base,
                     std::string &error)
{
    for (const FeelStrokeResult &r : report.strokes) {
        if (r.log.empty())
            continue;
        std::string name = r.key();
        for (char &ch : name)
            if (!std::isalnum(static_cast<unsigned char>(ch)))
                ch = '_';
        std::error_code ec;
        std::filesystem::create_directories(base / "feel_dump", ec);
        platform::TextReportFile f((base / "feel_dump" / (name + ".csv")).string(), error);
        f << "t_s,hip_x_mm,hip_y_mm,hip_z_mm,proxy_x_mm,proxy_y_mm,proxy_z_mm,fx_n,fy_n,fz_n,"
             "surface_z_mm,held_z_mm,surface_rise_mm,ideal_n,tripped,cut,pressed,"
             "reach_surface_z_mm,ideal_fx_n,ideal_fy_n,ideal_fz_n,state\n";
        for (const FeelSample &w : r.log)
            f << w.t << ',' << w.hip.x * 1e3 << ',' << w.hip.y * 1e3 << ',' << w.hip.z * 1e3 << ','
              << w.proxy.x * 1e3 << ',' << w.proxy.y * 1e3 << ',' << w.proxy.z * 1e3 << ','
              << w.force.x << ',' << w.force.y << ',' << w.force.z << ',' << w.surfaceZ * 1e3 << ','
              << w.heldSurfaceZ * 1e3 << ',' << w.surfaceRise * 1e3 << ',' << w.idealForce << ','
              << w.released << ',' << w.surfaceCut << ',' << w.pressed << ','
              << w.reachSurfaceZ * 1e3 << ',' << w.idealPenalty.x << ',' << w.idealPenalty.y << ','
              << w.idealPenalty.z << ',' << (w.state != nullptr ? w.state : "") << '\n';
        if (!f.close())
            return false;
    }
    return true;
}

bool writeFeelOutputs(const FeelReport &report, const std::string &dir, std::string &error,
                      std::string &note)
{
    namespace fs = std::filesystem;
    const fs::path base(dir);
    if (!platform::createReportFolder(dir, "cannot create " + dir, error))
        return false;
    if (!writeFeelCsvs(report, base, error) || !writeFeelJson(report, base, error) ||
        !writeStrokeLogs(report, base, error))
        return false;
    if (!writeChartScript(report, base, error))
        return false;
    const platform::PlotStatus plot = platform::runGnuplot((base / "feel.gp").string());
    std::filesystem::remove(base / "feel_vs_speed.png");
    if (plot != platform::PlotStatus::Drawn)
        note = std::string(platform::plotStatusNote(plot)) + "; CSV and JSON written";
    return true;
}

} // namespace depthtouch::haptics::bench
