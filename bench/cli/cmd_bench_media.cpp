/// \file
/// \brief `depthtouch bench media`: encode and decode + pairing throughput of the color + depth
/// pair at 720×486 and 1920×1080 per x264 preset (the receiver on the ffmpeg backends, one decoder
/// thread per stream), and depth bitrate against depth PSNR against the force error of a replayed
/// stroke (7-Scenes redkitchen, or a synthetic clip with --synthetic); writes media_throughput.csv,
/// rate_accuracy.csv, rate_vs_accuracy.png and media_throughput.png into --out and prints a table
/// and the goals (720×486 ≥ 10×, 1920×1080 ≥ 2× real time at 30 fps).

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

#include "bench_options.h"
#include "commands.h"
#include "option_cli.h"
#include "output_paths.h"

#if __has_include("depthtouch/media/media_bench.h")
#include "depthtouch/drivers/backends.h"
#include "depthtouch/media/media_bench.h"
#include "depthtouch/platform/log.h"
#define DT_CLI_HAVE_MEDIA_BENCH 1
#else
#define DT_CLI_HAVE_MEDIA_BENCH 0
#endif

namespace depthtouch::cli {

namespace {

struct BenchMediaOptions {
    std::string data;
    std::string out = "bench-out/media";
    int frames = 60;
    int runs = 3;
    std::vector<std::string> sizes{"720x486", "1920x1080"};
    std::vector<std::string> codecSizes{"720x486", "1920x1080", "3840x2160"};
    std::vector<int> codecCrfs{12, 18, 24, 30};
    std::vector<std::string> presets{"ultrafast", "veryfast", "medium"};
    std::vector<int> depthCrfs{10, 18, 24, 30, 36, 42};
    std::string ratePreset = "medium";
    int encodeThreads = 1;
    int decodeThreads = 1;
    bool synthetic = false;
    bool keepFiles = false;
};

/// The options of `bench media`, in `--help` order.
const OptionRow<BenchMediaOptions> kBenchMediaRows[] = {
    sharedDataRow<BenchMediaOptions>(),
    benchOutRow<BenchMediaOptions>(),
    {"frames", &BenchMediaOptions::frames,
     "Frames per clip at 30 fps (the 60 real frames are played forward and back beyond 60)"},
    {"runs", &BenchMediaOptions::runs, "Decode + pairing runs per file (median run reported)"},
    {"sizes", &BenchMediaOptions::sizes,
     "Frame sizes WxH; the first also gets the rate/accuracy sweep"},
    {"presets", &BenchMediaOptions::presets, "x264 presets timed (color and depth)"},
    {"depth-crfs", &BenchMediaOptions::depthCrfs,
     "Depth CRFs of the rate/accuracy sweep (lossless always)"},
    {"rate-preset", &BenchMediaOptions::ratePreset,
     "x264 / x265 preset of the rate/accuracy sweep and the depth codec comparison"},
    {"codec-sizes", &BenchMediaOptions::codecSizes,
     "Frame sizes WxH of the depth codec comparison (h264 8 and 10 bits, hevc, ffv1); the first "
     "gets every --codec-crfs"},
    {"codec-crfs", &BenchMediaOptions::codecCrfs,
     "CRFs of each lossy depth codec in the comparison (0..51)"},
    {"encode-threads", &BenchMediaOptions::encodeThreads,
     "x264 threads per stream (0 = automatic)"},
    {"decode-threads", &BenchMediaOptions::decodeThreads, "Decoder threads per stream"},
    {"synthetic", &BenchMediaOptions::synthetic,
     "Use a synthetic clip instead of the 7-Scenes frames"},
    {"keep-files", &BenchMediaOptions::keepFiles,
     "Keep the encoded files (their folder is printed)"},
};

#if DT_CLI_HAVE_MEDIA_BENCH
int fail(int code, const std::string &message)
{
    std::fprintf(stderr, "depthtouch bench media: %s\n", message.c_str());
    return code;
}

bool parseSize(const std::string &text, int &w, int &h)
{
    std::istringstream ss(text);
    char x = 0;
    return static_cast<bool>(ss >> w >> x >> h) && x == 'x' && ss.eof() && w >= 16 && h >= 16 &&
           w <= 8192 && h <= 8192 && w % 2 == 0 && h % 2 == 0;
}

using namespace depthtouch::media::bench;

/// Checks the numeric options and parses --sizes and --codec-sizes. Returns kExitOk, or the exit
/// code after printing the one error line.
int checkBenchOptions(const BenchMediaOptions &o, std::vector<std::pair<int, int>> &sizes,
                      std::vector<std::pair<int, int>> &codecSizes)
{
    if (o.frames < 2 || o.frames > 10000)
        return fail(kExitBadInput, "--frames must be in 2..10000");
    if (o.runs < 1 || o.runs > 100)
        return fail(kExitBadInput, "--runs must be in 1..100");
    if (o.encodeThreads < 0 || o.encodeThreads > 64)
        return fail(kExitBadInput, "--encode-threads must be in 0..64 (0 = automatic)");
    if (o.decodeThreads < 1 || o.decodeThreads > 16)
        return fail(kExitBadInput, "--decode-threads must be in 1..16");
    for (const int crf : o.depthCrfs)
        if (crf < 0 || crf > 51)
            return fail(kExitBadInput,
                        "--depth-crfs values must be in 0..51 (lossless is always measured)");
    if (o.presets.empty())
        return fail(kExitBadInput, "--presets needs at least one x264 preset");
    for (const std::string &s : o.sizes) {
        int w = 0;
        int h = 0;
        if (!parseSize(s, w, h))
            return fail(kExitBadInput, "--sizes entries must be WxH, even, 16..8192 ('" + s + "')");
        sizes.emplace_back(w, h);
    }
    for (const std::string &s : o.codecSizes) {
        int w = 0;
        int h = 0;
        if (!parseSize(s, w, h))
            return fail(kExitBadInput,
                        "--codec-sizes entries must be WxH, even, 16..8192 ('" + s + "')");
        codecSizes.emplace_back(w, h);
    }
    for (const int crf : o.codecCrfs)
        if (crf < 0 || crf > 51)
            return fail(kExitBadInput, "--codec-crfs values must be in 0..51");
    if (o.codecCrfs.empty() && !o.codecSizes.empty())
        return fail(kExitBadInput, "--codec-crfs needs at least one CRF");
    if (sizes.empty())
        return fail(kExitBadInput, "--sizes needs at least one size");
    return kExitOk;
}

/// Finds the 7-Scenes folder (unless --synthetic: `scene` stays empty). Returns kExitOk, or the
/// exit code after printing the one error line.
int findScene(const BenchMediaOptions &o, std::string &scene)
{
    if (!o.synthetic) {
        scene = sharedDataFolder(o.data) + "/rgbd-7scenes-redkitchen";
        std::error_code ec;
        if (!std::filesystem::exists(scene + "/frame-000000.depth.png", ec))
            return fail(
                kExitBadInput,
                "no 7-Scenes frames in " + scene +
                    " (set --data or DT_SHARED_DATA, or run on a synthetic clip with --synthetic)");
    }
    return kExitOk;
}

/// The receiver on the ffmpeg backends, `decodeThreads` decoder threads per stream.
ReceiverBackends ffmpegBackends(int decodeThreads)
{
    const std::string decoderOptions = "threads=" + std::to_string(decodeThreads);
    ReceiverBackends backends;
    backends.makeSource = [] { return drivers::createMediaSource("ffmpeg", hal::BackendConfig{}); };
    backends.makeDecoder = [decoderOptions](const hal::StreamInfo &) {
        hal::BackendConfig c;
        c.options = hal::OptionList(decoderOptions);
        return drivers::createVideoDecoder("ffmpeg", c);
    };
    backends.description = "ffmpeg media source + ffmpeg decoders (" + decoderOptions + " each)";
    return backends;
}

/// The library's bench options from the command line's, encoding into `work`.
MediaBenchOptions benchOptions(const BenchMediaOptions &o, const std::filesystem::path &work)
{
    MediaBenchOptions mo;
    mo.presets = o.presets;
    mo.encodeThreads = o.encodeThreads;
    mo.decodeRuns = o.runs;
    mo.depthCrfs = o.depthCrfs;
    mo.ratePreset = o.ratePreset;
    mo.workDir = work.string();
    mo.keepFiles = o.keepFiles;
    return mo;
}

#endif

int runBenchMedia(const BenchMediaOptions &o)
{
#if DT_CLI_HAVE_MEDIA_BENCH
    // An --out where nothing can be written fails now, not after the whole run.
    if (const int rc = checkOutFolder("bench media", o.out); rc != kExitOk)
        return rc;
    std::vector<std::pair<int, int>> sizes;
    std::vector<std::pair<int, int>> codecSizes;
    if (const int rc = checkBenchOptions(o, sizes, codecSizes); rc != kExitOk)
        return rc;
    std::string scene;
    if (const int rc = findScene(o, scene); rc != kExitOk)
        return rc;
    // The figures are the output: backend chatter and the receiver's expected notes (the depth-only
    // files of the rate sweep) stay quiet unless DT_LOG asks for them.
    if (std::getenv("DT_LOG") == nullptr)
        platform::setLogLevel(platform::LogLevel::Error);

    // Encoded files go to a private scratch folder, removed at the end.
    std::string error;
    const std::unique_ptr<ScratchFolder> scratch = ScratchFolder::make(o.keepFiles, error);
    if (!scratch)
        return fail(kExitFailure, error);
    const std::filesystem::path &work = scratch->path();

    const ReceiverBackends backends = ffmpegBackends(o.decodeThreads);
    const MediaBenchOptions mo = benchOptions(o, work);
    MediaBenchReport report;
    report.backends = backends.description;
    double load = 0.0;
    if (getloadavg(&load, 1) == 1)
        report.loadBefore = load;
    report.fps = 30.0;
    MediaSizesPlan plan;
    plan.sizes = sizes;
    plan.frames = o.frames;
    plan.synthetic = o.synthetic;
    plan.scene = scene;
    plan.codecSizes = codecSizes;
    plan.codecCrfs = o.codecCrfs;
    plan.codecThreads = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 16u));
    plan.allThreads = ffmpegBackends(plan.codecThreads);
    if (const auto e = measureSizes(plan, backends, mo, report))
        return fail(e->badInput ? kExitBadInput : kExitFailure, e->message);
    if (getloadavg(&load, 1) == 1)
        report.loadAfter = load;
    if (!finishReport(report, o.out, o.keepFiles ? work.string() : std::string(), error))
        return fail(kExitFailure, error);
    return kExitOk;
#else
    (void)o;
    std::fprintf(stderr, "depthtouch bench media: built without FFmpeg (no encoder or decoder)\n");
    return kExitFailure;
#endif
}

} // namespace

void registerBenchMediaCommand(CLI::App &bench, int &exitCode)
{
    addTableCommand<BenchMediaOptions>(
        bench, "media",
        "Media pipeline: encode and decode + pairing fps per preset "
        "and size, depth rate vs PSNR vs haptic force error; CSV/PNG",
        kBenchMediaRows, runBenchMedia, exitCode);
}

} // namespace depthtouch::cli
