#include "depthtouch/render/render_bench.h"

#include <GLES3/gl3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "depthtouch/depth/conversion.h"
#include "depthtouch/depth/fill.h"
#include "depthtouch/depth/resample.h"
#include "depthtouch/media/image_io.h"
#include "depthtouch/platform/cpu_time.h"
#include "depthtouch/platform/gnuplot.h"
#include "depthtouch/render/render_target.h"
#include "depthtouch/render/renderer.h"
#include "depthtouch/render/snapshot.h"
#include "depthtouch/platform/percentile.h"

namespace depthtouch::render::bench {

using platform::percentile;

namespace {

std::string framePath(const std::string &dir, int n, const char *kind)
{
    char name[64];
    std::snprintf(name, sizeof name, "/frame-%06d.%s", n, kind);
    return dir + name;
}

/// RGB → yuv420p, BT.601 limited range (what an H.264 sender produces), chroma averaged over 2×2.
void rgbToYuv420(const media::Image &rgb, RgbdFrame &out)
{
    const int w = rgb.width;
    const int h = rgb.height;
    const int cw = (w + 1) / 2;
    const int ch = (h + 1) / 2;
    out.colorWidth = w;
    out.colorHeight = h;
    out.y.assign(static_cast<std::size_t>(w * h), 0);
    out.u.assign(static_cast<std::size_t>(cw * ch), 0);
    out.v.assign(static_cast<std::size_t>(cw * ch), 0);
    std::vector<double> su(out.u.size(), 0.0);
    std::vector<double> sv(out.v.size(), 0.0);
    std::vector<int> count(out.u.size(), 0);
    for (int y = 0; y < h; ++y) {
        const std::uint8_t *row = rgb.row(y);
        for (int x = 0; x < w; ++x) {
            const double r = row[3 * x] / 255.0;
            const double g = row[3 * x + 1] / 255.0;
            const double b = row[3 * x + 2] / 255.0;
            const double luma = 0.299 * r + 0.587 * g + 0.114 * b;
            out.y[static_cast<std::size_t>(y * w + x)] =
                static_cast<std::uint8_t>(std::lround(16.0 + 219.0 * luma));
            const std::size_t ci = static_cast<std::size_t>((y / 2) * cw + x / 2);
            su[ci] += (b - luma) / 1.772;
            sv[ci] += (r - luma) / 1.402;
            ++count[ci];
        }
    }
    for (std::size_t i = 0; i < su.size(); ++i) {
        out.u[i] = static_cast<std::uint8_t>(std::lround(128.0 + 224.0 * su[i] / count[i]));
        out.v[i] = static_cast<std::uint8_t>(std::lround(128.0 + 224.0 * sv[i] / count[i]));
    }
}

scene::DepthFrameView depthView(const RgbdFrame &f)
{
    scene::DepthFrameView v;
    v.data = f.nearness.data();
    v.width = f.width;
    v.height = f.height;
    v.strideBytes = static_cast<std::size_t>(f.width);
    v.format = scene::SampleFormat::Gray8;
    return v;
}

hal::ImageView colorView(const RgbdFrame &f)
{
    hal::ImageView img;
    img.width = f.colorWidth;
    img.height = f.colorHeight;
    img.format = hal::PixelFormat::Yuv420p;
    const int cw = (f.colorWidth + 1) / 2;
    img.planes[0] = {const_cast<std::uint8_t *>(f.y.data()), f.colorWidth};
    img.planes[1] = {const_cast<std::uint8_t *>(f.u.data()), cw};
    img.planes[2] = {const_cast<std::uint8_t *>(f.v.data()), cw};
    return img;
}


} // namespace

Result<std::vector<RgbdFrame>> loadKitchenFrames(const std::string &sceneDir, int maxFrames, int width,
                                                 int height)
{
    if (width < 2 || height < 2 || maxFrames < 1)
        return unexpected(Errc::InvalidArgument, "frame size must be at least 2x2 and count >= 1");
    if (!std::filesystem::exists(framePath(sceneDir, 0, "depth.png")))
        return unexpected(Errc::Io, "no frame-000000.depth.png in the scene folder");
    std::vector<RgbdFrame> frames;
    std::optional<depth::DepthRange> range;
    for (int n = 0; n < maxFrames; ++n) {
        const std::string dpath = framePath(sceneDir, n, "depth.png");
        if (!std::filesystem::exists(dpath))
            break;
        auto dimg = media::readImage(dpath, media::PixelFormat::Gray16);
        if (!dimg)
            return unexpected(dimg.error());
        depth::ConvertOptions co;
        co.range = range; // planes of the first frame for the whole sequence
        auto nf = depth::metricToNearness(media::toPlane16(*dimg), co);
        if (!nf)
            return unexpected(nf.error());
        range = nf->range;
        if (auto filled = depth::fillInvalid(nf->nearness, nf->valid); !filled)
            return unexpected(filled.error());
        auto resampled = depth::resample(nf->nearness, width, height);
        if (!resampled)
            return unexpected(resampled.error());
        const depth::Plane<std::uint16_t> q = depth::quantize(*resampled, 255.0);
        RgbdFrame f;
        f.width = width;
        f.height = height;
        f.nearness.resize(q.samples.size());
        for (std::size_t i = 0; i < q.samples.size(); ++i)
            f.nearness[i] = static_cast<std::uint8_t>(q.samples[i]);
        auto cimg = media::readImage(framePath(sceneDir, n, "color.jpg"), media::PixelFormat::Rgb24);
        if (!cimg)
            return unexpected(cimg.error());
        rgbToYuv420(*cimg, f);
        frames.push_back(std::move(f));
    }
    return frames;
}

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
        MeshOptions m; // per-tile steps: tile 8, mean criterion, cap 16 levels
        m.mode = MeshMode::Adaptive;
        m.tileSize = 8;
        m.maxStep = 8;
        m.tolerance = tol;
        char name[32];
        std::snprintf(name, sizeof name, "adaptive-%.1f", tol);
        out.push_back({name, m});
    }
    for (const double tol : {0.3, 0.4, 0.45, 0.5, 0.6}) {
        MeshOptions m; // quadtree: root 32, frame mean error budget, cap 16 levels
        m.mode = MeshMode::Quadtree;
        m.tileSize = 32;
        m.maxStep = 32;
        m.tolerance = tol;
        char name[32];
        std::snprintf(name, sizeof name, "quadtree-%.2f", tol);
        out.push_back({name, m});
    }
    for (const int thousands : {3, 6, 9, 12}) {
        MeshOptions m; // quadtree-0.50 under a leaf-block budget (what the player's LOD sets)
        m.mode = MeshMode::Quadtree;
        m.tileSize = 32;
        m.maxStep = 32;
        m.tolerance = 0.5;
        m.maxBlocks = static_cast<std::size_t>(thousands) * 1000;
        char name[32];
        std::snprintf(name, sizeof name, "budget-%dk", thousands);
        out.push_back({name, m});
    }
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
        const auto it = std::find_if(all.begin(), all.end(), [&](const BenchConfig &c) { return c.name == name; });
        if (it == all.end())
            return unexpected(Errc::InvalidArgument, "unknown mesh setting (see the table's first column)");
        out.push_back(*it);
        pos = comma + 1;
    }
    return out;
}

const char *stageName(int i) noexcept
{
    static constexpr const char *kNames[kStageCount] = {"depth", "mesh", "index", "color", "clear",
                                                        "eye1",  "eye2", "overlay", "blit"};
    return i >= 0 && i < kStageCount ? kNames[i] : "?";
}

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
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

/// One frame as the player draws it; \a stages receives the stage times (ms) when not null.
Result<void> drawFrame(StereoRenderer &r, const RgbdFrame &f, const RenderTarget &target, std::uint32_t dst,
                       std::array<double, kStageCount> *stages)
{
    if (auto e = r.setDepth(depthView(f)); !e)
        return e;
    if (auto e = r.setColor(colorView(f), ColorSpec{}); !e)
        return e;
    setOverlays(r);
    if (auto e = r.render(target); !e)
        return e;
    const Clock::time_point t = Clock::now();
    if (auto e = target.blitTo(dst, target.width(), target.height()); !e)
        return e;
    if (stages != nullptr) {
        glFinish();
        const StageTimes &st = r.stageTimes();
        *stages = {st.depthUpload, st.mesh, st.indexUpload, st.colorUpload, st.clear,
                   st.eye[0],      st.eye[1], st.overlay,   msSince(t)};
    }
    glFinish();
    return ok();
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
    const std::vector<BenchConfig> configs = options.configs.empty() ? defaultConfigs() : options.configs;
    const std::size_t nc = configs.size();
    // Per setting: samples of the plain pass and of the staged pass.
    struct Samples {
        std::vector<double> frameMs, meshMs, drawMs;
        std::array<std::vector<double>, kStageCount> stage;
        std::vector<double> stagedSum;
        platform::Duration cpu{0};
        double triangles = 0.0;
        double errSum = 0.0;
        std::size_t errSamples = 0;
    };
    std::vector<Samples> samples(nc);
    std::vector<BenchRow> rows(nc);
    const auto use = [&](std::size_t k) -> Result<void> {
        ro.mesh = configs[k].mesh;
        return rr.setOptions(ro);
    };
    // The settings take turns frame by frame, so a change of load on a shared machine touches them
    // all alike and their ratios stay fair. Frame i is the same data for every setting.
    const int total = options.warmup + options.framesPerConfig;
    for (int i = 0; i < total; ++i) {
        const RgbdFrame &f = frames[static_cast<std::size_t>(i) % frames.size()];
        for (std::size_t k = 0; k < nc; ++k) {
            if (auto r = use(k); !r)
                return unexpected(r.error());
            Samples &sm = samples[k];
            BenchRow &row = rows[k];
            rr.setStageTiming(StageTiming::Cpu);
            const platform::Duration cpu0 = platform::processCpuTime();
            const Clock::time_point t0 = Clock::now();
            if (auto r = drawFrame(rr, f, *target, dst, nullptr); !r)
                return unexpected(r.error());
            const double ms = msSince(t0);
            const platform::Duration cpu = platform::processCpuTime() - cpu0;
            if (i < options.warmup)
                continue;
            sm.cpu += cpu;
            sm.frameMs.push_back(ms);
            sm.meshMs.push_back(rr.stageTimes().mesh);
            sm.drawMs.push_back(rr.stageTimes().eye[0] + rr.stageTimes().eye[1]);
            sm.triangles += static_cast<double>(rr.mesh().stats().triangles);
            // Geometric error of what was drawn (outside the timed part), on a third of the frames.
            if (i % 3 == 0) {
                const MeshError e = measureMeshError(depthView(f), rr.mesh().indices());
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
            if (auto r = drawFrame(rr, f, *target, dst, &st); !r)
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
        const BenchConfig &cfg = configs[k];
        const Samples &sm = samples[k];
        BenchRow &row = rows[k];
        row.name = cfg.name;
        row.tolerance = cfg.mesh.mode != MeshMode::Fixed ? cfg.mesh.tolerance : 0.0;
        row.step = cfg.mesh.mode == MeshMode::Fixed ? cfg.mesh.fixedStep : 0;
        row.meanTriangles = sm.triangles / options.framesPerConfig;
        row.medianMs = percentile(sm.frameMs, 0.5);
        row.p99Ms = percentile(sm.frameMs, 0.99);
        row.fps = row.medianMs > 0.0 ? 1000.0 / row.medianMs : 0.0;
        row.cpuMs = platform::toSeconds(sm.cpu) * 1e3 / options.framesPerConfig;
        row.meshMs = percentile(sm.meshMs, 0.5);
        row.drawMs = percentile(sm.drawMs, 0.5);
        row.meanError = sm.errSamples > 0 ? sm.errSum / static_cast<double>(sm.errSamples) : 0.0;
        if (options.stageBreakdown) {
            for (std::size_t s = 0; s < kStageCount; ++s) {
                row.stageMedianMs[s] = percentile(sm.stage[s], 0.5);
                row.stageP99Ms[s] = percentile(sm.stage[s], 0.99);
            }
            row.stagedMedianMs = percentile(sm.stagedSum, 0.5);
            row.stagedP99Ms = percentile(sm.stagedSum, 0.99);
        }
        std::fprintf(stderr, "  %-14s %7.1f fps  mean error %.3f levels\n", row.name.c_str(), row.fps,
                     row.meanError);
    }
    return rows;
}

Result<void> writeSideBySideSnapshot(const std::vector<RgbdFrame> &frames, std::size_t index,
                                     const MeshOptions &mesh, int width, int height, const std::string &path)
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

void printTable(const std::vector<BenchRow> &rows, const BenchOptions &options)
{
    std::printf("\nstereo %s %dx%d output, %d frames per setting. Frame = depth and colour upload, mesh\n"
                "choice, both eyes, avatar, OSD, blit and glFinish (median, p99); cpu = process CPU time per\n"
                "frame, all threads; draw = both eyes' draw calls on the calling thread (vertex processing and\n"
                "binning; the rasterizer threads shade later, waited for by the blit or glFinish);\n"
                "error = |mesh - samples| in 8-bit nearness levels\n\n",
                stereoModeName(options.mode), options.outputWidth, options.outputHeight,
                options.framesPerConfig);
    std::printf("%-14s %10s %9s %9s %7s %8s %8s %8s %11s %10s %9s\n", "mesh", "triangles", "median ms", "p99 ms",
                "fps", "cpu ms", "mesh ms", "draw ms", "mean error", "max error", "uncovered");
    for (const BenchRow &r : rows)
        std::printf("%-14s %10.0f %9.2f %9.2f %7.1f %8.2f %8.2f %8.2f %11.3f %10.1f %9zu\n", r.name.c_str(),
                    r.meanTriangles, r.medianMs, r.p99Ms, r.fps, r.cpuMs, r.meshMs, r.drawMs, r.meanError,
                    r.maxError, r.uncovered);
    if (!options.stageBreakdown)
        return;
    std::printf("\nstage breakdown, median ms (glFinish after each stage, so each carries its own\n"
                "rasterization; same frames, second pass); sum = median of the per-frame sums, with p99\n\n");
    std::printf("%-14s", "mesh");
    for (int k = 0; k < kStageCount; ++k)
        std::printf(" %7s", stageName(k));
    std::printf(" %8s %8s\n", "sum", "sum p99");
    for (const BenchRow &r : rows) {
        std::printf("%-14s", r.name.c_str());
        for (const double v : r.stageMedianMs)
            std::printf(" %7.2f", v);
        std::printf(" %8.2f %8.2f\n", r.stagedMedianMs, r.stagedP99Ms);
    }
    std::printf("\nshare of the sum, %%\n\n%-14s", "mesh");
    for (int k = 0; k < kStageCount; ++k)
        std::printf(" %7s", stageName(k));
    std::printf("\n");
    for (const BenchRow &r : rows) {
        std::printf("%-14s", r.name.c_str());
        for (const double v : r.stageMedianMs)
            std::printf(" %7.1f", r.stagedMedianMs > 0.0 ? 100.0 * v / r.stagedMedianMs : 0.0);
        std::printf("\n");
    }
}

bool writeBenchOutputs(const std::vector<BenchRow> &rows, const std::string &dir, std::string &error,
                       std::string &note)
{
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) {
        error = "cannot create " + dir + ": " + ec.message();
        return false;
    }
    const fs::path base(dir);
    {
        std::ofstream csv(base / "render_bench.csv");
        if (!csv) {
            error = "cannot write " + (base / "render_bench.csv").string();
            return false;
        }
        csv << "mesh,tolerance_levels,step,triangles,median_ms,p99_ms,fps,cpu_ms,mesh_ms,draw_ms,"
               "mean_error_levels,max_error_levels,uncovered";
        for (int k = 0; k < kStageCount; ++k)
            csv << ",stage_" << stageName(k) << "_median_ms,stage_" << stageName(k) << "_p99_ms";
        csv << ",staged_median_ms,staged_p99_ms\n";
        for (const BenchRow &r : rows) {
            csv << r.name << ',' << r.tolerance << ',' << r.step << ',' << r.meanTriangles << ',' << r.medianMs
                << ',' << r.p99Ms << ',' << r.fps << ',' << r.cpuMs << ',' << r.meshMs << ',' << r.drawMs << ','
                << r.meanError << ',' << r.maxError << ',' << r.uncovered;
            for (std::size_t k = 0; k < kStageCount; ++k)
                csv << ',' << r.stageMedianMs[k] << ',' << r.stageP99Ms[k];
            csv << ',' << r.stagedMedianMs << ',' << r.stagedP99Ms << '\n';
        }
    }
    {
        std::ofstream d(base / "fps_vs_error.dat");
        d << "# fixed\n";
        for (const BenchRow &r : rows)
            if (r.step > 0)
                d << r.meanError << ' ' << r.fps << " \"" << r.name << "\"\n";
        d << "\n\n# adaptive\n";
        for (const BenchRow &r : rows)
            if (r.step == 0)
                d << r.meanError << ' ' << r.fps << " \"" << r.name << "\"\n";
        d << "\n";
    }
    {
        std::ofstream gp(base / "fps_vs_error.gp");
        gp << "set terminal pngcairo size 900,600 noenhanced\n"
           << "set output '" << (base / "fps_vs_error.png").string() << "'\n"
           << "set title 'Stereo side-by-side: frame rate vs mean geometric error (llvmpipe)'\n"
           << "set xlabel 'mean geometric error (8-bit nearness levels)'\n"
           << "set ylabel 'frames per second (median)'\n"
           << "set grid\nset key bottom right\n"
           << "set arrow from 0.5, graph 0 to 0.5, graph 1 nohead dt 2 lc rgb 'gray40'\n"
           << "set arrow from graph 0, first 30 to graph 1, first 30 nohead dt 2 lc rgb 'gray40'\n"
           << "plot '" << (base / "fps_vs_error.dat").string()
           << "' index 0 using 1:2 with linespoints pt 7 title 'full / fixed decimation', \\\n"
           << "     '' index 0 using 1:2:3 with labels offset 1,1 notitle, \\\n"
           << "     '' index 1 using 1:2 with linespoints pt 5 title 'adaptive (tolerance sweep)', \\\n"
           << "     '' index 1 using 1:2:3 with labels offset 1,-1 notitle\n";
    }
    {
        // Stacked stage medians per setting.
        std::ofstream d(base / "stages.dat");
        d << "mesh";
        for (int k = 0; k < kStageCount; ++k)
            d << ' ' << stageName(k);
        d << '\n';
        for (const BenchRow &r : rows) {
            d << r.name;
            for (const double v : r.stageMedianMs)
                d << ' ' << v;
            d << '\n';
        }
        std::ofstream gp(base / "stages.gp");
        gp << "set terminal pngcairo size 900,600 noenhanced\n"
           << "set output '" << (base / "stages.png").string() << "'\n"
           << "set title 'Stereo side-by-side: median time per stage (glFinish after each stage, llvmpipe)'\n"
           << "set ylabel 'ms per frame'\nset grid ytics\nset key outside right top\n"
           << "set style data histograms\nset style histogram rowstacked\nset style fill solid 0.8 border -1\n"
           << "set boxwidth 0.7\nset xtics rotate by -30\n"
           << "plot for [k=2:" << (kStageCount + 1) << "] '" << (base / "stages.dat").string()
           << "' using k:xtic(1) title columnheader(k)\n";
    }
    platform::PlotStatus plot = platform::runGnuplot((base / "fps_vs_error.gp").string());
    if (plot == platform::PlotStatus::Drawn)
        plot = platform::runGnuplot((base / "stages.gp").string());
    if (plot != platform::PlotStatus::Drawn)
        note = std::string(platform::plotStatusNote(plot)) + "; CSV written";
    return true;
}

} // namespace depthtouch::render::bench
