// Frame rate of the `synthetic:` source (app/cli/source_providers.h) as `depthtouch encode` pulls
// it: one color (Rgb24) and one depth (Gray8 nearness) frame per pair. Cases: the two streams
// sharing one renderer (what encode does), two independent renderers (each frame drawn twice),
// and color alone; at 720×486 and 320×240. Besides the wall time, the process CPU time per pair
// (every llvmpipe and render thread): on a loaded machine the wall time measures the load.
#include <ctime>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "depthtouch/media/frame_source.h"
#include "source_providers.h"

namespace {

using namespace depthtouch;

enum class Mode { Shared, Separate, ColorOnly };

void pullPairs(benchmark::State &state, Mode mode)
{
    const std::string spec = "synthetic:head,size=" + std::to_string(state.range(0)) + "x" +
                             std::to_string(state.range(1)) + ",frames=0";
    const media::SourceProviders a = cli::makeSourceProviders();
    const media::SourceProviders b = cli::makeSourceProviders();
    media::SourceOptions colorOptions;
    colorOptions.streamTitle = "color";
    media::SourceOptions depthOptions;
    depthOptions.streamTitle = "depth";
    auto color = media::openFrameSource(spec, colorOptions, a);
    if (!color) {
        state.SkipWithError(color.error().what);
        return;
    }
    std::unique_ptr<media::FrameSource> depth;
    if (mode != Mode::ColorOnly) {
        auto d = media::openFrameSource(spec, depthOptions, mode == Mode::Shared ? a : b);
        if (!d) {
            state.SkipWithError(d.error().what);
            return;
        }
        depth = std::move(*d);
    }
    // Warm-up: llvmpipe compiles the shaders at the first draw.
    if (!(*color)->next(media::PixelFormat::Rgb24) ||
        (depth && !depth->next(media::PixelFormat::Gray8))) {
        state.SkipWithError("first frame failed");
        return;
    }
    long long pairs = 0;
    const std::clock_t cpu0 = std::clock();
    for (auto _ : state) {
        auto c = (*color)->next(media::PixelFormat::Rgb24);
        if (!c || (depth && !depth->next(media::PixelFormat::Gray8))) {
            state.SkipWithError("frame failed");
            break;
        }
        benchmark::DoNotOptimize(c->image.data.data());
        ++pairs;
    }
    const double cpuSeconds = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
    state.SetItemsProcessed(pairs);
    if (pairs > 0)
        state.counters["cpu_ms_per_pair"] = 1000.0 * cpuSeconds / static_cast<double>(pairs);
}

void sizes(benchmark::internal::Benchmark *b)
{
    b->Args({720, 486})
        ->Args({320, 240})
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->MinTime(3.0);
}

BENCHMARK_CAPTURE(pullPairs, shared, Mode::Shared)->Apply(sizes);
BENCHMARK_CAPTURE(pullPairs, separate, Mode::Separate)->Apply(sizes);
BENCHMARK_CAPTURE(pullPairs, color_only, Mode::ColorOnly)->Apply(sizes);

} // namespace

BENCHMARK_MAIN();
