/// \file
/// \brief `depthtouch bench render`: frame rate (median, p99 frame time) against mean/max geometric
/// error of the stereo renderer's meshes (full, fixed decimations, adaptive at several tolerances),
/// side-by-side on real RGB-D frames (7-Scenes redkitchen at 720×486), with a per-stage breakdown
/// of the frame and the render thread's CPU time for the depth geometry (geom_cpu_ms), at one depth
/// size or several (--depth-sizes: the kitchen and the synthetic head at each); writes
/// render_bench.csv, fps_vs_error.png, stages.png, cpu_vs_depth_size.png and a side-by-side
/// snapshot into --out and prints the tables. The GL context comes
/// from a Display backend (--display, default headless).

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bench_options.h"
#include "commands.h"
#include "option_cli.h"
#include "output_paths.h"

#if __has_include("depthtouch/render/render_bench.h")
#include "depthtouch/drivers/backends.h"
#include "depthtouch/render/render_bench.h"
#define DT_CLI_HAVE_RENDER 1
#else
#define DT_CLI_HAVE_RENDER 0
#endif

namespace depthtouch::cli {

namespace {

struct BenchRenderOptions {
    std::string display = "headless";
    std::string data;
    std::string out = "bench-out/render";
    int frames = 60;
    int width = 1440;
    int height = 486;
    int depthWidth = 720;
    int depthHeight = 486;
    std::vector<std::string> depthSizes;
    std::string only;
    bool stages = true;
};

/// What `bench render` measures (its line in `depthtouch bench --help`).
constexpr const char *kAbout = "Stereo renderer: frame rate vs geometric error of full, decimated "
                               "and adaptive meshes; CSV/PNG";

/// The options of `bench render`, in `--help` order.
const OptionRow<BenchRenderOptions> kBenchRenderRows[] = {
    {"display", &BenchRenderOptions::display, "Display backend providing the GLES context"},
    sharedDataRow<BenchRenderOptions>(),
    benchOutRow<BenchRenderOptions>(),
    {"frames", &BenchRenderOptions::frames, "Timed frames per mesh setting"},
    {"width", &BenchRenderOptions::width, "Side-by-side output width, pixels (two eyes)"},
    {"height", &BenchRenderOptions::height, "Output height, pixels"},
    {"depth-width", &BenchRenderOptions::depthWidth, "Depth frame width the data is resampled to"},
    {"depth-height", &BenchRenderOptions::depthHeight, "Depth frame height"},
    {"depth-sizes",
     &BenchRenderOptions::depthSizes,
     "Depth sizes WxH to run (the kitchen resampled and the synthetic head at each; replaces "
     "--depth-width/--depth-height; after the first: full,step4,quadtree-0.50,budget-6k unless "
     "--only, a quarter of --frames, no stage pass)",
     {},
     kCommaList},
    {"only", &BenchRenderOptions::only,
     "Comma-separated mesh settings to run (e.g. full,adaptive-0.5; default all)"},
    {"no-stages", &BenchRenderOptions::stages, "Skip the per-stage breakdown pass", {}, kNegated},
};

#if DT_CLI_HAVE_RENDER
/// Opens the display backend \a o.display at the output size with its GLES context current.
/// \return kExitOk, or the exit code of the failure (its line printed).
int openGlDisplay(const BenchRenderOptions &o, std::unique_ptr<hal::Display> &out)
{
    hal::SelectionReport report;
    auto display = drivers::createDisplay(o.display, hal::BackendConfig{}, &report);
    if (!display) {
        std::fprintf(stderr, "depthtouch bench render: %s\n",
                     report.message.empty() ? display.error().what : report.message.c_str());
        return display.error().code == Errc::InvalidArgument ? kExitBadInput : kExitFailure;
    }
    if (!(*display)->capabilities().hasGlesContext) {
        std::fprintf(stderr,
                     "depthtouch bench render: display backend '%s' has no OpenGL ES context\n",
                     report.chosen.c_str());
        return kExitBadInput;
    }
    hal::DisplayConfig dc;
    dc.width = o.width;
    dc.height = o.height;
    if (auto r = (*display)->open(dc); !r) {
        std::fprintf(stderr, "depthtouch bench render: cannot open the display: %s\n",
                     r.error().what);
        return kExitFailure;
    }
    if (auto r = (*display)->makeCurrent(); !r) {
        std::fprintf(stderr, "depthtouch bench render: cannot make the GL context current: %s\n",
                     r.error().what);
        return kExitFailure;
    }
    out = std::move(*display);
    return kExitOk;
}

/// The depth sizes to run: --depth-sizes, else --depth-width × --depth-height.
/// \return false (its line printed) for a size that is not WxH.
bool depthSizesOf(const BenchRenderOptions &o, std::vector<std::pair<int, int>> &sizes)
{
    for (const std::string &text : o.depthSizes) {
        int w = 0;
        int h = 0;
        if (!render::bench::parseDepthSize(text, w, h)) {
            std::fprintf(stderr, "depthtouch bench render: --depth-sizes: '%s' is not WxH\n",
                         text.c_str());
            return false;
        }
        sizes.emplace_back(w, h);
    }
    if (sizes.empty())
        sizes.emplace_back(o.depthWidth, o.depthHeight);
    return true;
}

#endif

int runBenchRender(const BenchRenderOptions &o)
{
#if DT_CLI_HAVE_RENDER
    // An --out where nothing can be written fails now, not after the whole run.
    if (const int rc = checkOutFolder("bench render", o.out); rc != kExitOk)
        return rc;
    using namespace depthtouch::render;
    if (o.frames < 5 || o.width < 16 || o.height < 16 || o.depthWidth < 2 || o.depthHeight < 2) {
        std::fprintf(stderr, "depthtouch bench render: --frames must be >= 5 and sizes positive\n");
        return kExitBadInput;
    }
    const std::string scene = sharedDataFolder(o.data) + "/rgbd-7scenes-redkitchen";
    if (!std::filesystem::exists(scene + "/frame-000000.depth.png")) {
        std::fprintf(
            stderr,
            "depthtouch bench render: no 7-Scenes frames in %s (use --data or DT_SHARED_DATA)\n",
            scene.c_str());
        return kExitBadInput;
    }
    std::unique_ptr<hal::Display> display;
    if (const int code = openGlDisplay(o, display); code != kExitOk)
        return code;
    auto configs = bench::selectConfigs(o.only);
    if (!configs) {
        std::fprintf(stderr, "depthtouch bench render: --only: %s\n", configs.error().what);
        return kExitBadInput;
    }
    std::vector<std::pair<int, int>> sizes;
    if (!depthSizesOf(o, sizes))
        return kExitBadInput;
    bench::BenchOptions bo;
    bo.outputWidth = o.width;
    bo.outputHeight = o.height;
    bo.presentFramebuffer = display->framebuffer();
    std::vector<bench::BenchRow> rows;
    std::vector<bench::RgbdFrame> firstFrames;
    const bench::DepthSizesPlan plan{
        scene, sizes, !o.depthSizes.empty(), !o.only.empty(), o.frames, o.stages, *configs};
    if (const auto e = bench::runDepthSizes(plan, bo, rows, firstFrames)) {
        std::fprintf(stderr, "depthtouch bench render: %s\n", e->message.c_str());
        return e->badInput ? kExitBadInput : kExitFailure;
    }
    bo.stageBreakdown = o.stages;
    bo.framesPerConfig = o.frames;
    if (std::string error; !bench::finishRenderBench(rows, bo, firstFrames, o.out, error)) {
        std::fprintf(stderr, "depthtouch bench render: %s\n", error.c_str());
        return kExitFailure;
    }
    display->close();
    return kExitOk;
#else
    (void)o;
    std::fprintf(stderr,
                 "depthtouch bench render: built without the GLES renderer (EGL/GLES not found)\n");
    return kExitFailure;
#endif
}

} // namespace

void registerBenchRenderCommand(CLI::App &bench, int &exitCode)
{
    addTableCommand<BenchRenderOptions>(bench, "render", kAbout, kBenchRenderRows, runBenchRender,
                                        exitCode);
}

} // namespace depthtouch::cli
