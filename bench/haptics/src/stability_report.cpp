/// \file
/// \brief The outputs of `depthtouch bench stability` (stability_bench.h): stability.csv (one row
/// per run), stability_limits.csv, the printed limits and the gnuplot charts stability.png
/// (oscillation against k) and stability_energy.png (energy into the hand against k).

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <ostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "depthtouch/haptics/stability_bench.h"
#include "depthtouch/platform/gnuplot.h"
#include "depthtouch/platform/report_file.h"

namespace depthtouch::haptics::bench {

namespace {

constexpr double kOscillationFloorUm = 1e-3; // µm: smaller peak-to-peak is drawn at the floor
constexpr double kEnergyFloorMj = 1e-6;      // mJ: smaller late energy is drawn at the floor

/// The series' colours, in the order the methods first appear in the rows.
constexpr const char *kPalette[] = {"#000000", "#1f77b4", "#ff7f0e", "#2ca02c",
                                    "#d62728", "#9467bd", "#8c564b"};
/// Their point types and sizes (the sweep's order: wall, finger, finger-unfiltered, modified,
/// proxy-graph, mesh-bvh): series that coincide (all but finger on a plane below their limit)
/// show as nested marks, open ones around the small filled ones.
constexpr const char *kMarks[] = {"pt 7 ps 0.6", "pt 5 ps 0.9", "pt 4 ps 1.5", "pt 6 ps 2.4",
                                  "pt 8 ps 1.7", "pt 7 ps 0.9", "pt 11 ps 1.0"};
constexpr double kOscillationCeilingUm = 1e5; // µm: the chart's top (the wall's runaway goes on)
constexpr double kEnergyCeilingMj = 1e4;      // mJ: the same for the energy

std::vector<std::string> methodsOf(const std::vector<StabilityRow> &rows)
{
    std::vector<std::string> out;
    for (const StabilityRow &r : rows)
        if (std::find(out.begin(), out.end(), r.method) == out.end())
            out.push_back(r.method);
    return out;
}

template <class T>
std::vector<T> distinct(const std::vector<StabilityRow> &rows, T StabilityRow::*f)
{
    std::vector<T> out;
    for (const StabilityRow &r : rows)
        if (std::find(out.begin(), out.end(), r.*f) == out.end())
            out.push_back(r.*f);
    return out;
}

/// What a chart draws on its y axis.
struct Quantity {
    const char *file;   ///< the PNG's name
    const char *title;  ///< the chart's title (no apostrophe: it goes in single quotes)
    const char *ylabel; ///< the y axis
    bool oscillation;   ///< peak-to-peak penetration (µm); else the late window's energy (mJ)
};

double chartValue(const StabilityRow &r, bool oscillation)
{
    return oscillation ? std::max(r.oscillation * 1e6, kOscillationFloorUm)
                       : std::max(r.lateEnergy * 1e3, kEnergyFloorMj);
}

/// The rows one panel draws: a surface, a servo rate (Hz) and a hand damping (N·s/m).
struct PanelSeries {
    std::string surface;
    double rate = 0.0;
    double damping = 0.0;
    [[nodiscard]] bool has(const StabilityRow &r) const
    {
        return r.surface == surface && r.servoRate == rate && r.handDamping == damping;
    }
};

/// Into \a gp, the plot command of one panel and its inline data: the Colgate bound at x from
/// \a yRange[0] to [1], the settled band across \a xRange (oscillation only), a line per method
/// and the let-through runs crossed. Series with no point are left out (gnuplot warns of them).
void writePanel(const std::vector<StabilityRow> &rows, const std::vector<std::string> &methods,
                const Quantity &q, const PanelSeries &panel, const std::array<double, 2> &xRange,
                const std::array<double, 2> &yRange, std::ostream &gp)
{
    std::vector<std::pair<std::string, std::string>> series; // plot style, data lines
    std::ostringstream d;
    const double bound = 2.0 * panel.damping * panel.rate;
    d << bound << ' ' << yRange[0] << '\n' << bound << ' ' << yRange[1] << '\n';
    series.emplace_back("with lines dt 2 lw 2 lc rgb 'black'", d.str());
    if (q.oscillation)
        series.emplace_back("with lines dt 3 lw 2 lc rgb '#7f7f7f'",
                            std::to_string(xRange[0]) + " 10\n" + std::to_string(xRange[1]) +
                                " 10\n");
    for (std::size_t mi = 0; mi < methods.size(); ++mi) {
        std::ostringstream m;
        for (const StabilityRow &r : rows)
            if (r.method == methods[mi] && panel.has(r))
                m << r.stiffness << ' ' << chartValue(r, q.oscillation) << '\n';
        series.emplace_back(std::string("with linespoints ") + kMarks[mi % std::size(kMarks)] +
                                " lw 2 lc rgb '" + kPalette[mi % std::size(kPalette)] + "'",
                            m.str());
    }
    std::ostringstream x;
    for (const StabilityRow &r : rows)
        if (r.outcome == "let-through" && panel.has(r))
            x << r.stiffness << ' ' << chartValue(r, q.oscillation) << '\n';
    series.emplace_back("with points pt 2 ps 2.5 lw 2 lc rgb 'black'", x.str());
    std::erase_if(series, [](const auto &e) { return e.second.empty(); });
    const char *sep = "plot ";
    for (const auto &e : series) {
        gp << sep << "'-' " << e.first << " notitle";
        sep = ", ";
    }
    gp << '\n';
    for (const auto &e : series)
        gp << e.second << "e\n";
}

/// Into \a gp, one chart of \a q: a panel per surface (rows) and servo rate (columns) at hand
/// damping \a b, a line per method, the Colgate bound and (for the oscillation) the settled band,
/// and a key panel naming them.
void writeChart(const std::vector<StabilityRow> &rows, const std::filesystem::path &base,
                const Quantity &q, double b, std::ostream &gp)
{
    const std::vector<std::string> methods = methodsOf(rows);
    const std::vector<std::string> surfaces = distinct(rows, &StabilityRow::surface);
    const std::vector<double> rates = distinct(rows, &StabilityRow::servoRate);
    const auto [kLo, kHi] = std::minmax_element(
        rows.begin(), rows.end(),
        [](const StabilityRow &x, const StabilityRow &y) { return x.stiffness < y.stiffness; });
    const double yLo = q.oscillation ? kOscillationFloorUm : kEnergyFloorMj;
    double yHi = yLo * 10.0;
    for (const StabilityRow &r : rows)
        yHi = std::max(yHi, chartValue(r, q.oscillation));
    yHi *= 3.0;
    yHi = std::min(yHi, q.oscillation ? kOscillationCeilingUm : kEnergyCeilingMj);
    const double panelW = 0.49;
    const double panelH = 0.41;
    gp << "reset\nset terminal pngcairo size 1600,1150 noenhanced font ',11'\nset output '"
       << (base / q.file).string() << "'\nset multiplot title '" << q.title
       << "'\nset logscale xy\nset format y '%g'\nset grid\nset key off\nset xrange ["
       << kLo->stiffness / 1.2 << ':' << kHi->stiffness * 1.2 << "]\nset yrange [" << yLo / 2.0
       << ':' << yHi << "]\nset xlabel 'stiffness k (N/m)'\nset ylabel '" << q.ylabel << "'\n";
    for (std::size_t si = 0; si < surfaces.size(); ++si)
        for (std::size_t ri = 0; ri < rates.size(); ++ri) {
            char title[200];
            std::snprintf(title, sizeof title,
                          "%s surface, servo rate %.0f Hz: Colgate bound 2b/T = %.0f N/m",
                          surfaces[si].c_str(), rates[ri], 2.0 * b * rates[ri]);
            gp << "set origin " << 0.01 + panelW * static_cast<double>(ri) << ','
               << 0.13 + panelH * static_cast<double>(surfaces.size() - 1 - si) << "\nset size "
               << panelW << ',' << panelH << "\nset title '" << title << "'\n";
            const PanelSeries panel{surfaces[si], rates[ri], b};
            writePanel(rows, methods, q, panel, {kLo->stiffness / 1.2, kHi->stiffness * 1.2},
                       {yLo / 2.0, yHi}, gp);
        }
    // The key panel: every line named once.
    gp << "set origin 0.0,0.0\nset size 1.0,0.12\nunset logscale\nunset border\nunset tics\n"
          "unset grid\nunset xlabel\nunset ylabel\nunset title\nset xrange [0:1]\n"
          "set yrange [0:1]\nset key center center box Left reverse horizontal maxrows 3 "
          "width 2 spacing 1.2 title "
          "'hand: 0.1 kg, 300 N/m, b = "
       << b << " N s/m.  Series that coincide show as nested marks; values "
       << (q.oscillation ? "under 0.001 um are" : "of 1e-6 mJ or less (none, or taken back) are")
       << " drawn at the bottom'\nplot NaN notitle";
    for (std::size_t mi = 0; mi < methods.size(); ++mi)
        gp << ", keyentry with linespoints " << kMarks[mi % std::size(kMarks)] << " lw 2 lc rgb '"
           << kPalette[mi % std::size(kPalette)] << "' title '" << methods[mi]
           << (methods[mi] == "wall" ? " (ideal sampled spring, no limiter)" : "") << "'";
    gp << ", keyentry with points pt 2 ps 2.5 lw 2 lc rgb 'black' title 'let through: a limiter "
          "released the hand (no force)'";
    gp << ", keyentry with lines dt 2 lw 2 lc rgb 'black' title 'goal line: Colgate bound "
          "k_max = 2b/T'";
    if (q.oscillation)
        gp << ", keyentry with lines dt 3 lw 2 lc rgb '#7f7f7f' title 'settled: peak-to-peak "
              "under 10 um'";
    gp << "\nunset multiplot\n";
}

void writeRowsCsv(const std::vector<StabilityRow> &rows, const std::filesystem::path &base,
                  std::string &error)
{
    platform::TextReportFile f((base / "stability.csv").string(), error);
    f << stabilityCsvHeader() << '\n';
    f.precision(9);
    for (const StabilityRow &r : rows) {
        f << r.method << ',' << r.surface << ',' << r.servoRate << ',' << r.handDamping << ','
          << r.stiffness << ',' << r.workspaceScale << ',' << r.colgateBound << ',' << r.oscillation
          << ',' << r.oscillationEarly << ',' << r.penetrationMean << ',' << r.forceMean << ','
          << r.forceExpected << ',' << r.energyEnd << ',' << r.energyPeak << ',' << r.lateEnergy
          << ',';
        if (r.settleTime >= 0.0)
            f << r.settleTime;
        f << ',' << r.releases << ',' << r.outcome << '\n';
    }
}

void writeLimitsCsv(const std::vector<StabilityLimit> &limits, const std::filesystem::path &base,
                    std::string &error)
{
    platform::TextReportFile f((base / "stability_limits.csv").string(), error);
    f << "method,surface,servo_rate_hz,hand_damping_n_s_per_m,colgate_bound_n_per_m,"
         "last_stable_n_per_m,first_unstable_n_per_m\n";
    f.precision(9);
    for (const StabilityLimit &l : limits)
        f << l.method << ',' << l.surface << ',' << l.servoRate << ',' << l.handDamping << ','
          << l.colgateBound << ',' << l.lastStable << ',' << l.firstUnstable << '\n';
}

} // namespace

const char *stabilityCsvHeader() noexcept
{
    return "method,surface,servo_rate_hz,hand_damping_n_s_per_m,stiffness_n_per_m,"
           "workspace_scale,colgate_bound_n_per_m,oscillation_pp_m,oscillation_early_pp_m,"
           "penetration_mean_m,"
           "force_mean_n,force_expected_n,energy_end_j,energy_peak_j,late_energy_j,"
           "settle_time_s,releases,outcome";
}

void printStabilityLimits(const std::vector<StabilityLimit> &limits)
{
    std::printf("%-17s %-7s %7s %8s %10s %14s %14s\n", "method", "surface", "rate", "b N s/m",
                "2b/T N/m", "stable to", "not at");
    for (const StabilityLimit &l : limits) {
        char stableTo[32] = "none";
        char notAt[32] = "all stable";
        if (l.lastStable > 0.0)
            std::snprintf(stableTo, sizeof stableTo, "%.0f N/m", l.lastStable);
        if (l.firstUnstable > 0.0)
            std::snprintf(notAt, sizeof notAt, "%.0f N/m", l.firstUnstable);
        std::printf("%-17s %-7s %4.0f Hz %8.1f %10.0f %14s %14s\n", l.method.c_str(),
                    l.surface.c_str(), l.servoRate, l.handDamping, l.colgateBound, stableTo, notAt);
    }
}

bool writeStabilityOutputs(const std::vector<StabilityRow> &rows,
                           const std::vector<StabilityLimit> &limits, const std::string &dir,
                           std::string &error, std::string &note)
{
    if (!platform::createReportFolder(dir, "Failed to create '" + dir + "'", error))
        return false;
    const std::filesystem::path base(dir);
    writeRowsCsv(rows, base, error);
    writeLimitsCsv(limits, base, error);
    if (!rows.empty()) {
        const double b = rows.front().handDamping; // the charts' hand: the sweep's first
        const Quantity oscillation{"stability.png",
                                   "Closed-loop stability against stiffness: a simulated hand "
                                   "presses with 1 N (1 kHz and 500 Hz servo rate)",
                                   "penetration peak-to-peak, last 0.5 s (um)", true};
        const Quantity energy{
            "stability_energy.png",
            "Energy the renderer put into the hand over the last 0.5 s "
            "(passivity observer, Hannaford and Ryu 2002): near zero once a press "
            "settles, growing with the oscillation where the loop is unstable",
            "energy into the hand, last 0.5 s (mJ)", false};
        platform::TextReportFile g((base / "charts.gp").string(), error);
        writeChart(rows, base, oscillation, b, g);
        writeChart(rows, base, energy, b, g);
    }
    if (!error.empty())
        return false;
    // gnuplot's messages go to a file, not amid the printed table.
    const platform::PlotStatus plot =
        platform::runGnuplot((base / "charts.gp").string(), (base / "gnuplot.log").string());
    if (plot != platform::PlotStatus::Drawn)
        note = std::string(platform::plotStatusNote(plot)) + "; CSV written";
    return true;
}

} // namespace depthtouch::haptics::bench
