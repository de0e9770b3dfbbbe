/// \file
/// \brief `depthtouch bench feel`: what a finger meets on real depth video (false safety trips,
/// pop-through, phantom force, force spikes, ripple) against the update time, per renderer setting,
/// on the 7-Scenes kitchen encoded as `depthtouch encode` does by default (8-bit H.264 4:0:0 depth,
/// decoded again), on synthetic scenes seen through a Kinect-style sensor model, and on any --clip.
/// Writes CSV, JSON and a PNG chart into --out (feel_bench.h, feel_scenes.h).

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "option_cli.h"
#include "depthtouch/haptics/feel_bench.h"
#include "depthtouch/haptics/feel_scenes.h"
#include "depthtouch/media/encode_job.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/image_io.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/thread_config.h"

namespace depthtouch::cli {

namespace {

namespace hb = haptics::bench;

struct BenchFeelOptions {
    std::string out = "bench-feel-out";
    std::vector<std::string> clips;
    std::vector<std::string> methods{"finger", "modified", "proxy-graph"};
    std::string data;
    bool quick = false;
    bool fifo = true;
};

/// What `bench feel` measures (its line in `depthtouch bench --help`).
constexpr const char *kAbout =
    "Feel on real content: false trips, pop-through, phantom force, spikes, ripple vs update time";

/// The options of `bench feel`, in `--help` order.
const OptionRow<BenchFeelOptions> kBenchFeelRows[] = {
    {"out", &BenchFeelOptions::out, "Output directory"},
    {"clip",
     &BenchFeelOptions::clips,
     "Also touch the depth of this video or DepthTouch file (repeatable)",
     {},
     kHideDefault},
    {"method",
     &BenchFeelOptions::methods,
     "Renderers (comma-separated): finger, modified, proxy-graph, mesh-bvh",
     {},
     kCommaList},
    {"data", &BenchFeelOptions::data,
     "Folder of the shared RGB-D captures, holding rgbd-7scenes-redkitchen/ (default "
     "$DT_SHARED_DATA, else ../shared/data)"},
    {"quick", &BenchFeelOptions::quick, "Shorter synthetic clips and one slide per depth x speed"},
    {"no-fifo",
     &BenchFeelOptions::fifo,
     "Time on a normal thread instead of a SCHED_FIFO one at the haptic priority",
     {},
     kNegated},
};

constexpr long long kMaxClipFrames = 300; ///< 10 s at 30 fps: bounds the run time of a --clip.

/// Decodes the depth stream of \a url (a DepthTouch file, a depth video) into a FeelScene.
Result<hb::FeelScene> loadClip(const std::string &url, const std::string &name)
{
    media::SourceOptions so;
    so.streamTitle = "depth";
    auto src = media::openFfmpegFrameSource(url, so);
    if (!src)
        return unexpected(src.error());
    const media::SourceInfo &info = (*src)->info();
    const bool wide = info.nativeFormat == media::PixelFormat::Gray16;
    std::vector<depth::Plane<std::uint16_t>> frames;
    while (static_cast<long long>(frames.size()) < kMaxClipFrames) {
        auto f = (*src)->next(wide ? media::PixelFormat::Gray16 : media::PixelFormat::Gray8);
        if (!f && f.error().code == Errc::EndOfStream)
            break;
        if (!f)
            return unexpected(f.error());
        if (wide) {
            frames.push_back(media::toPlane16(f->image));
        } else {
            const depth::Plane<std::uint8_t> p8 = media::toPlane8(f->image);
            depth::Plane<std::uint16_t> p(p8.width, p8.height);
            std::copy(p8.samples.begin(), p8.samples.end(), p.samples.begin());
            frames.push_back(std::move(p));
        }
    }
    const double fps = info.fps > 0.0 ? info.fps : 30.0;
    return hb::sceneFromNearness(
        name, frames, wide ? haptics::SampleFormat::Gray16 : haptics::SampleFormat::Gray8, fps,
        haptics::SceneBox{});
}

/// The kitchen: encoded with `depthtouch encode`'s defaults into \a outDir/kitchen.mkv, its depth
/// decoded again (8-bit); the stroke mask from the raw PNGs (valid in >= 90 % of the frames).
Result<hb::FeelScene> loadKitchen(const std::string &dir, const std::string &outDir)
{
    const std::string colorSpec = dir + "/frame-%06d.color.jpg";
    const std::string depthSpec = dir + "/frame-%06d.depth.png";
    media::SourceOptions so;
    so.fps = 30.0;
    auto color = media::openFfmpegFrameSource(colorSpec, so);
    if (!color)
        return unexpected(color.error());
    auto depthSrc = media::openFfmpegFrameSource(depthSpec, so);
    if (!depthSrc)
        return unexpected(depthSrc.error());
    media::EncodeOptions eo;
    eo.output = (std::filesystem::path(outDir) / "kitchen.mkv").string();
    DT_TRY(eo.validate());
    auto summary = media::encodeStreams(**color, **depthSrc, eo);
    if (!summary)
        return unexpected(summary.error());
    auto scene = loadClip(eo.output, "7scenes-kitchen");
    if (!scene)
        return scene;
    depth::Plane<int> count(scene->width, scene->height, 0);
    int n = 0;
    for (int i = 0; i < static_cast<int>(scene->frameCount()); ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "/frame-%06d.depth.png", i);
        auto img = media::readImage(dir + name, media::PixelFormat::Gray16);
        if (!img || img->width != scene->width || img->height != scene->height)
            break;
        const depth::Plane<std::uint16_t> raw = media::toPlane16(*img);
        for (std::size_t k = 0; k < raw.size(); ++k)
            count.samples[k] += raw.samples[k] != 0 && raw.samples[k] != 65535;
        ++n;
    }
    if (n > 0)
        for (std::size_t k = 0; k < count.size(); ++k)
            scene->valid.samples[k] = count.samples[k] >= 0.9 * n ? 1 : 0;
    return scene;
}

std::string defaultDataDir()
{
    const char *env = std::getenv("DT_SHARED_DATA");
    return std::string(env != nullptr && *env != '\0' ? env : "../shared/data");
}

int fail(int code, const std::string &message)
{
    std::fprintf(stderr, "depthtouch bench feel: %s\n", message.c_str());
    return code;
}

/// Gathers the scenes: kitchen (when its data is there), the synthetic ones, the clips.
int loadScenes(const BenchFeelOptions &o, std::vector<hb::FeelScene> &scenes)
{
    const std::string dir =
        (o.data.empty() ? defaultDataDir() : o.data) + "/rgbd-7scenes-redkitchen";
    if (std::filesystem::exists(dir + "/frame-000000.depth.png")) {
        std::fprintf(stderr, "encoding the 7-Scenes kitchen (depthtouch encode defaults) ...\n");
        auto k = loadKitchen(dir, o.out);
        if (!k)
            return fail(kExitFailure, "kitchen: " + std::string(k.error().what));
        scenes.push_back(std::move(*k));
    } else {
        std::printf("note: no 7-Scenes kitchen in %s (set DT_SHARED_DATA or --data): skipped\n",
                    dir.c_str());
    }
    hb::SyntheticSceneOptions so;
    so.seconds = o.quick ? 2.0 : 3.0;
    for (hb::SyntheticScene s :
         {hb::SyntheticScene::Table, hb::SyntheticScene::Head, hb::SyntheticScene::Forearm}) {
        std::fprintf(stderr, "rendering %s ...\n", hb::syntheticSceneName(s));
        auto sc = hb::makeSyntheticScene(s, so);
        if (!sc)
            return fail(kExitFailure,
                        std::string(hb::syntheticSceneName(s)) + ": " + sc.error().what);
        scenes.push_back(std::move(*sc));
    }
    for (const std::string &clip : o.clips) {
        auto c = loadClip(clip, std::filesystem::path(clip).filename().string());
        if (!c)
            return fail(kExitBadInput,
                        "cannot read depth of --clip '" + clip + "': " + c.error().what);
        scenes.push_back(std::move(*c));
    }
    return kExitOk;
}

int runBenchFeel(const BenchFeelOptions &o)
{
    const auto start = std::chrono::steady_clock::now();
    std::vector<haptics::Method> methods;
    for (const std::string &m : o.methods) {
        auto parsed = haptics::parseMethod(m);
        if (!parsed)
            return fail(kExitBadInput, "--method: unknown method '" + m +
                                           "' (finger, modified, proxy-graph, mesh-bvh)");
        methods.push_back(*parsed);
    }
    for (const std::string &clip : o.clips)
        if (!std::filesystem::exists(clip))
            return fail(kExitBadInput, "--clip: no such file '" + clip + "'");
    std::error_code ec;
    std::filesystem::create_directories(o.out, ec);
    if (ec)
        return fail(kExitFailure, "cannot create --out " + o.out + ": " + ec.message());
    platform::setLogLevel(platform::LogLevel::Error);
    std::vector<hb::FeelScene> scenes;
    if (const int rc = loadScenes(o, scenes); rc != kExitOk)
        return rc;
    hb::StrokePlan plan;
    if (o.quick)
        plan.slidesPerSetting = 1;
    std::vector<std::vector<hb::Stroke>> strokes;
    for (const hb::FeelScene &s : scenes) {
        strokes.push_back(hb::makeStrokes(s, plan));
        std::printf("%-20s %dx%d %s, %zu frames at %.0f fps, %zu strokes\n", s.name.c_str(),
                    s.width, s.height,
                    s.format == haptics::SampleFormat::Gray8 ? "8-bit" : "16-bit", s.frameCount(),
                    s.fps, strokes.back().size());
    }
    std::fflush(stdout);
    const auto settings = hb::feelSettings(methods);
    // Time the updates on a SCHED_FIFO thread at the haptic priority, as `bench haptics` does, so
    // other processes do not preempt them; normal scheduling (with a note) when the kernel refuses.
    hb::FeelReport report;
    platform::RealtimeThreadOptions rt;
    rt.lockMemory = false;
    const platform::ThreadConfig cfg{
        "dt-bench-feel", o.fifo ? platform::SchedPolicy::Fifo : platform::SchedPolicy::Other,
        o.fifo ? platform::kHapticThread.relativePriority : 0, 8u << 20};
    platform::RealtimeThread worker(cfg, rt, [&](platform::StopToken) {
        report = hb::runFeelBenchmark(scenes, strokes, settings, [](const std::string &line) {
            std::fprintf(stderr, "  %s\n", line.c_str());
        });
    });
    if (Result<void> started = worker.start(); !started)
        return fail(kExitFailure,
                    std::string("cannot start the bench thread: ") + started.error().what);
    char how[160];
    std::printf("\nupdate times: steady_clock around update() on the timing thread: %s\n\n",
                worker.report().format(how, sizeof how));
    worker.join();
    hb::printFeelReport(report);
    std::string error;
    std::string note;
    if (!hb::writeFeelOutputs(report, o.out, error, note))
        return fail(kExitFailure, error);
    if (!note.empty())
        std::printf("note: %s\n", note.c_str());
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("wrote %s/{feel.csv,feel_strokes.csv,feel.json,feel_vs_speed.png} in %.0f s "
                "(replays %.1f s)\n",
                o.out.c_str(), secs, report.seconds);
    return kExitOk;
}

} // namespace

void registerBenchFeelCommand(CLI::App &bench, int &exitCode)
{
    addTableCommand<BenchFeelOptions>(bench, "feel", kAbout, kBenchFeelRows, runBenchFeel,
                                      exitCode);
}

} // namespace depthtouch::cli
