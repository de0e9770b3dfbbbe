/// \file
/// \brief The benchmark's report: the printed tables, render_bench.csv, and gnuplot run on the
/// charts of render_bench_charts.cpp (render_bench.h).

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

#include "depthtouch/platform/gnuplot.h"
#include "depthtouch/platform/report_file.h"
#include "depthtouch/render/render_bench.h"
#include "render_bench_charts.h"

namespace depthtouch::render::bench {

namespace {

void printStages(const std::vector<BenchRow> &rows)
{
    std::printf(
        "\nstage breakdown, median ms (glFinish after each stage, so each carries its own\n"
        "rasterization; same frames, second pass); sum = median of the per-frame sums, with "
        "p99\n\n");
    std::printf("%-8s %-9s %-14s", "source", "depth", "mesh");
    for (int k = 0; k < kStageCount; ++k)
        std::printf(" %7s", stageName(k));
    std::printf(" %8s %8s\n", "sum", "sum p99");
    for (const BenchRow &r : rows) {
        if (!(r.stagedMedianMs > 0.0))
            continue; // a run without the stage pass (--depth-sizes after the first)
        std::printf("%-8s %4dx%-4d %-14s", r.source.c_str(), r.depthWidth, r.depthHeight,
                    r.name.c_str());
        for (const double v : r.stageMedianMs)
            std::printf(" %7.2f", v);
        std::printf(" %8.2f %8.2f\n", r.stagedMedianMs, r.stagedP99Ms);
    }
}

/// Runs gnuplot on each of \a scripts in \a base, its messages into gnuplot.log there (never amid
/// the printed tables). \return a note for the user: gnuplot missing or failed, and its first
/// message ("" when it drew every chart without a word).
std::string drawCharts(const std::filesystem::path &base, const std::vector<std::string> &scripts)
{
    namespace fs = std::filesystem;
    const fs::path log = base / "gnuplot.log";
    std::error_code ec;
    fs::remove(log, ec);
    std::fflush(stdout);
    platform::PlotStatus plot = platform::PlotStatus::Drawn;
    for (const std::string &script : scripts) {
        plot = platform::runGnuplot((base / script).string(), log.string());
        if (plot != platform::PlotStatus::Drawn)
            break;
    }
    std::string note;
    if (plot != platform::PlotStatus::Drawn)
        note = std::string(platform::plotStatusNote(plot)) + "; CSV written";
    std::ifstream in(log);
    std::string first;
    int lines = 0;
    for (std::string line; std::getline(in, line);)
        if (!line.empty() && lines++ == 0)
            first = line;
    if (lines == 0) {
        fs::remove(log, ec);
        return note;
    }
    return note + (note.empty() ? "" : "; ") + "gnuplot: " + first +
           (lines > 1 ? " (and " + std::to_string(lines - 1) + " more lines)" : "") + ", in " +
           log.string();
}

} // namespace

void printTable(const std::vector<BenchRow> &rows, const BenchOptions &options)
{
    std::printf(
        "\nstereo %s %dx%d output, %d frames per setting. Frame = depth and colour upload, mesh\n"
        "choice, both eyes, avatar, OSD, blit and glFinish (median, p99); cpu = process CPU time "
        "per\nframe, all threads; geom = render-thread CPU time of the frame's depth geometry "
        "(setDepth\nwith the mesh made ahead: index selection, depth texture, mapping; median, "
        "p99); prep = CPU\ntime of making the mesh ahead (the player's prep thread; here before "
        "the "
        "frame); draw = both\neyes' draw calls on the calling thread; error = |mesh - samples| in "
        "8-bit nearness levels\n\n",
        stereoModeName(options.mode), options.outputWidth, options.outputHeight,
        options.framesPerConfig);
    std::printf("%-8s %-9s %-14s %9s %9s %8s %6s %8s %8s %8s %8s %8s %10s %9s %5s\n", "source",
                "depth", "mesh", "triangles", "median ms", "p99 ms", "fps", "cpu ms", "geom ms",
                "geom p99", "prep ms", "draw ms", "mean error", "max error", "uncov");
    for (const BenchRow &r : rows)
        std::printf("%-8s %4dx%-4d %-14s %9.0f %9.2f %8.2f %6.1f %8.2f %8.3f %8.3f %8.2f %8.2f "
                    "%10.3f %9.1f %5zu\n",
                    r.source.c_str(), r.depthWidth, r.depthHeight, r.name.c_str(), r.meanTriangles,
                    r.medianMs, r.p99Ms, r.fps, r.cpuMs, r.geomCpuMs, r.geomCpuP99Ms, r.prepCpuMs,
                    r.drawMs, r.meanError, r.maxError, r.uncovered);
    if (options.stageBreakdown)
        printStages(rows);
}

bool writeBenchOutputs(const std::vector<BenchRow> &rows, const std::string &dir,
                       std::string &error, std::string &note)
{
    namespace fs = std::filesystem;
    if (!platform::createReportFolder(dir, "cannot create " + dir, error))
        return false;
    const fs::path base(dir);
    {
        platform::TextReportFile csv((base / "render_bench.csv").string(), error);
        csv << "source,depth_size,mesh,family,tolerance_levels,step,triangles,median_ms,p99_ms,fps,"
               "cpu_ms,geom_cpu_ms,geom_cpu_p99_ms,prep_cpu_ms,mesh_ms,draw_ms,mean_error_levels,"
               "max_error_levels,uncovered";
        for (int k = 0; k < kStageCount; ++k)
            csv << ",stage_" << stageName(k) << "_median_ms,stage_" << stageName(k) << "_p99_ms";
        csv << ",staged_median_ms,staged_p99_ms\n";
        for (const BenchRow &r : rows) {
            csv << r.source << ',' << r.depthWidth << 'x' << r.depthHeight << ',' << r.name << ','
                << r.family << ',' << r.tolerance << ',' << r.step << ',' << r.meanTriangles << ','
                << r.medianMs << ',' << r.p99Ms << ',' << r.fps << ',' << r.cpuMs << ','
                << r.geomCpuMs << ',' << r.geomCpuP99Ms << ',' << r.prepCpuMs << ',' << r.meshMs
                << ',' << r.drawMs << ',' << r.meanError << ',' << r.maxError << ',' << r.uncovered;
            for (std::size_t k = 0; k < kStageCount; ++k)
                csv << ',' << r.stageMedianMs[k] << ',' << r.stageP99Ms[k];
            csv << ',' << r.stagedMedianMs << ',' << r.stagedP99Ms << '\n';
        }
        if (!csv.close())
            return false;
    }
    // Each file is written whole when its writer's scope ends; the first failure is in error.
    std::vector<std::string> scripts = {"fps_vs_error.gp", "cpu_vs_depth_size.gp"};
    detail::writeFpsChart(rows, base, error);
    detail::writeCpuChart(rows, base, error);
    if (detail::stagePassRun(rows)) {
        detail::writeStagesChart(rows, base, error);
        scripts.emplace_back("stages.gp");
    } else { // a run without the stage pass leaves no earlier run's chart to be taken for its own
        std::error_code ec;
        for (const char *name : {"stages.png", "stages.dat", "stages.gp"})
            fs::remove(base / name, ec);
    }
    if (!error.empty())
        return false;
    note = drawCharts(base, scripts);
    return true;
}

} // namespace depthtouch::render::bench
