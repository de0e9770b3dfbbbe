/// \file
/// \brief `depthtouch bench feel`'s scenes and run: see feel_suite.h.

#include "depthtouch/haptics/feel_suite.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/image_io.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/thread_config.h"

namespace depthtouch::haptics::bench {

namespace {

constexpr long long kMaxClipFrames = 300; ///< 10 s at 30 fps: bounds the run time of a --clip.

/// Decodes the depth stream of \a url (a DepthTouch file, a depth video) into a FeelScene.
Result<FeelScene> loadClip(const std::string &url, const std::string &name)
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
    return sceneFromNearness(name, frames,
                             wide ? scene::SampleFormat::Gray16 : scene::SampleFormat::Gray8, fps,
                             scene::SceneBox{});
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

/// Places the stroke families on each scene (a line per scene on stdout) and the accuracy
/// strokes on the clean scenes.
void planStrokes(const FeelSuiteOptions &o, const std::vector<FeelScene> &scenes,
                 const std::vector<FeelScene> &clean, std::vector<std::vector<Stroke>> &strokes,
                 std::vector<std::string> &placeNotes,
                 std::vector<std::vector<Stroke>> &cleanStrokes)
{
    FamilyPlan plan;
    if (o.quick) {
        plan.places = 1;
        plan.pressSpeeds = {0.10};
        plan.traceSpeeds = {0.05};
        plan.holdDepths = {1e-3};
        plan.moveSeconds = 0.6;
        plan.holdSeconds = 1.0;
    }
    for (const FeelScene &s : scenes) {
        strokes.push_back(makeFamilyStrokes(s, plan, &placeNotes));
        std::printf("%-28s %dx%d %s, %zu frames at %.1f fps, %zu strokes\n", s.name.c_str(),
                    s.width, s.height, s.format == scene::SampleFormat::Gray8 ? "8-bit" : "16-bit",
                    s.frameCount(), s.fps, strokes.back().size());
    }
    StrokePlan cleanPlan;
    cleanPlan.speeds = {0.05};
    cleanPlan.slidesPerSetting = 1;
    cleanPlan.crossings = false;
    cleanPlan.timing.slide = 0.5;
    cleanPlan.timing.hold = 0.2;
    for (const FeelScene &s : clean)
        cleanStrokes.push_back(makeStrokes(s, cleanPlan));
}

/// The settings of \a methods: those --setting names, else every one (with --quick, each
/// method's first).
std::vector<FeelSetting> planSettings(const FeelSuiteOptions &o, const std::vector<Method> &methods)
{
    std::vector<FeelSetting> settings = feelSettings(methods);
    if (!o.settings.empty()) {
        std::erase_if(settings, [&o](const FeelSetting &s) {
            return std::find(o.settings.begin(), o.settings.end(), s.name) == o.settings.end();
        });
        return settings;
    }
    if (o.quick) { // each method's first setting
        std::vector<FeelSetting> first;
        for (const FeelSetting &s : settings)
            if (first.empty() || first.back().method != s.method)
                first.push_back(s);
        settings = std::move(first);
    }
    return settings;
}

/// \return whether a scene named \a name is touched under \a o.scenes (any of them is part of
/// the name, or there are none).
bool sceneWanted(const FeelSuiteOptions &o, const std::string &name)
{
    if (o.scenes.empty())
        return true;
    for (const std::string &s : o.scenes)
        if (name.find(s) != std::string::npos)
            return true;
    return false;
}

} // namespace

std::string unknownFeelSetting(const FeelSuiteOptions &o, const std::vector<Method> &methods,
                               std::string &known)
{
    const std::vector<FeelSetting> all = feelSettings(methods);
    known.clear();
    for (const FeelSetting &s : all)
        known += (known.empty() ? "" : ", ") + s.name;
    for (const std::string &name : o.settings)
        if (std::none_of(all.begin(), all.end(),
                         [&name](const FeelSetting &s) { return s.name == name; }))
            return name;
    return {};
}

std::string defaultSharedDataDir()
{
    const char *env = std::getenv("DT_SHARED_DATA");
    return std::string(env != nullptr && *env != '\0' ? env : "../shared/data");
}

std::optional<FeelSuiteError> loadFeelScenes(const FeelSuiteOptions &o,
                                             std::vector<FeelScene> &scenes,
                                             std::vector<FeelScene> &clean)
{
    const std::string data = o.data.empty() ? defaultSharedDataDir() : o.data;
    const std::vector<int> bits = o.quick ? std::vector<int>{8} : std::vector<int>{8, 16};
    const auto named = [&](const std::string &base, int b) {
        return sceneWanted(o, base + "/" + std::to_string(b));
    };
    for (const Capture &c : kCaptures) {
        if (std::none_of(bits.begin(), bits.end(), [&](int b) { return named(c.name, b); }))
            continue;
        auto mm = readCapture(data, c, o.quick ? kQuickFrames : c.frames);
        if (!mm)
            return FeelSuiteError{false, std::string(c.name) + ": " + mm.error().what};
        if (mm->empty()) {
            std::printf("note: no %s in %s/%s (set DT_SHARED_DATA or --data): skipped\n", c.name,
                        data.c_str(), c.folder);
            continue;
        }
        for (int b : bits) {
            if (!named(c.name, b))
                continue;
            std::fprintf(stderr, "mapping %s (%d-bit, holes kept) ...\n", c.name, b);
            auto sc = sceneFromSensorDepth(std::string(c.name) + "/" + std::to_string(b), *mm,
                                           c.fps, scene::SceneBox{}, b);
            if (!sc)
                return FeelSuiteError{false, std::string(c.name) + ": " + sc.error().what};
            scenes.push_back(std::move(*sc));
        }
    }
    struct Synthetic {
        SyntheticScene scene;
        SensorModel sensor;
        bool quick;
    };
    constexpr Synthetic kSynthetic[] = {
        {SyntheticScene::Table, SensorModel::StructuredLight, false},
        {SyntheticScene::Head, SensorModel::StructuredLight, true},
        {SyntheticScene::Forearm, SensorModel::StructuredLight, false},
        {SyntheticScene::Occluder, SensorModel::StructuredLight, true},
        {SyntheticScene::Occluder, SensorModel::TimeOfFlight, true},
        {SyntheticScene::Occluder, SensorModel::ActiveStereo, true},
        {SyntheticScene::Typing, SensorModel::TimeOfFlight, true},
        {SyntheticScene::Typing, SensorModel::StructuredLight, false},
        {SyntheticScene::Ridges, SensorModel::StructuredLight, false},
    };
    for (const Synthetic &s : kSynthetic) {
        if (o.quick && !s.quick)
            continue;
        for (int b : bits) {
            if (!named(syntheticFeelSceneName(s.scene, s.sensor), b))
                continue;
            SyntheticSceneOptions so;
            so.seconds = o.quick ? 1.5 : 3.0;
            so.bits = b;
            so.sensor = s.sensor;
            std::fprintf(stderr, "rendering %s (%s, %d-bit) ...\n", syntheticSceneName(s.scene),
                         sensorModelName(s.sensor), b);
            auto sc = makeSyntheticScene(s.scene, so);
            if (!sc)
                return FeelSuiteError{false, std::string(syntheticSceneName(s.scene)) + ": " +
                                                 sc.error().what};
            sc->name += "/" + std::to_string(b);
            scenes.push_back(std::move(*sc));
        }
    }
    for (SyntheticScene s : {SyntheticScene::Table, SyntheticScene::Head}) {
        SyntheticSceneOptions so;
        so.seconds = 1.0;
        so.bits = 16;
        so.noisy = false;
        auto sc = makeSyntheticScene(s, so);
        if (!sc)
            return FeelSuiteError{false, std::string("clean ") + sc.error().what};
        clean.push_back(std::move(*sc));
    }
    for (const std::string &clip : o.clips) {
        auto c = loadClip(clip, std::filesystem::path(clip).filename().string());
        if (!c)
            return FeelSuiteError{true,
                                  "cannot read depth of --clip '" + clip + "': " + c.error().what};
        if (sceneWanted(o, c->name))
            scenes.push_back(std::move(*c));
    }
    if (scenes.empty() && !o.scenes.empty())
        return FeelSuiteError{true, "--scene: no scene's name contains '" + o.scenes.front() + "'" +
                                        (o.scenes.size() > 1 ? " (nor the others)" : "") +
                                        " (names such as bonn-crowd/16, synthetic-head/8)"};
    return std::nullopt;
}

std::optional<FeelSuiteError> runFeelSuite(const FeelSuiteOptions &o,
                                           const std::vector<Method> &methods,
                                           const std::vector<FeelScene> &scenes,
                                           const std::vector<FeelScene> &clean, FeelReport &report)
{
    std::vector<std::vector<Stroke>> strokes;
    std::vector<std::string> placeNotes;
    std::vector<std::vector<Stroke>> cleanStrokes;
    planStrokes(o, scenes, clean, strokes, placeNotes, cleanStrokes);
    std::fflush(stdout);
    const std::vector<FeelSetting> settings = planSettings(o, methods);
    // Time the updates on a SCHED_FIFO thread at the haptic priority, as `bench haptics` does, so
    // other processes do not preempt them; normal scheduling (with a note) when the kernel refuses.
    platform::RealtimeThreadOptions rt;
    rt.lockMemory = false;
    const platform::ThreadConfig cfg{
        "dt-bench-feel", o.fifo ? platform::SchedPolicy::Fifo : platform::SchedPolicy::Other,
        o.fifo ? platform::kHapticThread.relativePriority : 0, 8u << 20};
    platform::RealtimeThread worker(cfg, rt, [&](platform::StopToken) {
        report = runFeelBenchmark(
            scenes, strokes, settings,
            [](const std::string &line) { std::fprintf(stderr, "  %s\n", line.c_str()); }, clean,
            cleanStrokes, o.dump, o.dumpBallIdeal);
        report.notes.insert(report.notes.begin(), placeNotes.begin(), placeNotes.end());
    });
    if (Result<void> started = worker.start(); !started)
        return FeelSuiteError{false, std::string("cannot start the bench thread: ") +
                                         started.error().what};
    char how[160];
    std::printf("\nupdate times: steady_clock around update() on the timing thread: %s\n\n",
                worker.report().format(how, sizeof how));
    worker.join();
    return std::nullopt;
}

} // namespace depthtouch::haptics::bench
