/// \file
/// \brief `depthtouch demo`: the main job with no arguments. Encodes the built-in synthetic scene
/// (the turning head, rendered with OpenGL ES: color from the color buffer, depth from the
/// Z-buffer, paper §V.A) into a two-stream file once (kept in the output folder and reused), then
/// plays it with `play` on the headless EGL display with the simulated hand stroking the face and
/// across the head's contour, and leaves side-by-side snapshots, the force log, the stats JSON and
/// a PNG chart of the force and the heights over play time and the force's power spectral density
/// (paper Fig. 12) in the output folder. After the run it decodes the clip's depth again and puts
/// the surface under the finger beside each force-log row, for the feel figures
/// (haptics::computeFeel: safety trips, pop-through, phantom force, spikes) and the share of the
/// contact time spent on the head rather than on the curtain.
/// Units: s, m, N, scene-box frame (docs/architecture.md §3; the player's default box and an
/// identity device mapping, so the simulated hand's device coordinates are box coordinates).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <glm/geometric.hpp>

#include "commands.h"
#include "option_cli.h"
#include "output_paths.h"
#include "depthtouch/demo/demo_chart.h"
#include "depthtouch/demo/demo_clip.h"
#include "depthtouch/demo/demo_feel.h"
#include "depthtouch/drivers/backends.h"
#include "depthtouch/haptic_task/haptic_task.h"
#include "depthtouch/haptics/feel.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/percentile.h"
#include "depthtouch/platform/stop_signals.h"
#include "play.h"
#include "play_options.h"
#include "source_providers.h"

namespace depthtouch::cli {

namespace {

/// The simulated finger on the head (box frame, m; the face is about x ±11 mm, y −4..21 mm, its
/// nose 8 mm in front of the box centre, the curtain 16 mm behind it): from the forehead over the
/// right cheek, the chin and the left cheek, across the contour onto the curtain and back, at
/// 3 cm/s, pressing 4 mm in (1.2 N with the hand's 300 N/m).
constexpr const char *kHeadStroke = "intent=stroke,path=0:0.015/0.007:0.004/0:-0.001/-0.007:0.004/"
                                    "-0.02:0.004,speed=0.03,z=0.012,depth=0.004,delay=0.5";

struct DemoOptions {
    double duration = 8.0; ///< Seconds of playback (the clip loops).
    std::string scene = "head";
    std::string size = "480x324"; ///< Clip size WxH.
    int frames = 120;             ///< Clip length, frames at 30 fps.
    std::string outDir = "demo-out";
    std::string display = "headless";
    std::string haptic = "sim";
    std::string hapticOptions; ///< Empty with sim: kHeadStroke on the head, else "intent=stroke".
    double stiffness = 800.0;
    double rate = 1000.0;
    bool requireRt = false;
    bool rebuild = false; ///< Encode the clip again even when it exists.
};

/// What `demo` does (its line in `depthtouch --help`).
constexpr const char *kAbout =
    "The main job: play the built-in head scene and touch it with the simulated hand";

/// The options of `demo`, in `--help` order.
const OptionRow<DemoOptions> kDemoRows[] = {
    {"duration", &DemoOptions::duration, "Seconds of playback"},
    {"out", &DemoOptions::outDir, "Folder for the clip, snapshots, force log, stats, chart"},
    {"scene", &DemoOptions::scene, "Built-in scene: head, spheres, cut"},
    {"size", &DemoOptions::size, "Clip size WxH"},
    {"frames", &DemoOptions::frames, "Clip length in frames (30 fps)"},
    {"display", &DemoOptions::display, "Display backend"},
    {"haptic", &DemoOptions::haptic, "Haptic device backend: sim, mock, falcon, none"},
    {"haptic-options", &DemoOptions::hapticOptions,
     "Options of the haptic device (default for sim: a stroke over the face and across the head's "
     "contour)"},
    {"stiffness", &DemoOptions::stiffness, "Surface stiffness, N/m (100..3000)"},
    {"rate", &DemoOptions::rate, "Haptic servo rate, Hz"},
    {"require-rt", &DemoOptions::requireRt, "Fail when SCHED_FIFO is refused"},
    {"rebuild", &DemoOptions::rebuild, "Render and encode the clip again"},
};

/// Measures the run in \a forceLog against the clip's depth, prints the feel lines and draws the
/// chart (when the clip or the log cannot be read, prints a note instead).
/// \return why a file of the chart could not be written, or empty.
std::string reportFeel(const DemoOptions &o, const std::string &clip, const std::string &forceLog)
{
    const std::vector<demo::LogRow> rows = demo::readForceLog(forceLog);
    std::string err;
    const std::unique_ptr<demo::DemoSurface> surface = demo::loadClipSurface(clip, err);
    if (!surface || rows.empty()) {
        std::printf("  feel              not measured: %s\n",
                    err.empty() ? "empty force log" : err.c_str());
        return {};
    }
    const std::vector<double> play = demo::playTimes(rows);
    std::vector<std::array<double, 6>> plot;
    plot.reserve(rows.size());
    const demo::DemoFeel d = demo::measureFeel(rows, play, *surface, plot);
    const haptics::FeelFigures &f = d.feel;
    std::printf("  feel              %zu safety trips (%zu at real cuts), pop-through %.0f ms, "
                "phantom force %.0f ms, %.2f spikes/s while sliding (%.1f s), largest force step "
                "%.2f N per update\n",
                f.trips, f.realCutTrips, f.popThroughMs, f.phantomMs, f.spikesPerSecond,
                f.slidingSeconds, f.maxStepN);
    std::printf("  contact on %-6s %.0f %% of %.1f s in contact (surface over %.0f mm nearer "
                "than the %s)\n",
                o.scene == "head" ? "head" : "fig.",
                d.contactSeconds > 0 ? 100.0 * d.figureSeconds / d.contactSeconds : 0.0,
                d.contactSeconds, 1e3 * demo::kFigureMargin,
                o.scene == "head" ? "curtain" : "backdrop");
    // "curtain 528 N/m", or "curtain not touched" when the finger never pressed it.
    auto felt = [](const char *what, const std::vector<double> &v) {
        char text[64];
        if (v.empty())
            std::snprintf(text, sizeof text, "%s not touched", what);
        else
            std::snprintf(text, sizeof text, "%s %.0f N/m", what, platform::percentile(v, 0.5));
        return std::string(text);
    };
    std::printf("  stiffness felt    %s, %s (median |F| / depth; the clip's material track scales "
                "--stiffness %.0f N/m)\n",
                felt(o.scene == "head" ? "head" : "figure", d.figureStiffness).c_str(),
                felt(o.scene == "head" ? "curtain" : "backdrop", d.backdropStiffness).c_str(),
                o.stiffness);
    std::string lost;
    const std::string chart = demo::chartForce(o.outDir, plot, o.rate, lost);
    std::printf("  chart             %s\n", chart.c_str());
    return lost;
}

/// \return whether \a name is a compiled-in backend of \a kind.
bool isBackend(drivers::BackendKind kind, const std::string &name)
{
    const std::vector<hal::BackendInfo> all = drivers::listBackends(kind);
    return std::any_of(all.begin(), all.end(),
                       [&name](const hal::BackendInfo &b) { return name == b.name; });
}

/// The checks of every option, before anything is rendered: \return the one-line message of the
/// first value refused (bad input), or empty.
std::string checkDemoOptions(const DemoOptions &o)
{
    int w = 0;
    int h = 0;
    char x = 0;
    int used = 0;
    // Even sizes: the colour is coded 4:2:0.
    if (std::sscanf(o.size.c_str(), "%d%c%d%n", &w, &x, &h, &used) != 3 || x != 'x' ||
        static_cast<std::size_t>(used) != o.size.size() || w < 16 || h < 16 || w > 4096 ||
        h > 4096 || w % 2 != 0 || h % 2 != 0)
        return "--size must be WxH, even, 16..4096 pixels each";
    if (o.frames < 2 || o.frames > 100000)
        return "--frames must be in [2, 100000]";
    if (!(o.duration > 0.0) || !std::isfinite(o.duration))
        return "--duration must be a number of seconds > 0";
    if (o.scene != "head" && o.scene != "spheres" && o.scene != "cut")
        return "--scene must be head, spheres or cut";
    if (!isBackend(drivers::BackendKind::Display, o.display))
        return "--display: no display backend '" + o.display + "' (see depthtouch backends)";
    if (!isBackend(drivers::BackendKind::HapticDevice, o.haptic))
        return "--haptic: no haptic device backend '" + o.haptic + "' (see depthtouch backends)";
    PlayOptions p;
    p.url = "demo.mkv";
    p.stiffness = o.stiffness;
    p.rate = o.rate;
    return checkPlayOptionValues(p);
}

int runDemo(const DemoOptions &o)
{
    if (const std::string bad = checkDemoOptions(o); !bad.empty()) {
        std::fprintf(stderr, "depthtouch demo: %s\n", bad.c_str());
        return kExitBadInput;
    }
    // The demo's report is its own lines and the play's summary, as play's: the log's timestamped
    // lines (backend choices, the decoder's hwaccel probe) only when DT_LOG asks for them.
    if (std::getenv("DT_LOG") == nullptr)
        platform::setLogLevel(platform::LogLevel::Off);
    std::string hapticOptions = o.hapticOptions;
    if (hapticOptions.empty() && o.haptic == "sim")
        hapticOptions = o.scene == "head" ? kHeadStroke : "intent=stroke";
    // A folder where nothing can be written is found now, not after the clip and the play.
    if (const platform::OutputPathCheck c = platform::checkOutputFolder("--out", o.outDir);
        c.exitCode != kExitOk) {
        std::fprintf(stderr, "depthtouch demo: %s\n", c.message.c_str());
        return c.exitCode;
    }
    std::error_code ec;
    std::filesystem::create_directories(o.outDir + "/snapshots", ec);
    if (ec) {
        std::fprintf(stderr, "depthtouch demo: cannot create '%s': %s\n", o.outDir.c_str(),
                     ec.message().c_str());
        return kExitFailure;
    }
    // The clip: made once per scene, size and length, then reused.
    const std::string clip = o.outDir + "/" + o.scene + "-" + o.size + "-" +
                             std::to_string(o.frames) + "-materials-sound.mkv";
    if (o.rebuild || !std::filesystem::exists(clip)) {
        std::printf("Rendering the built-in '%s' scene (%d frames at %s) into %s (once)...\n",
                    o.scene.c_str(), o.frames, o.size.c_str(), clip.c_str());
        std::fflush(stdout);
        bool interrupted = false;
        if (const std::string err = demo::encodeScene(o.scene, o.size, o.frames, clip,
                                                      makeSourceProviders(), interrupted);
            !err.empty()) {
            std::fprintf(stderr, "depthtouch demo: %s\n", err.c_str());
            return kExitFailure;
        }
        if (interrupted) {
            std::fprintf(stderr,
                         "depthtouch demo: interrupted by %s while making the clip; "
                         "nothing was kept\n",
                         platform::stopSignalName(platform::StopSignals::caughtSignal()));
            return kExitInterrupted;
        }
    }
    for (const auto &entry : std::filesystem::directory_iterator(o.outDir + "/snapshots", ec))
        std::filesystem::remove(entry.path(), ec);

    PlayOptions p;
    p.url = clip;
    p.display = o.display;
    p.haptic = o.haptic;
    p.hapticOptions = hapticOptions;
    p.stiffness = o.stiffness;
    p.rate = o.rate;
    p.loop = true;
    p.duration = o.duration;
    p.snapshotDir = o.outDir + "/snapshots";
    p.snapshotEvery = 30;
    p.forceLog = o.outDir + "/force-log.csv";
    p.stats = o.outDir + "/stats.json";
    p.requireRt = o.requireRt;
    p.quiet = false; // the play's summary is the demo's report (state lines only on a terminal)
    std::printf("Playing it for %.0f s on the '%s' display with the '%s' haptic device "
                "(%s)\n",
                o.duration, o.display.c_str(), o.haptic.c_str(), hapticOptions.c_str());
    std::fflush(stdout);
    const PlayResult r = runPlay(p);
    if (r.exitCode != kExitOk)
        return r.exitCode;
    if (const std::string lost = reportFeel(o, clip, p.forceLog); !lost.empty()) {
        std::fprintf(stderr, "depthtouch demo: %s\n", lost.c_str());
        return kExitFailure;
    }
    std::printf("  snapshots         %s/snapshots/ (side-by-side, every 30 frames)\n",
                o.outDir.c_str());
    return kExitOk;
}

} // namespace

void registerDemoCommand(CLI::App &app, int &exitCode)
{
    addTableCommand<DemoOptions>(app, "demo", kAbout, kDemoRows, runDemo, exitCode);
}

} // namespace depthtouch::cli
