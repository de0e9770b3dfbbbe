#include "depthtouch/render/render_bench.h"

#include <GLES3/gl3.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>

#include "bench_frames.h"
#include "depthtouch/platform/cpu_time.h"
#include "depthtouch/platform/percentile.h"
#include "depthtouch/render/render_target.h"
#include "depthtouch/render/renderer.h"
#include "depthtouch/render/snapshot.h"

// The benchmark's settings and its timed loop (the frames: render_bench_data.cpp; the tables,
// CSV and charts: render_bench_report.cpp).

namespace depthtouch::render::bench {

using detail::colorView;
using detail::depthView;
using platform::percentile;

namespace {

/// Mesh options of a tiled mode: \a tile cells a tile side, also the coarsest step; error bound
/// \a tolerance; at most \a thousandBlocks thousand blocks (0: no budget).
MeshOptions tiledMesh(MeshMode mode, int tile, double tolerance, int thousandBlocks = 0)
{
    MeshOptions m;
    m.mode = mode;
    m.tileSize = tile;
    m.maxStep = tile;
    m.tolerance = tolerance;
    m.maxBlocks = static_cast<std::size_t>(thousandBlocks) * 1000;
    return m;
}

} // namespace

std::vector<BenchConfig> defaultConfigs()
{
    std::vector<BenchConfig> out;
    for (const int step : {1, 2, 4, 8}) {
        MeshOptions m;
        m.mode = MeshMode::Fixed;
        m.fixedStep = step;
        out.push_back({step == 1 ? "full" : "step" + std::to_string(step), m});
    }
    for (const double tol : {0.3, 0.5, 0.7, 0.9, 1.2}) {
        // per-tile steps: tile 8, mean criterion, cap 16 levels
        const MeshOptions m = tiledMesh(MeshMode::Adaptive, 8, tol);
        char name[32];
        std::snprintf(name, sizeof name, "adaptive-%.1f", tol);
        out.push_back({name, m});
    }
    for (const double tol : {0.3, 0.4, 0.45, 0.5, 0.6}) {
        // quadtree: root 32, frame mean error budget, cap 16 levels
        const MeshOptions m = tiledMesh(MeshMode::Quadtree, 32, tol);
        char name[32];
        std::snprintf(name, sizeof name, "quadtree-%.2f", tol);
        out.push_back({name, m});
    }
    for (const int thousands : {3, 6, 9, 12}) {
        // quadtree-0.50 under a leaf-block budget (what the player's LOD sets)
        const MeshOptions m = tiledMesh(MeshMode::Quadtree, 32, 0.5, thousands);
        char name[32];
        std::snprintf(name, sizeof name, "budget-%dk", thousands);
        out.push_back({name, m});
    }
    for (const int tile : {8, 16, 32})
        for (const double tol : {0.4, 0.5, 0.6}) {
            if (tile != 8 && tol != 0.5)
                continue;
            // a step per tile from probes, precomputed ranges (the player's LOD)
            const MeshOptions m = tiledMesh(MeshMode::Blocks, tile, tol);
            char name[32];
            if (tile == 8) // blocks-*: the player's tile size for the depth size (8 at 720x486)
                std::snprintf(name, sizeof name, "blocks-%.2f", tol);
            else
                std::snprintf(name, sizeof name, "blocks%d-%.2f", tile, tol);
            out.push_back({name, m});
        }
    for (const int thousands : {3, 6, 9}) {
        // blocks-0.40 (the player's tolerance) under a cell budget
        const MeshOptions m = tiledMesh(MeshMode::Blocks, 8, 0.4, thousands);
        char name[32];
        std::snprintf(name, sizeof name, "blocks-budget-%dk", thousands);
        out.push_back({name, m});
    }
    return out;
}

std::vector<BenchConfig> depthSizeConfigs()
{
    std::vector<BenchConfig> out;
    for (BenchConfig &c : defaultConfigs())
        if (c.name == "full" || c.name == "step4" || c.name == "quadtree-0.50" ||
            c.name == "budget-6k" || c.name == "blocks-0.40")
            out.push_back(std::move(c));
    return out;
}

Result<std::vector<BenchConfig>> selectConfigs(const std::string &names)
{
    std::vector<BenchConfig> all = defaultConfigs();
    if (names.empty())
        return all;
    std::vector<BenchConfig> out;
    std::size_t pos = 0;
    while (pos <= names.size()) {
        const std::size_t comma = std::min(names.find(',', pos), names.size());
        const std::string name = names.substr(pos, comma - pos);
        const auto it = std::find_if(all.begin(), all.end(),
                                     [&](const BenchConfig &c) { return c.name == name; });
        if (it == all.end())
            return unexpected(Errc::InvalidArgument,
                              "unknown mesh setting (see the table's first column)");
        out.push_back(*it);
        pos = comma + 1;
    }
    return out;
}

bool parseDepthSize(const std::string &text, int &width, int &height)
{
    int w = 0;
    int h = 0;
    char tail = 0;
    if (std::sscanf(text.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 2 || h < 2 || w > 8192 ||
        h > 8192)
        return false;
    width = w;
    height = h;
    return true;
}

const char *stageName(int i) noexcept
{
    static constexpr const char *kNames[kStageCount] = {
        "depth", "mesh", "index", "color", "clear", "eye1", "eye2", "overlay", "blit"};
    return i >= 0 && i < kStageCount ? kNames[i] : "?";
}

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// CPU time of the calling thread, ms (CLOCK_THREAD_CPUTIME_ID).
double threadCpuMs() noexcept
{
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

/// The per-frame inputs the player gives besides depth and colour: the avatar resting on the
/// middle of the surface with the HIP sunk below it, and the on-screen display.
void setOverlays(StereoRenderer &r)
{
    AvatarState avatar;
    avatar.visible = true;
    avatar.proxy = glm::dvec3(0.0, 0.0, 0.0);
    avatar.hip = glm::dvec3(0.0, 0.0, -0.002);
    r.setAvatar(avatar);
    OsdState osd;
    osd.visible = true;
    osd.status = "PLAYING";
    osd.hapticsOn = true;
    osd.force = 2.0;
    r.setOsd(osd);
}

/// CPU times of one frame's depth geometry, ms.
struct GeomCpu {
    double prep = 0.0;   ///< FramePrep::build() (the player's prep thread).
    double render = 0.0; ///< setDepth() with that prep (the render thread).
};

/// One frame as the player draws it: the mesh made ahead in \a prep (timed on its own), then
/// depth, colour, overlays, both eyes, blit. \a stages receives the stage times (ms) when not null.
Result<void> drawFrame(StereoRenderer &r, FramePrep &prep, const RgbdFrame &f,
                       const RenderTarget &target, std::uint32_t dst, GeomCpu &cpu,
                       std::array<double, kStageCount> *stages)
{
    const scene::DepthFrameView dv = depthView(f);
    double t = threadCpuMs();
    if (auto e = prep.build(dv, nullptr, ColorSpec{}, r.options().mesh); !e)
        return e;
    cpu.prep = threadCpuMs() - t;
    t = threadCpuMs();
    if (auto e = r.setDepth(dv, prep); !e)
        return e;
    cpu.render = threadCpuMs() - t;
    if (auto e = r.setColor(colorView(f), ColorSpec{}); !e)
        return e;
    setOverlays(r);
    if (auto e = r.render(target); !e)
        return e;
    const Clock::time_point t0 = Clock::now();
    if (auto e = target.blitTo(dst, target.width(), target.height()); !e)
        return e;
    if (stages != nullptr) {
        glFinish();
        const StageTimes &st = r.stageTimes();
        *stages = {st.depthUpload, st.mesh,   st.indexUpload, st.colorUpload, st.clear,
                   st.eye[0],      st.eye[1], st.overlay,     msSince(t0)};
    }
    glFinish();
    return ok();
}

/// One setting's samples over the timed frames.
struct Samples {
    std::vector<double> frameMs, meshMs, drawMs, geomCpuMs, prepCpuMs;
    std::array<std::vector<double>, kStageCount> stage;
    std::vector<double> stagedSum;
    platform::Duration cpu{0};
    double triangles = 0.0;
    double errSum = 0.0;
    std::size_t errSamples = 0;
};

/// \return the family of setting \a c (the lines of fps_vs_error.png).
const char *familyOf(const BenchConfig &c) noexcept
{
    if (c.mesh.mode == MeshMode::Fixed)
        return "fixed";
    if (c.mesh.mode == MeshMode::Adaptive)
        return "adaptive";
    if (c.mesh.mode == MeshMode::Blocks)
        return c.mesh.maxBlocks > 0 ? "block budgets" : "blocks";
    return c.mesh.maxBlocks > 0 ? "budgets" : "quadtree";
}

/// The figures of setting \a cfg from its samples.
BenchRow summarise(const BenchConfig &cfg, const Samples &sm, BenchRow row,
                   const BenchOptions &options)
{
    const double n = options.framesPerConfig;
    row.name = cfg.name;
    row.family = familyOf(cfg);
    row.source = options.source;
    row.tolerance = cfg.mesh.mode != MeshMode::Fixed ? cfg.mesh.tolerance : 0.0;
    row.step = cfg.mesh.mode == MeshMode::Fixed ? cfg.mesh.fixedStep : 0;
    row.meanTriangles = sm.triangles / n;
    row.medianMs = percentile(sm.frameMs, 0.5);
    row.p99Ms = percentile(sm.frameMs, 0.99);
    row.fps = row.medianMs > 0.0 ? 1000.0 / row.medianMs : 0.0;
    row.cpuMs = platform::toSeconds(sm.cpu) * 1e3 / n;
    row.meshMs = percentile(sm.meshMs, 0.5);
    row.drawMs = percentile(sm.drawMs, 0.5);
    row.geomCpuMs = percentile(sm.geomCpuMs, 0.5);
    row.geomCpuP99Ms = percentile(sm.geomCpuMs, 0.99);
    row.prepCpuMs = percentile(sm.prepCpuMs, 0.5);
    row.meanError = sm.errSamples > 0 ? sm.errSum / static_cast<double>(sm.errSamples) : 0.0;
    if (options.stageBreakdown) {
        for (std::size_t s = 0; s < kStageCount; ++s) {
            row.stageMedianMs[s] = percentile(sm.stage[s], 0.5);
            row.stageP99Ms[s] = percentile(sm.stage[s], 0.99);
        }
        row.stagedMedianMs = percentile(sm.stagedSum, 0.5);
        row.stagedP99Ms = percentile(sm.stagedSum, 0.99);
    }
    return row;
}

} // namespace

Result<std::vector<BenchRow>> runRenderBenchmark(const std::vector<RgbdFrame> &frames,
                                                 const BenchOptions &options)
{
    if (frames.empty())
        return unexpected(Errc::InvalidArgument, "no frames to render");
    RendererOptions ro;
    ro.mode = options.mode;
    ro.stereo.frameCompatible = options.frameCompatible;
    auto renderer = StereoRenderer::create(ro);
    if (!renderer)
        return unexpected(renderer.error());
    StereoRenderer &rr = **renderer;
    auto target = RenderTarget::create(options.outputWidth, options.outputHeight);
    if (!target)
        return unexpected(target.error());
    std::optional<RenderTarget> display;
    std::uint32_t dst = 0;
    if (options.presentFramebuffer) {
        dst = *options.presentFramebuffer;
    } else {
        auto d = RenderTarget::create(options.outputWidth, options.outputHeight);
        if (!d)
            return unexpected(d.error());
        display = std::move(*d);
        dst = display->framebuffer();
    }
    const std::vector<BenchConfig> configs =
        options.configs.empty() ? defaultConfigs() : options.configs;
    const std::size_t nc = configs.size();
    std::vector<Samples> samples(nc);
    std::vector<BenchRow> rows(nc);
    FramePrep prep;
    std::vector<std::uint32_t> drawn; // the triangles drawn, for the error measure
    // The settings take turns frame by frame, so a change of load on a shared machine touches them
    // all alike and their ratios stay fair. Frame i is the same data for every setting.
    const int total = options.warmup + options.framesPerConfig;
    for (int i = 0; i < total; ++i) {
        const RgbdFrame &f = frames[static_cast<std::size_t>(i) % frames.size()];
        for (std::size_t k = 0; k < nc; ++k) {
            ro.mesh = configs[k].mesh;
            // blocks-*: the tile size the player takes for this depth size.
            if (ro.mesh.mode == MeshMode::Blocks && configs[k].name.rfind("blocks-", 0) == 0)
                ro.mesh.tileSize = ro.mesh.maxStep = blockTileFor(f.width, f.height);
            if (auto r = rr.setOptions(ro); !r)
                return unexpected(r.error());
            Samples &sm = samples[k];
            BenchRow &row = rows[k];
            rr.setStageTiming(StageTiming::Cpu);
            GeomCpu geom;
            const platform::Duration cpu0 = platform::processCpuTime();
            const Clock::time_point t0 = Clock::now();
            if (auto r = drawFrame(rr, prep, f, *target, dst, geom, nullptr); !r)
                return unexpected(r.error());
            const double ms = msSince(t0);
            const platform::Duration cpu = platform::processCpuTime() - cpu0;
            if (i < options.warmup)
                continue;
            sm.cpu += cpu;
            sm.frameMs.push_back(ms);
            sm.meshMs.push_back(rr.stageTimes().mesh);
            sm.drawMs.push_back(rr.stageTimes().eye[0] + rr.stageTimes().eye[1]);
            sm.geomCpuMs.push_back(geom.render);
            sm.prepCpuMs.push_back(geom.prep);
            sm.triangles += static_cast<double>(rr.mesh().stats().triangles);
            // Geometric error of what was drawn (outside the timed part), on a third of the frames.
            if (i % 3 == 0) {
                rr.mesh().drawnIndices(drawn);
                const MeshError e = measureMeshError(depthView(f), drawn);
                sm.errSum += e.mean * static_cast<double>(e.samples - e.uncovered);
                sm.errSamples += e.samples - e.uncovered;
                row.maxError = std::max(row.maxError, e.max);
                row.uncovered += e.uncovered;
            }
            if (!options.stageBreakdown)
                continue;
            // The same frame again, each stage finished before the next starts.
            rr.setStageTiming(StageTiming::Finished);
            std::array<double, kStageCount> st{};
            if (auto r = drawFrame(rr, prep, f, *target, dst, geom, &st); !r)
                return unexpected(r.error());
            double sum = 0.0;
            for (std::size_t s = 0; s < kStageCount; ++s) {
                sm.stage[s].push_back(st[s]);
                sum += st[s];
            }
            sm.stagedSum.push_back(sum);
        }
    }
    rr.setStageTiming(StageTiming::Cpu);
    for (std::size_t k = 0; k < nc; ++k) {
        BenchRow base = rows[k];
        base.depthWidth = frames.front().width;
        base.depthHeight = frames.front().height;
        rows[k] = summarise(configs[k], samples[k], base, options);
        std::fprintf(stderr, "  %-8s %5dx%-5d %-14s %7.1f fps  geometry %.3f ms  mean error %.3f\n",
                     rows[k].source.c_str(), rows[k].depthWidth, rows[k].depthHeight,
                     rows[k].name.c_str(), rows[k].fps, rows[k].geomCpuMs, rows[k].meanError);
    }
    return rows;
}

Result<void> writeSideBySideSnapshot(const std::vector<RgbdFrame> &frames, std::size_t index,
                                     const MeshOptions &mesh, int width, int height,
                                     const std::string &path)
{
    if (index >= frames.size())
        return unexpected(Errc::InvalidArgument, "snapshot frame index out of range");
    RendererOptions ro;
    ro.mode = StereoMode::SideBySide;
    ro.stereo.frameCompatible = 2 * height > width; // two full-aspect eyes in a wide frame
    ro.mesh = mesh;
    auto renderer = StereoRenderer::create(ro);
    if (!renderer)
        return unexpected(renderer.error());
    auto target = RenderTarget::create(width, height);
    if (!target)
        return unexpected(target.error());
    const RgbdFrame &f = frames[index];
    if (auto r = (*renderer)->setDepth(depthView(f)); !r)
        return r;
    if (auto r = (*renderer)->setColor(colorView(f), ColorSpec{}); !r)
        return r;
    if (auto r = (*renderer)->render(*target); !r)
        return r;
    return writeSnapshot(*target, path);
}

} // namespace depthtouch::render::bench
