/// \file
/// \brief The benchmark's report: the printed tables, render_bench.csv and the gnuplot charts
/// (render_bench.h).

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "depthtouch/platform/gnuplot.h"
#include "depthtouch/platform/report_file.h"
#include "depthtouch/render/render_bench.h"

namespace depthtouch::render::bench {

namespace {

/// Whether \a r is of the first source and depth size (what the frame-rate charts show).
bool firstSet(const std::vector<BenchRow> &rows, const BenchRow &r)
{
    return !rows.empty() && r.source == rows.front().source &&
           r.depthWidth == rows.front().depthWidth && r.depthHeight == rows.front().depthHeight;
}

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

/// fps_vs_error.dat/.gp: one line per family, the rows of the first source and size.
void writeFpsChart(const std::vector<BenchRow> &rows, const std::filesystem::path &base,
                   std::string &error)
{
    static constexpr const char *kFamilies[] = {"fixed",   "adaptive", "quadtree",
                                                "budgets", "blocks",   "block budgets"};
    static constexpr const char *kTitles[] = {
        "fixed step (full, 2, 4, 8)",      "adaptive per tile (tolerance)",
        "quadtree (mean error budget)",    "quadtree-0.50 under a block budget",
        "blocks: a step per tile, ranges", "blocks-0.40 under a cell budget"};
    static constexpr const char *kColors[] = {"#1f77b4", "#2ca02c", "#d62728",
                                              "#9467bd", "#ff7f0e", "#8c564b"};
    // Labels placed apart per family: right, left, above, below the point.
    static constexpr const char *kOffsets[] = {"1.2,0.6",   "-1.2,-0.9", "1.0,1.1",
                                               "-1.0,-1.3", "1.2,-0.9",  "-1.2,0.9"};
    static constexpr const char *kAlign[] = {"left", "right", "left", "right", "left", "right"};
    constexpr int kFamilyCount = 6;
    // One data block per family that has rows (gnuplot's `index` counts the blocks written).
    std::vector<int> present;
    {
        platform::TextReportFile d((base / "fps_vs_error.dat").string(), error);
        for (int k = 0; k < kFamilyCount; ++k) {
            const bool any = std::any_of(rows.begin(), rows.end(), [&](const BenchRow &r) {
                return firstSet(rows, r) && r.family == kFamilies[k];
            });
            if (!any)
                continue;
            present.push_back(k);
            d << "# " << kFamilies[k] << '\n';
            for (const BenchRow &r : rows)
                if (firstSet(rows, r) && r.family == kFamilies[k])
                    d << r.meanError << ' ' << r.fps << " \"" << r.name << "\"\n";
            d << "\n\n";
        }
    }
    const std::string src = rows.empty() ? std::string()
                                         : rows.front().source + ' ' +
                                               std::to_string(rows.front().depthWidth) + 'x' +
                                               std::to_string(rows.front().depthHeight);
    platform::TextReportFile gp((base / "fps_vs_error.gp").string(), error);
    gp << "set terminal pngcairo size 1100,700 noenhanced font ',10'\n"
       << "set output '" << (base / "fps_vs_error.png").string() << "'\n"
       << "set title 'Stereo side-by-side, " << src << ": frame rate vs mean geometric error'\n"
       << "set xlabel 'mean geometric error (8-bit nearness levels)'\n"
       << "set ylabel 'frames per second (median)'\n"
       << "set grid\nset key bottom right box opaque\nset logscale x\n"
       << "set offsets graph 0.08, graph 0.22, graph 0.08, 0\nset yrange [0:*]\n"
       << "set arrow from 0.5, graph 0 to 0.5, graph 1 nohead dt 2 lc rgb 'gray40'\n"
       << "set arrow from graph 0, first 30 to graph 1, first 30 nohead dt 2 lc rgb 'gray40'\n"
       << "plot ";
    // The full mesh has zero error: drawn at 0.1 on the log axis.
    for (std::size_t i = 0; i < present.size(); ++i) {
        const int k = present[i];
        const std::string file = i == 0 ? "'" + (base / "fps_vs_error.dat").string() + "'" : "''";
        gp << (i == 0 ? "" : ", \\\n     ") << file << " index " << i
           << " using ($1 < 0.1 ? 0.1 : $1):2 with linespoints lw 2 pt 7 lc rgb '" << kColors[k]
           << "' title '" << kTitles[k] << "', \\\n     '' index " << i
           << " using ($1 < 0.1 ? 0.1 : $1):2:3 with labels " << kAlign[k] << " offset "
           << kOffsets[k] << " tc rgb '" << kColors[k] << "' notitle";
    }
    if (present.empty())
        gp << "NaN notitle";
    gp << '\n';
}

/// stages.dat/.gp: stacked stage medians, one bar per setting of the first source and size.
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
       << "colours = '#1f77b4 #ff7f0e #2ca02c #d62728 #9467bd #8c564b #e377c2 #7f7f7f #17becf'\n"
       << "plot for [k=2:" << (kStageCount + 1) << "] '" << (base / "stages.dat").string()
       << "' using k:xtic(1) lc rgb word(colours, k-1) title columnheader(k)\n";
}

/// cpu_vs_depth_size.dat/.gp: two panels, the render thread's geometry CPU (geom_cpu_ms) and the
/// prep thread's (prep_cpu_ms) per frame against the depth size, one line per setting of the first
/// source (the kitchen), the key below, the goals as labelled dotted lines.
void writeCpuChart(const std::vector<BenchRow> &rows, const std::filesystem::path &base,
                   std::string &error)
{
    if (rows.empty())
        return;
    const std::string source = rows.front().source;
    std::vector<std::string> series;
    for (const BenchRow &r : rows)
        if (r.source == source && std::find(series.begin(), series.end(), r.name) == series.end())
            series.push_back(r.name);
    {
        platform::TextReportFile d((base / "cpu_vs_depth_size.dat").string(), error);
        for (const std::string &name : series) {
            d << "# " << name << '\n';
            for (const BenchRow &r : rows)
                if (r.source == source && r.name == name)
                    d << static_cast<double>(r.depthWidth) * r.depthHeight / 1e6 << ' '
                      << std::max(r.geomCpuMs, 1e-3) << ' ' << std::max(r.prepCpuMs, 1e-3) << '\n';
            d << "\n\n";
        }
    }
    static constexpr const char *kColors[] = {"#1f77b4", "#2ca02c", "#d62728", "#9467bd",
                                              "#ff7f0e", "#8c564b", "#17becf", "#7f7f7f"};
    const std::string dat = "'" + (base / "cpu_vs_depth_size.dat").string() + "'";
    platform::TextReportFile gp((base / "cpu_vs_depth_size.gp").string(), error);
    gp << "set terminal pngcairo size 1200,620 noenhanced font ',10'\n"
       << "set output '" << (base / "cpu_vs_depth_size.png").string() << "'\n"
       << "set multiplot layout 1,2 title 'CPU time per frame for the depth geometry vs depth "
          "size (median, "
       << source << "; 0.001 ms = none)'\n"
       << "set logscale xy\nset grid\nset xrange [0.25:12]\nset yrange [0.001:300]\n"
       << "set xlabel 'depth samples, millions (720x486: 0.35, 1920x1080: 2.07, 3840x2160: 8.29)' "
          "offset 0,0.6\n"
       << "set key below horizontal maxcols 3 box\n"
       << "set style line 99 dt 3 lw 1.5 lc rgb 'gray30'\n";
    const auto goal = [&gp](double ms, const char *text, bool above) {
        gp << "set arrow from graph 0, first " << ms << " to graph 1, first " << ms
           << " nohead ls 99\nset label '" << text << "' at graph 0.02, first "
           << (above ? ms * 1.35 : ms / 1.45) << " tc rgb 'gray20'\n";
    };
    const auto panel = [&](const char *title, int column) {
        gp << "set title '" << title << "'\nset ylabel 'ms per frame (thread CPU time)'\nplot ";
        for (std::size_t k = 0; k < series.size(); ++k)
            gp << (k == 0 ? "" : ", \\\n     ") << (k == 0 ? dat : "''") << " index " << k
               << " using 1:" << column << " with linespoints lw 2 pt 7 lc rgb '" << kColors[k % 8]
               << "' title '" << series[k] << "'";
        gp << '\n';
    };
    goal(3.0, "goal at 3840x2160: 3 ms", true);
    goal(0.5, "goal, quadtree at 720x486: 0.5 ms", true);
    goal(0.3, "goal, full mesh at 720x486: 0.3 ms", false);
    panel("render thread (geom_cpu_ms: index choice, depth upload, mapping)", 2);
    // The prep thread's goal is a shape, not a line: no growth with the triangles drawn.
    gp << "unset arrow\nunset label\n";
    panel("prep thread (prep_cpu_ms: level of detail, not to grow with the triangles)", 3);
    gp << "unset multiplot\n";
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
    writeFpsChart(rows, base, error);
    writeStagesChart(rows, base, error);
    writeCpuChart(rows, base, error);
    if (!error.empty())
        return false;
    platform::PlotStatus plot = platform::runGnuplot((base / "fps_vs_error.gp").string());
    if (plot == platform::PlotStatus::Drawn)
        plot = platform::runGnuplot((base / "stages.gp").string());
    if (plot == platform::PlotStatus::Drawn)
        plot = platform::runGnuplot((base / "cpu_vs_depth_size.gp").string());
    if (plot != platform::PlotStatus::Drawn)
        note = std::string(platform::plotStatusNote(plot)) + "; CSV written";
    return true;
}

} // namespace depthtouch::render::bench
