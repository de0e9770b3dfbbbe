#pragma once
/// \file
/// \brief The demo's force chart (`depthtouch demo`): the force log's rows set against the surface
/// (demo_feel.h measureFeel()'s plot columns) and their force spectrum, written into the output
/// folder as force-plot.csv, force-psd.csv and force.gp, drawn into force.png by gnuplot. Each file
/// is written whole (a temporary name, renamed when complete). Units: s, N, mm, Hz.
/// Thread-safety: reentrant (no shared state); runs gnuplot as a child process.

#include <array>
#include <string>
#include <vector>

namespace depthtouch::demo {

/// \brief Writes force-plot.csv, force-psd.csv (the |F| column's averaged PSD, \a rate Hz) and the
/// chart script into \a dir; runs gnuplot.
/// \param plot per row: play time s, |F| N, contact 0/1, HIP z mm, surface z mm, on the figure 0/1.
/// \return a note for the summary: the chart's path, why it was not drawn, or "force log too short
/// for a chart" (under 256 rows); \a lost is set to the one line of a file that could not be
/// written (when it is still empty).
std::string chartForce(const std::string &dir, const std::vector<std::array<double, 6>> &plot,
                       double rate, std::string &lost);

} // namespace depthtouch::demo
