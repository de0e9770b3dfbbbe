#pragma once
/// \file
/// \brief The gnuplot charts of `depthtouch bench render`, private to dt_render_bench: each writer
/// makes its chart's data file and script in the output folder (render_bench_report.cpp runs
/// gnuplot on them). Thread-safety: reentrant (each call writes its own files).

#include <filesystem>
#include <string>
#include <vector>

#include "depthtouch/render/render_bench.h"

namespace depthtouch::render::bench::detail {

/// \return whether the rows of the first source and depth size carry the stage pass (not so with
/// --no-stages): only then is there a stages.png to draw.
bool stagePassRun(const std::vector<BenchRow> &rows) noexcept;

/// \brief fps_vs_error.dat/.gp: frame rate against mean geometric error of the first source and
/// size, one line per family (colour and point type), each point labelled apart from the others,
/// the goals (30 fps, a mean error of 0.5 levels) named in the key.
/// \param[out] error the first file that could not be written (left as is when all were).
void writeFpsChart(const std::vector<BenchRow> &rows, const std::filesystem::path &base,
                   std::string &error);

/// \brief stages.dat/.gp: stacked stage medians, one bar per setting of the first source and size.
/// Only for rows with the stage pass (stagePassRun()). \param[out] error as writeFpsChart().
void writeStagesChart(const std::vector<BenchRow> &rows, const std::filesystem::path &base,
                      std::string &error);

/// \brief cpu_vs_depth_size.dat/.gp: the render thread's (geom_cpu_ms) and the prep thread's
/// (prep_cpu_ms) CPU time per frame. With several depth sizes: against the depth size, one panel
/// row per source, one line per setting run at more than one size; with one size: against the
/// mesh's triangles, one line per family. The render thread's goals are named lines.
/// \param[out] error as writeFpsChart().
void writeCpuChart(const std::vector<BenchRow> &rows, const std::filesystem::path &base,
                   std::string &error);

} // namespace depthtouch::render::bench::detail
