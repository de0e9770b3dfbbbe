/// \file
/// \brief `depthtouch bench render` over several depth sizes, and its end: see runDepthSizes() and
/// finishRenderBench() in render_bench.h.

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "depthtouch/render/render_bench.h"
#include "render_bench_charts.h"

namespace depthtouch::render::bench {

std::optional<DepthSizesError> runDepthSizes(const DepthSizesPlan &plan, BenchOptions &bo,
                                             std::vector<BenchRow> &rows,
                                             std::vector<RgbdFrame> &firstFrames)
{
    const std::vector<std::pair<int, int>> &sizes = plan.sizes;
    for (std::size_t si = 0; si < sizes.size(); ++si) {
        const auto [w, h] = sizes[si];
        // Fewer frames of a larger size: about the memory of 60 frames of 720×486.
        const double area = static_cast<double>(w) * h;
        const int count = std::clamp(static_cast<int>(60.0 * 720.0 * 486.0 / area), 8, 60);
        for (const char *source : {"kitchen", "head"}) {
            const bool kitchen = source[0] == 'k';
            if (!kitchen && !plan.withHead)
                continue;
            auto frames = kitchen ? loadKitchenFrames(plan.scene, count, w, h)
                                  : loadHeadFrames(std::min(count, 12), w, h);
            if (!frames)
                return DepthSizesError{true, std::string("cannot make the ") + source +
                                                 " frames: " + frames.error().what};
            const bool first = si == 0 && kitchen;
            bo.source = source;
            bo.configs = first || plan.allConfigs ? plan.configs : depthSizeConfigs();
            bo.framesPerConfig = first ? plan.frames : std::max(5, plan.frames / 4);
            bo.warmup = first ? 5 : 2;
            bo.stageBreakdown = first && plan.stages;
            auto part = runRenderBenchmark(*frames, bo);
            if (!part)
                return DepthSizesError{false, part.error().what};
            rows.insert(rows.end(), part->begin(), part->end());
            if (first)
                firstFrames = std::move(*frames);
        }
    }
    return std::nullopt;
}

bool finishRenderBench(const std::vector<BenchRow> &rows, const BenchOptions &options,
                       const std::vector<RgbdFrame> &firstFrames, const std::string &out,
                       std::string &error)
{
    printTable(rows, options);
    std::string note;
    if (!writeBenchOutputs(rows, out, error, note))
        return false;
    const std::string snap = out + "/kitchen_sbs.png";
    if (auto r = writeSideBySideSnapshot(firstFrames, 0, MeshOptions{}, options.outputWidth,
                                         options.outputHeight, snap);
        !r)
        std::fprintf(stderr, "depthtouch bench render: snapshot not written: %s\n", r.error().what);
    if (!note.empty())
        std::printf("note: %s\n", note.c_str());
    std::printf("wrote %s/{render_bench.csv,fps_vs_error.png,%scpu_vs_depth_size.png,"
                "kitchen_sbs.png}\n",
                out.c_str(), detail::stagePassRun(rows) ? "stages.png," : "");
    return true;
}

} // namespace depthtouch::render::bench
