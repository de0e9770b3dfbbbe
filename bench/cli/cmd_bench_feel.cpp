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

#include "bench_options.h"
#include "commands.h"
#include "option_cli.h"
#include "output_paths.h"
#include "depthtouch/haptics/feel_bench.h"
#include "depthtouch/haptics/feel_suite.h"
#include "depthtouch/haptics/renderer_table.h"
#include "depthtouch/platform/log.h"

namespace depthtouch::cli {

namespace {

namespace hb = haptics::bench;

std::vector<std::string> defaultFeelMethods()
{
    std::vector<std::string> out;
    for (const haptics::RendererEntry &e : haptics::rendererTable())
        if (e.feelByDefault)
            out.emplace_back(e.name);
    return out;
}

struct BenchFeelOptions {
    std::string out = "bench-feel-out";
    std::vector<std::string> clips;
    /// The renderer table's rows measured by default (RendererEntry::feelByDefault).
    std::vector<std::string> methods = defaultFeelMethods();
    std::string data;
    bool quick = false;
    bool fifo = true;
    std::string dump;
    bool dumpBallIdeal = false;
    std::vector<std::string> scenes;
    std::vector<std::string> settings;
};

/// What `bench feel` measures (its line in `depthtouch bench --help`).
constexpr const char *kAbout =
    "Feel on real and synthetic depth: six stroke families placed where the content is hardest, "
    "goals judged on the worst family x clip x setting";

/// The options of `bench feel`, in `--help` order.
const OptionRow<BenchFeelOptions> kBenchFeelRows[] = {
    benchOutRow<BenchFeelOptions>(),
    {"clip",
     &BenchFeelOptions::clips,
     "Also touch the depth of this video or DepthTouch file (repeatable)",
     {},
     kHideDefault},
    {"method",
     &BenchFeelOptions::methods,
     "Renderers (comma-separated), rows of the renderer table (docs/architecture.md)",
     {},
     kCommaList},
    {"data", &BenchFeelOptions::data,
     "Folder of the shared RGB-D captures (rgbd-7scenes-redkitchen/, rgbd-bonn-crowd/, "
     "rgbd-realsense-lab/, rgbd-azure-kinect-still/, rgbd-open3d/; default $DT_SHARED_DATA, else "
     "../shared/data); those missing are skipped"},
    {"quick", &BenchFeelOptions::quick,
     "8-bit only, fewer synthetic scenes, one stroke per family variant, each method's first "
     "setting (under 30 s)"},
    noFifoRow<BenchFeelOptions>(),
    {"scene",
     &BenchFeelOptions::scenes,
     "Touch only the scenes whose name contains this text (repeatable; e.g. bonn-crowd/16, "
     "synthetic-typing, a --clip's file name)",
     {},
     kHideDefault},
    {"setting",
     &BenchFeelOptions::settings,
     "Measure only these settings of the methods (comma-separated; e.g. finger, finger-ramp, "
     "modified-release: the rows of feel.csv)",
     {},
     kCommaList | kHideDefault},
    {"dump",
     &BenchFeelOptions::dump,
     "Write the per-update log of every stroke whose 'scene|setting|stroke' contains this text to "
     "feel_dump/ (e.g. 'bonn-crowd/8|finger|tap')",
     {},
     kHideDefault},
    {"dump-ball-ideal", &BenchFeelOptions::dumpBallIdeal,
     "Fill the dumped rows' ball_ideal_f*_n columns with the ideal ball's force (seconds a "
     "stroke; nan without it)"},
};

hb::FeelSuiteOptions suiteOptions(const BenchFeelOptions &o)
{
    return {o.data, o.clips, o.quick, o.fifo, o.dump, o.scenes, o.settings, o.dumpBallIdeal};
}

int fail(int code, const std::string &message)
{
    std::fprintf(stderr, "depthtouch bench feel: %s\n", message.c_str());
    return code;
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
            return fail(kExitBadInput,
                        "--method: unknown method '" + m + "' (" + haptics::rendererNames() + ")");
        methods.push_back(*parsed);
    }
    std::string known;
    if (const std::string bad = hb::unknownFeelSetting(suiteOptions(o), methods, known);
        !bad.empty())
        return fail(kExitBadInput,
                    "--setting: no setting '" + bad + "' of the methods measured (" + known + ")");
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
    if (const auto e = hb::loadFeelScenes(suiteOptions(o), scenes, clean))
        return fail(e->badInput ? kExitBadInput : kExitFailure, e->message);
    hb::FeelReport report;
    if (const auto e = hb::runFeelSuite(suiteOptions(o), methods, scenes, clean, report))
        return fail(kExitFailure, e->message);
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
