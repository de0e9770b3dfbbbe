/// \file
/// \brief The demo's force chart: see demo_chart.h.

#include "depthtouch/demo/demo_chart.h"

#include <cmath>
#include <sstream>

#include "depthtouch/haptics/spectrum.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/gnuplot.h"
#include "depthtouch/platform/message_text.h"

namespace depthtouch::demo {

namespace {

/// Writes \a text to \a path whole (a temporary name, renamed when complete). \return true, or
/// false with \a lost set to the one error line (when it is still empty).
bool writeDemoFile(const std::string &path, const std::string &text, std::string &lost)
{
    auto w = platform::writeOutputFile(path, text);
    if (!w && lost.empty()) {
        char why[160];
        lost = "cannot write " + platform::quotedText(path, 120) + ": " +
               w.error().format(why, sizeof why);
    }
    return w.has_value();
}

} // namespace

/// Writes force-plot.csv, force-psd.csv and the chart script; runs gnuplot.
/// \return a note for the summary; \a lost says why a file could not be written.
std::string chartForce(const std::string &dir, const std::vector<std::array<double, 6>> &plot,
                       double rate, std::string &lost)
{
    if (plot.size() < 256)
        return "force log too short for a chart";
    std::vector<double> magnitude(plot.size());
    for (std::size_t i = 0; i < plot.size(); ++i)
        magnitude[i] = plot[i][1];
    const haptics::Psd psd =
        haptics::averagedPsd(magnitude.data(), magnitude.size(), 8, rate, rate / 2.0);
    const std::string psdCsv = dir + "/force-psd.csv";
    std::ostringstream psdText;
    {
        std::ostream &f = psdText;
        f << "hz,psd_n2_per_hz\n";
        for (std::size_t k = 1; k < psd.density.size(); ++k)
            f << static_cast<double>(k) * psd.binHz << ',' << psd.density[k] << '\n';
    }
    const std::string plotCsv = dir + "/force-plot.csv";
    std::ostringstream plotText;
    {
        std::ostream &f = plotText;
        f << "play_s,force_n,contact,hip_z_mm,surface_z_mm,on_figure\n";
        for (const auto &p : plot)
            f << p[0] << ',' << p[1] << ',' << p[2] << ',' << p[3] << ','
              << (std::isnan(p[4]) ? std::string("NaN") : std::to_string(p[4])) << ',' << p[5]
              << '\n';
    }
    const std::string script = dir + "/force.gp";
    std::ostringstream scriptText;
    {
        std::ostream &g = scriptText;
        g << "set terminal pngcairo size 1000,900 font ',10'\n"
          << "set output '" << dir << "/force.png'\n"
          << "set datafile separator ','\nset datafile missing 'NaN'\n"
          << "set multiplot layout 3,1 title 'DepthTouch demo: the simulated finger stroking "
             "the head'\n"
          << "set grid\nset key outside right top vertical\nset lmargin 10\nset rmargin 20\n"
          << "set xlabel 'play time (s)'\nset ylabel '|F| (N)'\n"
          << "plot '" << plotCsv << "' every ::1 using 1:($6*0.3) with filledcurves y=0 "
          << "lc rgb '#d8e8d0' title 'on the head', '' every ::1 using 1:($3*0.15) with steps "
          << "lc rgb '#888888' title 'contact', '' every ::1 using 1:2 with lines lw 1 "
          << "lc rgb '#1f5fbf' title '|F|'\n"
          << "set ylabel 'height under the finger (mm)'\n"
          << "plot '" << plotCsv << "' every ::1 using 1:5 with lines lw 1 lc rgb '#c05000' "
          << "title 'surface', '' every ::1 using 1:4 with lines lw 1 "
          << "lc rgb '#1f5fbf' title 'finger'\n"
          << "set xlabel 'frequency (Hz)'\nset ylabel 'PSD (N^2/Hz)'\nset logscale y\n"
          << "set format y '10^{%L}'\n"
          << "plot '" << psdCsv << "' every ::1 using 1:2 with lines lw 1 lc rgb '#1f5fbf' "
          << "title 'force PSD'\n"
          << "unset multiplot\n";
    }
    if (!writeDemoFile(psdCsv, psdText.str(), lost) ||
        !writeDemoFile(plotCsv, plotText.str(), lost) ||
        !writeDemoFile(script, scriptText.str(), lost))
        return "not drawn: " + lost;
    const platform::PlotStatus st = platform::runGnuplot(script);
    return st == platform::PlotStatus::Drawn ? dir + "/force.png" : platform::plotStatusNote(st);
}

} // namespace depthtouch::demo
