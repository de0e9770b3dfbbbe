#pragma once
/// \file
/// \brief `depthtouch bench feel`'s chart, written by writeFeelOutputs() (feel_report.cpp);
/// internal to the bench library.

#include <filesystem>
#include <string>

#include "depthtouch/haptics/feel_bench.h"

namespace depthtouch::haptics::bench {

/// The chart: which renderer setting is both accurate and robust, and at what cost. Writes
/// \a base/feel.gp and renders feel.png (gnuplot, where installed): three panels, one labelled
/// point per setting. \return false (\a error set) when it could not be written.
bool writeChartScript(const FeelReport &report, const std::filesystem::path &base,
                      std::string &error);

} // namespace depthtouch::haptics::bench
