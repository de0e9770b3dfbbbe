/// \file
/// \brief `depthtouch bench feel`'s chart (feel.gp, feel.png): which renderer setting is both
/// accurate and robust, and at what cost (feel_chart_internal.h).

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "depthtouch/haptics/feel_bench.h"
#include "depthtouch/platform/gnuplot.h"
#include "depthtouch/platform/report_file.h"
#include "feel_chart_internal.h"

namespace depthtouch::haptics::bench {

namespace {

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

} // namespace

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

} // namespace depthtouch::haptics::bench
