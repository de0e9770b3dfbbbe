/// \file
/// \brief `depthtouch bench feel`: what a finger meets on real depth video, per renderer setting:
/// six stroke families (swipes across silhouettes, presses 0.5 and 6 mm deep, circles, taps,
/// traces along edges, holds beside moving objects, under occluders, on edges, flicker and hole
/// borders) placed where each clip is hardest, on every capture in the shared RGB-D data (holes
/// kept as the receiver sees them), on synthetic scenes seen through structured-light,
/// time-of-flight and active-stereo models, 8- and 16-bit, and on any --clip. Writes CSV, JSON and
/// a PNG chart into --out (feel_bench.h, feel_scenes.h).

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
#include "output_paths.h"
#include "depthtouch/haptics/feel_bench.h"
#include "depthtouch/haptics/feel_scenes.h"
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
    std::string dump;
};

/// What `bench feel` measures (its line in `depthtouch bench --help`).
constexpr const char *kAbout =
    "Feel on real and synthetic depth: six stroke families placed where the content is hardest, "
    "goals judged on the worst family x clip x setting";

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
     "Folder of the shared RGB-D captures (rgbd-7scenes-redkitchen/, rgbd-bonn-crowd/, "
     "rgbd-realsense-lab/, rgbd-azure-kinect-still/, rgbd-open3d/; default $DT_SHARED_DATA, else "
     "../shared/data); those missing are skipped"},
    {"quick", &BenchFeelOptions::quick,
     "8-bit only, fewer synthetic scenes, one stroke per family variant, each method's first "
     "setting (under 30 s)"},
    {"no-fifo",
     &BenchFeelOptions::fifo,
     "Time on a normal thread instead of a SCHED_FIFO one at the haptic priority",
     {},
     kNegated},
    {"dump",
     &BenchFeelOptions::dump,
     "Write the per-update log of every stroke whose 'scene|setting|stroke' contains this text to "
     "feel_dump/ (e.g. 'bonn-crowd/8|finger|tap')",
     {},
     kHideDefault},
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
    return hb::sceneFromNearness(name, frames,
                                 wide ? scene::SampleFormat::Gray16 : scene::SampleFormat::Gray8,
                                 fps, scene::SceneBox{});
}

/// One capture of the shared data: where its depth PNGs are and how to play them.
struct Capture {
    const char *name;
    const char *folder;
    const char *prefix; ///< A depth PNG under the folder: prefix, the frame index in `digits`
    int digits;         ///< digits (zero-padded), suffix.
    const char *suffix;
    double fps;
    int frames; ///< Frames read at most.
    /// Played as: 0 as captured; > 0 looped back and forth (0..n-1..0..) to this many frames
    /// (a still frame, or clips shorter than a stroke).
    int pingPongTo;
};

constexpr Capture kCaptures[] = {
    {"7scenes-kitchen", "rgbd-7scenes-redkitchen", "/frame-", 6, ".depth.png", 30.0, 60, 0},
    {"bonn-crowd", "rgbd-bonn-crowd", "/depth/", 5, ".png", 29.8, 60, 0},
    {"realsense-lab", "rgbd-realsense-lab", "/depth/", 5, ".png", 10.0, 60, 0},
    {"azure-kinect-still", "rgbd-azure-kinect-still", "/depth/", 5, ".png", 30.0, 1, 60},
    {"open3d-livingroom", "rgbd-open3d", "/depth/", 5, ".png", 30.0, 5, 60},
};

constexpr int kQuickFrames = 40; ///< Frames of a capture read with --quick.

/// Reads the depth PNGs of \a c (mm, 0 or 65535 = invalid). \return none when the first is absent.
Result<std::vector<depth::Plane<std::uint16_t>>> readCapture(const std::string &data,
                                                             const Capture &c, int maxFrames)
{
    std::vector<depth::Plane<std::uint16_t>> mm;
    for (int i = 0; i < std::min(c.frames, maxFrames); ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "%s%0*d%s", c.prefix, c.digits, i, c.suffix);
        const std::string path = data + "/" + c.folder + name;
        if (!std::filesystem::exists(path))
            break;
        auto img = media::readImage(path, media::PixelFormat::Gray16);
        if (!img)
            return unexpected(img.error());
        depth::Plane<std::uint16_t> p = media::toPlane16(*img);
        for (auto &v : p.samples)
            v = v == 65535 ? 0 : v;
        if (!mm.empty() && !p.sameSize(mm.front()))
            break;
        mm.push_back(std::move(p));
    }
    if (c.pingPongTo > 0 && !mm.empty()) {
        const std::vector<depth::Plane<std::uint16_t>> once = mm;
        const int n = static_cast<int>(once.size());
        mm.clear();
        for (int k = 0; k < c.pingPongTo; ++k) {
            const int period = n > 1 ? 2 * (n - 1) : 1;
            const int m = k % period;
            mm.push_back(once[static_cast<std::size_t>(m < n ? m : period - m)]);
        }
    }
    return mm;
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

/// Gathers the scenes: every capture found in the shared data, the synthetic ones, the clips; and
/// the clean synthetic scenes of the accuracy figure.
int loadScenes(const BenchFeelOptions &o, std::vector<hb::FeelScene> &scenes,
               std::vector<hb::FeelScene> &clean)
{
    const std::string data = o.data.empty() ? defaultDataDir() : o.data;
    const std::vector<int> bits = o.quick ? std::vector<int>{8} : std::vector<int>{8, 16};
    for (const Capture &c : kCaptures) {
        auto mm = readCapture(data, c, o.quick ? kQuickFrames : c.frames);
        if (!mm)
            return fail(kExitFailure, std::string(c.name) + ": " + mm.error().what);
        if (mm->empty()) {
            std::printf("note: no %s in %s/%s (set DT_SHARED_DATA or --data): skipped\n", c.name,
                        data.c_str(), c.folder);
            continue;
        }
        for (int b : bits) {
            std::fprintf(stderr, "mapping %s (%d-bit, holes kept) ...\n", c.name, b);
            auto sc = hb::sceneFromSensorDepth(std::string(c.name) + "/" + std::to_string(b), *mm,
                                               c.fps, scene::SceneBox{}, b);
            if (!sc)
                return fail(kExitFailure, std::string(c.name) + ": " + sc.error().what);
            scenes.push_back(std::move(*sc));
        }
    }
    struct Synthetic {
        hb::SyntheticScene scene;
        hb::SensorModel sensor;
        bool quick;
    };
    constexpr Synthetic kSynthetic[] = {
        {hb::SyntheticScene::Table, hb::SensorModel::StructuredLight, false},
        {hb::SyntheticScene::Head, hb::SensorModel::StructuredLight, true},
        {hb::SyntheticScene::Forearm, hb::SensorModel::StructuredLight, false},
        {hb::SyntheticScene::Occluder, hb::SensorModel::StructuredLight, true},
        {hb::SyntheticScene::Occluder, hb::SensorModel::TimeOfFlight, true},
        {hb::SyntheticScene::Occluder, hb::SensorModel::ActiveStereo, true},
    };
    for (const Synthetic &s : kSynthetic) {
        if (o.quick && !s.quick)
            continue;
        for (int b : bits) {
            hb::SyntheticSceneOptions so;
            so.seconds = o.quick ? 1.5 : 3.0;
            so.bits = b;
            so.sensor = s.sensor;
            std::fprintf(stderr, "rendering %s (%s, %d-bit) ...\n", hb::syntheticSceneName(s.scene),
                         hb::sensorModelName(s.sensor), b);
            auto sc = hb::makeSyntheticScene(s.scene, so);
            if (!sc)
                return fail(kExitFailure,
                            std::string(hb::syntheticSceneName(s.scene)) + ": " + sc.error().what);
            sc->name += "/" + std::to_string(b);
            scenes.push_back(std::move(*sc));
        }
    }
    for (hb::SyntheticScene s : {hb::SyntheticScene::Table, hb::SyntheticScene::Head}) {
        hb::SyntheticSceneOptions so;
        so.seconds = 1.0;
        so.bits = 16;
        so.noisy = false;
        auto sc = hb::makeSyntheticScene(s, so);
        if (!sc)
            return fail(kExitFailure, std::string("clean ") + sc.error().what);
        clean.push_back(std::move(*sc));
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
    // An --out where nothing can be written fails now, not after the whole run.
    if (const int rc = checkOutFolder("bench feel", o.out); rc != kExitOk)
        return rc;
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
    std::vector<hb::FeelScene> clean;
    if (const int rc = loadScenes(o, scenes, clean); rc != kExitOk)
        return rc;
    hb::FamilyPlan plan;
    if (o.quick) {
        plan.places = 1;
        plan.pressSpeeds = {0.10};
        plan.traceSpeeds = {0.05};
        plan.holdDepths = {1e-3};
        plan.moveSeconds = 0.6;
        plan.holdSeconds = 1.0;
    }
    std::vector<std::vector<hb::Stroke>> strokes;
    std::vector<std::string> placeNotes;
    for (const hb::FeelScene &s : scenes) {
        strokes.push_back(hb::makeFamilyStrokes(s, plan, &placeNotes));
        std::printf("%-28s %dx%d %s, %zu frames at %.1f fps, %zu strokes\n", s.name.c_str(),
                    s.width, s.height, s.format == scene::SampleFormat::Gray8 ? "8-bit" : "16-bit",
                    s.frameCount(), s.fps, strokes.back().size());
    }
    std::vector<std::vector<hb::Stroke>> cleanStrokes;
    hb::StrokePlan cleanPlan;
    cleanPlan.speeds = {0.05};
    cleanPlan.slidesPerSetting = 1;
    cleanPlan.crossings = false;
    cleanPlan.timing.slide = 0.5;
    cleanPlan.timing.hold = 0.2;
    for (const hb::FeelScene &s : clean)
        cleanStrokes.push_back(hb::makeStrokes(s, cleanPlan));
    std::fflush(stdout);
    std::vector<hb::FeelSetting> settings = hb::feelSettings(methods);
    if (o.quick) { // each method's first setting
        std::vector<hb::FeelSetting> first;
        for (const hb::FeelSetting &s : settings)
            if (first.empty() || first.back().method != s.method)
                first.push_back(s);
        settings = std::move(first);
    }
    // Time the updates on a SCHED_FIFO thread at the haptic priority, as `bench haptics` does, so
    // other processes do not preempt them; normal scheduling (with a note) when the kernel refuses.
    hb::FeelReport report;
    platform::RealtimeThreadOptions rt;
    rt.lockMemory = false;
    const platform::ThreadConfig cfg{
        "dt-bench-feel", o.fifo ? platform::SchedPolicy::Fifo : platform::SchedPolicy::Other,
        o.fifo ? platform::kHapticThread.relativePriority : 0, 8u << 20};
    platform::RealtimeThread worker(cfg, rt, [&](platform::StopToken) {
        report = hb::runFeelBenchmark(
            scenes, strokes, settings,
            [](const std::string &line) { std::fprintf(stderr, "  %s\n", line.c_str()); }, clean,
            cleanStrokes, o.dump);
        report.notes.insert(report.notes.begin(), placeNotes.begin(), placeNotes.end());
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
    std::printf("wrote %s/{feel.csv,feel_families.csv,feel_strokes.csv,feel.json,feel.png} in "
                "%.0f s (replays %.1f s)\n",
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
