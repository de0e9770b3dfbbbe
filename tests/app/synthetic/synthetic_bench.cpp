// Frame rate of the synthetic scenes at 720×486 on the headless EGL display: render, then read
// back color (RGB24) and nearness (16-bit), as the encoder does for every frame. Besides the wall
// time, reports the process CPU time per frame (all llvmpipe threads): on a loaded machine the wall
// time measures the load, the CPU time the work.
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <vector>

#include <benchmark/benchmark.h>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/synthetic/synthetic_scene.h"

namespace {

using namespace depthtouch;

void renderScene(benchmark::State &state, const char *name)
{
    constexpr int kW = 720;
    constexpr int kH = 486;
    auto display = drivers::createDisplay("headless", {});
    if (!display || !(*display)->open({}) || !(*display)->makeCurrent()) {
        state.SkipWithError("No headless EGL display");
        return;
    }
    auto scene = synthetic::SyntheticScene::create(name, kW, kH, 30.0);
    if (!scene) {
        state.SkipWithError(scene.error().what);
        return;
    }
    std::vector<std::uint8_t> rgb(kW * kH * 3);
    std::vector<std::uint8_t> near(kW * kH * 2);
    hal::ImageView color;
    color.width = kW;
    color.height = kH;
    color.format = hal::PixelFormat::Rgb24;
    color.planes[0] = {rgb.data(), kW * 3};
    hal::ImageView depth = color;
    depth.format = hal::PixelFormat::Gray16;
    depth.planes[0] = {near.data(), kW * 2};
    // Warm-up: llvmpipe compiles the shaders at the first draw.
    if (!(*scene)->render(0, color, depth)) {
        state.SkipWithError("render failed");
        return;
    }
    std::uint64_t frame = 0;
    const std::clock_t cpu0 = std::clock();
    for (auto _ : state) {
        if (!(*scene)->render(frame++, color, depth)) {
            state.SkipWithError("render failed");
            break;
        }
        benchmark::DoNotOptimize(rgb.data());
    }
    const double cpuSeconds = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
    state.SetItemsProcessed(static_cast<std::int64_t>(frame));
    if (frame > 0)
        state.counters["process_cpu_ms_per_frame"] =
            1000.0 * cpuSeconds / static_cast<double>(frame);
}

BENCHMARK_CAPTURE(renderScene, head, "head")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(renderScene, spheres, "spheres")->Unit(benchmark::kMillisecond)->UseRealTime();

} // namespace

BENCHMARK_MAIN();
