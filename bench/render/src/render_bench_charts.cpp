/// \file
/// \brief The charts of `depthtouch bench render` (render_bench_charts.h): fps_vs_error, stages and
/// cpu_vs_depth_size, each a data file and a gnuplot script.

#include "render_bench_charts.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "depthtouch/platform/report_file.h"

namespace depthtouch::render::bench::detail {

namespace {

/// A family of settings (BenchRow::family) as the charts draw it.
struct FamilyStyle {
    const char *family;
    const char *title;  ///< Its key entry.
    const char *labels; ///< What its point labels say, for the key of fps_vs_error.
    const char *prefix; ///< What its point labels leave out of a setting's name.
    const char *color;
    int pointType;
};

constexpr FamilyStyle kFamilies[] = {
    {"fixed", "fixed step: full, step2, step4, step8", "", "", "#1f77b4", 7},
    {"adaptive", "adaptive per tile", " (label: tolerance)", "adaptive-", "#2ca02c", 5},
    {"quadtree", "quadtree", " (label: mean error budget)", "quadtree-", "#d62728", 9},
    {"budgets", "quadtree-0.50 under a block budget", " (label: blocks)", "budget-", "#9467bd", 11},
    {"blocks", "blocks", " (label: tolerance; t16, t32: tile size)", "blocks", "#ff7f0e", 13},
    {"block budgets", "blocks-0.40 under a cell budget", " (label: cells)", "blocks-budget-",
     "#8c564b", 15},
};

/// The goals fps_vs_error.png is read against (docs/benchmarks.md, the stereo renderer).
constexpr double kGoalFps = 30.0;
constexpr double kGoalMeanError = 0.5;

/// The render thread's geometry goals (docs/benchmarks.md, depth sizes), at the size each is for.
struct CpuGoal {
    int width;
    int height;
    double ms;
    const char *title;
    int dashType;
};
constexpr CpuGoal kCpuGoals[] = {
    {720, 486, 0.3, "goal at 720x486, full mesh: 0.3 ms", 2},
    {720, 486, 0.5, "goal at 720x486, level of detail: 0.5 ms", 4},
    {3840, 2160, 3.0, "goal at 3840x2160: 3 ms", 3},
};

/// Series colours and point types of cpu_vs_depth_size.png (one pair per setting).
constexpr const char *kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e",
                                   "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22"};
constexpr int kPointTypes[] = {7, 5, 9, 11, 13, 15, 4, 6, 8, 10, 12, 14};

bool sameSet(const BenchRow &a, const BenchRow &b) noexcept
{
    return a.source == b.source && a.depthWidth == b.depthWidth && a.depthHeight == b.depthHeight;
}

/// Whether \a r is of the first source and depth size (what fps_vs_error and stages show).
bool firstSet(const std::vector<BenchRow> &rows, const BenchRow &r) noexcept
{
    return !rows.empty() && sameSet(rows.front(), r);
}

std::string sizeText(int width, int height)
{
    return std::to_string(width) + 'x' + std::to_string(height);
}

double megaSamples(int width, int height) noexcept
{
    return static_cast<double>(width) * height / 1e6;
}

/// \return the point label of setting \a name in family \a f: what tells it from the family's
/// others ("adaptive-0.5": "0.5", "blocks16-0.50": "t16 0.50", "step4" as it is).
std::string shortLabel(const FamilyStyle &f, const std::string &name)
{
    const std::size_t n = std::strlen(f.prefix);
    if (n == 0 || name.size() <= n || name.compare(0, n, f.prefix) != 0)
        return name;
    const std::string rest = name.substr(n);
    if (rest.front() == '-')
        return rest.substr(1);
    const std::size_t dash = rest.find('-');
    if (std::isdigit(static_cast<unsigned char>(rest.front())) != 0 && dash != std::string::npos)
        return 't' + rest.substr(0, dash) + ' ' + rest.substr(dash + 1);
    return rest;
}

/// A rectangle on a chart, pixels from its bottom left corner.
struct Box {
    double x0 = 0.0;
    double y0 = 0.0;
    double x1 = 0.0;
    double y1 = 0.0;
};

double overlapArea(const Box &a, const Box &b) noexcept
{
    const double w = std::min(a.x1, b.x1) - std::max(a.x0, b.x0);
    const double h = std::min(a.y1, b.y1) - std::max(a.y0, b.y0);
    return w > 0.0 && h > 0.0 ? w * h : 0.0;
}

/// A chart whose plot area has fixed margins and axis ranges (x logarithmic): data to pixels.
struct PlotFrame {
    double width = 0.0; ///< The canvas, pixels.
    double height = 0.0;
    Box area; ///< The plot area's border, pixels.
    double xMin = 0.0;
    double xMax = 0.0;
    double yMin = 0.0;
    double yMax = 0.0;

    [[nodiscard]] double px(double x) const
    {
        return area.x0 + std::log(x / xMin) / std::log(xMax / xMin) * (area.x1 - area.x0);
    }
    [[nodiscard]] double py(double y) const
    {
        return area.y0 + (y - yMin) / (yMax - yMin) * (area.y1 - area.y0);
    }
};

/// The label of one point: data coordinates, text, colour.
struct PointLabel {
    double x = 0.0;
    double y = 0.0;
    std::string text;
    const char *color = "";
};

/// Text size of font ',10' on pngcairo, pixels, with a little room.
constexpr double kCharWidthPx = 7.2;
constexpr double kLineHeightPx = 14.0;

/// \return the place of a label \a w × \a h pixels for the point at (\a px, \a py): the nearest in
/// eight directions, farther out ring by ring, that overlaps nothing in \a taken and stays inside
/// \a f's plot area (the least overlap where none is free); \a ring says how far out it is.
Box placeBox(double px, double py, double w, double h, const PlotFrame &f,
             const std::vector<Box> &taken, int &ring)
{
    static constexpr int kDirs[8][2] = {{1, 0}, {-1, 0}, {0, 1},  {0, -1},
                                        {1, 1}, {-1, 1}, {1, -1}, {-1, -1}};
    Box best{px + 7.0, py - h / 2, px + 7.0 + w, py + h / 2};
    double bestCost = std::numeric_limits<double>::infinity();
    ring = 0;
    for (int r = 0; r < 9 && bestCost > 0.0; ++r) {
        const double gap = 7.0 + 9.0 * r;
        for (const auto &d : kDirs) {
            Box b;
            b.x0 = d[0] > 0 ? px + gap : d[0] < 0 ? px - gap - w : px - w / 2;
            b.y0 = d[1] > 0 ? py + gap : d[1] < 0 ? py - gap - h : py - h / 2;
            b.x1 = b.x0 + w;
            b.y1 = b.y0 + h;
            if (b.x0 < f.area.x0 || b.x1 > f.area.x1 || b.y0 < f.area.y0 || b.y1 > f.area.y1)
                continue;
            double cost = 0.0;
            for (const Box &t : taken)
                cost += overlapArea(b, t);
            if (cost < bestCost) {
                bestCost = cost;
                best = b;
                ring = r;
            }
            if (cost == 0.0)
                break;
        }
    }
    return best;
}

/// Writes `set label` for each of \a labels where it overlaps no other label and no point, and a
/// leader line to a label placed away from its point.
void placeLabels(const std::vector<PointLabel> &labels, const PlotFrame &f, std::ostream &gp)
{
    std::vector<Box> taken;
    for (const PointLabel &l : labels)
        taken.push_back({f.px(l.x) - 7.0, f.py(l.y) - 7.0, f.px(l.x) + 7.0, f.py(l.y) + 7.0});
    for (const PointLabel &l : labels) {
        const double px = f.px(l.x);
        const double py = f.py(l.y);
        const double w = kCharWidthPx * static_cast<double>(l.text.size()) + 2.0;
        int ring = 0;
        const Box b = placeBox(px, py, w, kLineHeightPx, f, taken, ring);
        taken.push_back(b);
        gp << "set label '" << l.text << "' at screen " << (b.x0 + 1.0) / f.width << ", "
           << (b.y0 + b.y1) / 2 / f.height << " left tc rgb '" << l.color << "' front\n";
        if (ring > 0)
            gp << "set arrow from first " << l.x << ", first " << l.y << " to screen "
               << std::clamp(px, b.x0, b.x1) / f.width << ", "
               << std::clamp(py, b.y0, b.y1) / f.height << " nohead lw 0.8 lc rgb '" << l.color
               << "' front\n";
    }
}

/// The frame of fps_vs_error.png for \a rows (the first set): the axis ranges hold every point, the
/// goals, and a mesh without error at \a zeroX.
PlotFrame fpsFrame(const std::vector<const BenchRow *> &rows, double &zeroX)
{
    double minError = std::numeric_limits<double>::infinity();
    double maxError = kGoalMeanError;
    double maxFps = kGoalFps;
    for (const BenchRow *r : rows) {
        if (r->meanError > 0.0)
            minError = std::min(minError, r->meanError);
        maxError = std::max(maxError, r->meanError);
        maxFps = std::max(maxFps, r->fps);
    }
    zeroX = std::isfinite(minError) ? std::min(0.1, minError / 2) : 0.1;
    PlotFrame f;
    f.width = 1360;
    f.height = 760;
    f.area = {0.065 * f.width, 0.09 * f.height, 0.64 * f.width, 0.92 * f.height};
    f.xMin = zeroX / 1.5;
    f.xMax = maxError * 1.6;
    f.yMax = maxFps * 1.12;
    return f;
}

/// The range of the values of a log axis.
struct LogRange {
    double lo = std::numeric_limits<double>::infinity();
    double hi = 0.0;
    void add(double v) noexcept
    {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    /// \return the gnuplot range with a margin either side, at least a decade wide (one value
    /// is no empty range, and shows a labelled tick); "[*:*]" when empty.
    [[nodiscard]] std::string text() const
    {
        if (!(hi > 0.0))
            return "[*:*]";
        const double mid = std::sqrt(lo * hi);
        const double half = std::max(std::sqrt(hi / lo) * 1.6, std::sqrt(10.0));
        return '[' + std::to_string(mid / half) + ':' + std::to_string(mid * half) + ']';
    }
};

/// cpu_vs_depth_size: one data block (a line) of a panel row.
struct CpuSeries {
    std::string title;
    const char *color = "";
    int pointType = 7;
    std::size_t panelRow = 0; ///< The source's row of panels.
    bool prep = true;         ///< Drawn in the prep panel (not a fixed step).
};

/// What cpu_vs_depth_size shows: against the depth size (several sizes) or the triangles (one).
struct CpuPlan {
    bool bySize = false;
    std::vector<std::pair<int, int>> sizes;
    std::vector<std::string> sources; ///< A row of panels each.
    std::vector<CpuSeries> series;    ///< In data block order.
    LogRange x;                       ///< The x values.
    LogRange geom;                    ///< The render thread's figures and goals.
    LogRange prep;                    ///< The prep thread's figures of the series drawn there.
};

/// Writes one data block per series of \a p into \a d: (x, geom ms, prep ms) per row.
void writeCpuData(const std::vector<BenchRow> &rows, CpuPlan &p, std::ostream &d)
{
    const auto block = [&d, &p](std::vector<const BenchRow *> of, CpuSeries s) {
        std::sort(of.begin(), of.end(), [&p](const BenchRow *a, const BenchRow *b) {
            return p.bySize ? megaSamples(a->depthWidth, a->depthHeight) <
                                  megaSamples(b->depthWidth, b->depthHeight)
                            : a->meanTriangles < b->meanTriangles;
        });
        d << "# " << s.title << '\n';
        for (const BenchRow *r : of) {
            const double x =
                p.bySize ? megaSamples(r->depthWidth, r->depthHeight) : r->meanTriangles;
            p.x.add(x);
            p.geom.add(std::max(r->geomCpuMs, 1e-3));
            if (s.prep)
                p.prep.add(std::max(r->prepCpuMs, 1e-3));
            d << x << ' ' << std::max(r->geomCpuMs, 1e-3) << ' ' << std::max(r->prepCpuMs, 1e-3)
              << '\n';
        }
        d << "\n\n";
        p.series.push_back(std::move(s));
    };
    if (!p.bySize) { // one line per family
        for (const FamilyStyle &f : kFamilies) {
            std::vector<const BenchRow *> of;
            for (const BenchRow &r : rows)
                if (firstSet(rows, r) && r.family == f.family)
                    of.push_back(&r);
            if (!of.empty())
                block(of, {f.title, f.color, f.pointType, 0, std::string(f.family) != "fixed"});
        }
        return;
    }
    const auto runsOf = [&rows](const std::string &source, const std::string &name) {
        std::vector<const BenchRow *> of;
        for (const BenchRow &r : rows)
            if (r.source == source && r.name == name)
                of.push_back(&r);
        return of;
    };
    // The settings with a line (run at more than one size), each its own colour and point type.
    std::vector<std::string> names;
    for (const BenchRow &r : rows)
        if (std::find(names.begin(), names.end(), r.name) == names.end() &&
            std::any_of(p.sources.begin(), p.sources.end(),
                        [&](const std::string &src) { return runsOf(src, r.name).size() > 1; }))
            names.push_back(r.name);
    for (std::size_t si = 0; si < p.sources.size(); ++si)
        for (std::size_t k = 0; k < names.size(); ++k) {
            const std::vector<const BenchRow *> of = runsOf(p.sources[si], names[k]);
            if (of.size() > 1)
                block(of,
                      {names[k], kColors[k % std::size(kColors)],
                       kPointTypes[k % std::size(kPointTypes)], si, of.front()->family != "fixed"});
        }
}

/// The plan of cpu_vs_depth_size for \a rows, its data written to \a base.
CpuPlan cpuPlan(const std::vector<BenchRow> &rows, const std::filesystem::path &base,
                std::string &error)
{
    CpuPlan p;
    for (const BenchRow &r : rows) {
        const std::pair<int, int> s{r.depthWidth, r.depthHeight};
        if (std::find(p.sizes.begin(), p.sizes.end(), s) == p.sizes.end())
            p.sizes.push_back(s);
        if (std::find(p.sources.begin(), p.sources.end(), r.source) == p.sources.end())
            p.sources.push_back(r.source);
    }
    p.bySize = p.sizes.size() > 1;
    if (!p.bySize)
        p.sources.resize(std::min<std::size_t>(p.sources.size(), 1));
    platform::TextReportFile d((base / "cpu_vs_depth_size.dat").string(), error);
    writeCpuData(rows, p, d);
    return p;
}

/// Sets the axes of cpu_vs_depth_size's panels: x the depth size (ticks at the sizes run) or the
/// triangles, y log ms.
void writeCpuAxes(const CpuPlan &p, std::ostream &gp)
{
    gp << "set logscale xy\nset grid\nset format y '%g'\nset ytics (0.001, 0.002, 0.005, 0.01, "
          "0.02, "
          "0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000)\n"
       << "set ylabel 'ms per frame (thread CPU time, median)'\n";
    gp << "set xrange " << p.x.text() << '\n';
    if (!p.bySize) {
        gp << "set xlabel 'triangles in the mesh (log scale)'\nset format x '%.0s%c'\n";
        return;
    }
    bool close = false; // sizes under twice apart: their tick labels are turned
    gp << "set xtics (";
    for (std::size_t i = 0; i < p.sizes.size(); ++i) {
        const double m = megaSamples(p.sizes[i].first, p.sizes[i].second);
        for (std::size_t j = 0; j < i; ++j) {
            const double o = megaSamples(p.sizes[j].first, p.sizes[j].second);
            close = close || std::max(m, o) < 2.0 * std::min(m, o);
        }
        gp << (i == 0 ? "" : ", ") << '\'' << sizeText(p.sizes[i].first, p.sizes[i].second) << "' "
           << m;
    }
    gp << ")" << (close ? " rotate by -25" : "")
       << "\nset xlabel 'depth size (samples, log scale)'\n";
}

/// Writes the render thread's goals of \a p's sizes as named lines: a segment at its size (by
/// size), across the panel (one size), their times in \a p's geom range. \return the plot terms;
/// the datablocks go to \a gp.
std::string cpuGoalTerms(CpuPlan &p, std::ostream &gp)
{
    std::string terms;
    int n = 0;
    for (const CpuGoal &g : kCpuGoals) {
        if (std::find(p.sizes.begin(), p.sizes.end(), std::make_pair(g.width, g.height)) ==
            p.sizes.end())
            continue;
        p.geom.add(g.ms);
        std::string source = std::to_string(g.ms);
        if (p.bySize) {
            const double m = megaSamples(g.width, g.height);
            source = "$goal" + std::to_string(n++);
            gp << source << " << EOD\n"
               << m / 1.35 << ' ' << g.ms << '\n'
               << m * 1.35 << ' ' << g.ms << "\nEOD\n";
            source += " using 1:2";
        }
        terms += ", \\\n     " + source + " with lines dt " + std::to_string(g.dashType) +
                 " lw 2 lc rgb 'black' title '" + g.title + "'";
    }
    return terms;
}

/// Writes the two panels (render thread, prep thread) of source row \a si; the first panel holds
/// the key (the series and \a goals).
void writeCpuPanels(const CpuPlan &p, std::size_t si, const std::string &dat,
                    const std::string &goals, double keyTop, std::ostream &gp)
{
    const std::string &source = p.sources[si];
    for (int col = 0; col < 2; ++col) {
        gp << "set title \"" << source
           << (col == 0 ? ": render thread, geom_cpu_ms\\n(index choice, depth upload, mapping)\"\n"
                        : ": prep thread, prep_cpu_ms\\n(making the level of detail; not to grow "
                          "with the triangles)\"\n");
        if (si == 0 && col == 0)
            gp << "set key at screen 0.695, " << keyTop
               << " left top Left reverse box opaque spacing 1.2 samplen 4\n";
        else
            gp << "unset key\n";
        std::string terms;
        for (std::size_t k = 0; k < p.series.size(); ++k) {
            const CpuSeries &s = p.series[k];
            if (s.panelRow != si || (col == 1 && !s.prep))
                continue;
            terms += std::string(terms.empty() ? "" : ", \\\n     ") +
                     (terms.empty() ? dat : "''") + " index " + std::to_string(k) +
                     " using 1:" + (col == 0 ? "2" : "3") + " with linespoints lw 2 ps 1.3 pt " +
                     std::to_string(s.pointType) + " lc rgb '" + s.color + "' title '" + s.title +
                     "'";
        }
        gp << "set yrange " << (col == 0 ? p.geom : p.prep).text() << '\n';
        if (terms.empty()) { // only fixed steps: nothing is made ahead
            gp << "set label 1 'fixed steps only: no level of detail is made' at graph 0.5, "
                  "graph 0.5 center\nset yrange [0.01:10]\nplot NaN notitle\n"
                  "unset label 1\n";
            continue;
        }
        gp << "plot " << terms << (col == 0 ? goals : "") << '\n';
    }
}

} // namespace

bool stagePassRun(const std::vector<BenchRow> &rows) noexcept
{
    return std::any_of(rows.begin(), rows.end(), [&rows](const BenchRow &r) {
        return firstSet(rows, r) && r.stagedMedianMs > 0.0;
    });
}

void writeFpsChart(const std::vector<BenchRow> &rows, const std::filesystem::path &base,
                   std::string &error)
{
    std::vector<const BenchRow *> first;
    for (const BenchRow &r : rows)
        if (firstSet(rows, r))
            first.push_back(&r);
    double zeroX = 0.1;
    const PlotFrame f = fpsFrame(first, zeroX);
    std::vector<const FamilyStyle *> present; // one data block each
    std::vector<PointLabel> labels;
    {
        platform::TextReportFile d((base / "fps_vs_error.dat").string(), error);
        for (const FamilyStyle &fam : kFamilies) {
            bool any = false;
            for (const BenchRow *r : first) {
                if (r->family != fam.family)
                    continue;
                if (!any)
                    d << "# " << fam.family << '\n';
                any = true;
                const double x = r->meanError > 0.0 ? r->meanError : zeroX;
                d << x << ' ' << r->fps << '\n';
                labels.push_back(
                    {x, r->fps, shortLabel(fam, r->name) + (r->meanError > 0.0 ? "" : " (error 0)"),
                     fam.color});
            }
            if (any) {
                d << "\n\n";
                present.push_back(&fam);
            }
        }
    }
    const std::string src = rows.empty()
                                ? std::string()
                                : rows.front().source + ' ' +
                                      sizeText(rows.front().depthWidth, rows.front().depthHeight);
    const std::string dat = "'" + (base / "fps_vs_error.dat").string() + "'";
    platform::TextReportFile gp((base / "fps_vs_error.gp").string(), error);
    gp << "set terminal pngcairo size " << f.width << ',' << f.height << " noenhanced font ',10'\n"
       << "set output '" << (base / "fps_vs_error.png").string() << "'\n"
       << "set title 'Stereo side-by-side, " << src
       << ": frame rate vs mean geometric error (the shaded corner meets both goals)'\n"
       << "set xlabel 'mean geometric error, 8-bit nearness levels (log scale; a mesh without "
          "error at the left)'\n"
       << "set ylabel 'frames per second (median)'\nset grid\nset logscale x\n"
       << "set lmargin at screen " << f.area.x0 / f.width << "\nset rmargin at screen "
       << f.area.x1 / f.width << "\nset bmargin at screen " << f.area.y0 / f.height
       << "\nset tmargin at screen " << f.area.y1 / f.height << "\nset xrange [" << f.xMin << ':'
       << f.xMax << "]\nset yrange [" << f.yMin << ':' << f.yMax << "]\n"
       << "set key at screen 0.655, 0.92 left top Left reverse box opaque spacing 1.3 samplen 4\n"
       << "set object 1 rect from graph 0, first " << kGoalFps << " to first " << kGoalMeanError
       << ", graph 1 behind fc rgb '#e3f2e3' fs solid 1.0 noborder\n"
       << "set arrow from first " << kGoalMeanError << ", graph 0 to first " << kGoalMeanError
       << ", graph 1 nohead dt 3 lw 2 lc rgb 'gray20'\n";
    placeLabels(labels, f, gp);
    gp << "plot ";
    for (std::size_t i = 0; i < present.size(); ++i)
        gp << (i == 0 ? dat : "''") << " index " << i
           << " using 1:2 with linespoints lw 2 ps 1.3 pt " << present[i]->pointType << " lc rgb '"
           << present[i]->color << "' title '" << present[i]->title << present[i]->labels
           << "', \\\n     ";
    gp << kGoalFps << " with lines dt 2 lw 2 lc rgb 'gray20' title 'goal: " << kGoalFps
       << " fps', \\\n     NaN with lines dt 3 lw 2 lc rgb 'gray20' title 'goal: mean error at "
          "most "
       << kGoalMeanError
       << " levels', \\\n     NaN with boxes fs solid 1.0 fc rgb '#e3f2e3' title 'both goals "
          "met'\n";
}

void writeStagesChart(const std::vector<BenchRow> &rows, const std::filesystem::path &base,
                      std::string &error)
{
    platform::TextReportFile d((base / "stages.dat").string(), error);
    d << "mesh";
    for (int k = 0; k < kStageCount; ++k)
        d << ' ' << stageName(k);
    d << '\n';
    for (const BenchRow &r : rows) {
        if (!firstSet(rows, r))
            continue;
        d << r.name;
        for (const double v : r.stageMedianMs)
            d << ' ' << v;
        d << '\n';
    }
    platform::TextReportFile gp((base / "stages.gp").string(), error);
    gp << "set terminal pngcairo size 1100,650 noenhanced font ',10'\n"
       << "set output '" << (base / "stages.png").string() << "'\n"
       << "set title 'Stereo side-by-side: median time per stage (glFinish after each stage)'\n"
       << "set ylabel 'ms per frame'\nset grid ytics\nset key outside right top\n"
       << "set style data histograms\nset style histogram rowstacked\n"
       << "set style fill solid 0.9 border rgb 'black'\nset boxwidth 0.7\n"
       << "set xtics rotate by -35\nset bmargin 6\n"
       << "colors = '#1f77b4 #ff7f0e #2ca02c #d62728 #9467bd #8c564b #e377c2 #7f7f7f #17becf'\n"
       << "plot for [k=2:" << (kStageCount + 1) << "] '" << (base / "stages.dat").string()
       << "' using k:xtic(1) lc rgb word(colors, k-1) title columnheader(k)\n";
}

void writeCpuChart(const std::vector<BenchRow> &rows, const std::filesystem::path &base,
                   std::string &error)
{
    if (rows.empty())
        return;
    CpuPlan p = cpuPlan(rows, base, error);
    const std::size_t panelRows = std::max<std::size_t>(p.sources.size(), 1);
    const double height = 150.0 + 360.0 * static_cast<double>(panelRows);
    const std::string dat = "'" + (base / "cpu_vs_depth_size.dat").string() + "'";
    platform::TextReportFile gp((base / "cpu_vs_depth_size.gp").string(), error);
    gp << "set terminal pngcairo size 1360," << height << " noenhanced font ',10'\n"
       << "set output '" << (base / "cpu_vs_depth_size.png").string() << "'\n";
    const std::string goals = cpuGoalTerms(p, gp);
    const std::string title =
        p.bySize ? "CPU time per frame for the depth geometry against the depth size (one line "
                   "per setting run at more than one size)"
                 : "CPU time per frame for the depth geometry at one depth size (" +
                       sizeText(p.sizes.front().first, p.sizes.front().second) +
                       "): against the triangles, one line per family (--depth-sizes: against "
                       "the depth size)";
    gp << "set multiplot layout " << panelRows << ",2 title '" << title << "' margins 0.06,0.68,"
       << 60.0 / height << ',' << 1.0 - 80.0 / height << " spacing 0.07," << 110.0 / height << '\n';
    writeCpuAxes(p, gp);
    for (std::size_t si = 0; si < p.sources.size(); ++si)
        writeCpuPanels(p, si, dat, goals, 1.0 - 80.0 / height, gp);
    gp << "unset multiplot\n";
}

} // namespace depthtouch::render::bench::detail
