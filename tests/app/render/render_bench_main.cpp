/// \file
/// \brief `render_bench [OUT_DIR] [FRAMES] [SETTINGS]`: the `depthtouch bench render` figures on
/// the tests' surfaceless GLES context (no Display backend needed); SETTINGS is a comma-separated
/// list of mesh settings (default all). Reads DT_SHARED_DATA; exits 77 without it.

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "app/render/egl_test_context.h"
#include "depthtouch/render/render_bench.h"

using namespace depthtouch::render;

int main(int argc, char **argv)
{
    const std::string out = argc > 1 ? argv[1] : "bench-out/render";
    const int frames = argc > 2 ? std::atoi(argv[2]) : 60;
    const char *data = std::getenv("DT_SHARED_DATA");
    if (data == nullptr) {
        std::fprintf(stderr, "render_bench: set DT_SHARED_DATA to ../shared/data\n");
        return 77;
    }
    std::string why;
    auto ctx = depthtouch::test::EglTestContext::create(why);
    if (!ctx) {
        std::fprintf(stderr, "render_bench: no GLES 3 context: %s\n", why.c_str());
        return 77;
    }
    std::fprintf(stderr, "GL: %s\n", ctx->renderer().c_str());
    auto loaded =
        bench::loadKitchenFrames(std::string(data) + "/rgbd-7scenes-redkitchen", 60, 720, 486);
    if (!loaded) {
        std::fprintf(stderr, "render_bench: %s\n", loaded.error().what);
        return 1;
    }
    auto configs = bench::selectConfigs(argc > 3 ? argv[3] : "");
    if (!configs) {
        std::fprintf(stderr, "render_bench: %s\n", configs.error().what);
        return 2;
    }
    bench::BenchOptions o;
    o.framesPerConfig = std::max(frames, 5);
    o.configs = std::move(*configs);
    auto rows = bench::runRenderBenchmark(*loaded, o);
    if (!rows) {
        std::fprintf(stderr, "render_bench: %s\n", rows.error().what);
        return 1;
    }
    bench::printTable(*rows, o);
    std::string error;
    std::string note;
    if (!bench::writeBenchOutputs(*rows, out, error, note)) {
        std::fprintf(stderr, "render_bench: %s\n", error.c_str());
        return 1;
    }
    const MeshOptions snap;
    if (auto r =
            bench::writeSideBySideSnapshot(*loaded, 0, snap, 1440, 486, out + "/kitchen_sbs.png");
        !r)
        std::fprintf(stderr, "render_bench: snapshot: %s\n", r.error().what);
    if (!note.empty())
        std::printf("note: %s\n", note.c_str());
    std::printf("wrote %s/{render_bench.csv,fps_vs_error.png,stages.png,kitchen_sbs.png}\n",
                out.c_str());
    return 0;
}
