/// \file
/// \brief `depthtouch touch DEPTH --trajectory traj.csv --out forces.csv`: replays a HIP trajectory
/// against a depth video at the haptic rate and writes the force log CSV (docs/architecture.md §4),
/// deterministically. Bad input prints one error line and exits 2 without leaving an output file.
/// A stop signal (SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGXFSZ: stop_signals.h) ends the
/// replay with one line and exit 130, nothing written; one that comes while the force log is
/// written lets it be finished and renamed first (never a temporary file left behind).
///
/// DEPTH is a raw gray file (with --size) or anything FFmpeg reads: a video file, a URL or an image
/// sequence pattern (`frame-%06d.depth.png`, frame rate --fps). The depth stream (or the only
/// stream, its luma when it is YUV) is decoded through the `ffmpeg` media source and decoder
/// backends; frame times come from the PTS. 16-bit samples of a depth stream (titled depth, or
/// carrying depth metadata) are nearness unless --near/--far are given: then they are metric depth
/// (--depth-scale metres per unit), converted to 16-bit nearness (docs/architecture.md §3) with 0
/// and saturated samples kept as holes (§3 "Holes": free space to the finger). Frames of a file
/// with the depth_occupancy tag carry its hole threshold; 10-bit depth is widened to 16 bits by bit
/// replication, as the player does. The 16-bit samples of an input that says nothing of depth (an
/// image sequence from a depth camera) are metric depth: without --near/--far its planes are the
/// robust range of the first frame (as `encode` takes it), named in the summary.

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "commands.h"
#include "option_cli.h"
#include "output_paths.h"
#include "source_providers.h"
#include "depthtouch/depth/conversion.h"
#include "depthtouch/drivers/backends.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/haptics/renderer_table.h"
#include "depthtouch/haptics/replay.h"
#include "depthtouch/receiver/depth_file.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/stop_signals.h"
#include "depthtouch/touch/touch_frames.h"

namespace depthtouch::cli {

namespace {

struct TouchOptions {
    std::string depth;
    std::string trajectory;
    std::string out;
    std::string size;
    double fps = 30.0;
    int bits = 8;
    double rate = 1000.0;
    double stiffness = 800.0;
    double damping = 0.0;
    double maxForce = 8.5;
    double boxWidth = 0.10;
    double boxDepth = 0.04;
    std::string method = "finger";
    bool noCorrection = false;
    bool noInterpolation = false;
    bool noSafety = false;
    double maxForceStep = 2.0;
    /// --reengage: play's default (one constant), so touch measures what play renders.
    std::string reengage = haptics::reengageName(haptics::kCommandReengage);
    std::string fingerContact = "god-object"; ///< --finger-contact (RendererConfig's default)
    double fingerRadius = std::nan("");       ///< m; NaN: 0.015 x box width
    double staticFriction = 0.0;              ///< μs of the friction cone
    double dynamicFriction = 0.0;             ///< μd
    std::string material;                     ///< --material SRC: the material track's codes
    double rampTime = 0.25;
    std::optional<double> nearM;
    std::optional<double> farM;
    double depthScale = 0.001;
    std::string depthMapping = "inverse_z";
    bool quiet = false; ///< No summary after the run.
};

/// What `touch` does (its line in `depthtouch --help`).
constexpr const char *kAbout =
    "Replay a HIP trajectory against a depth video at the haptic rate; write the force log CSV";

/// The options of `touch`, in `--help` order.
const OptionRow<TouchOptions> kTouchRows[] = {
    {"DEPTH",
     &TouchOptions::depth,
     "Depth video: any file, URL or image-sequence pattern FFmpeg reads (frame-%06d.depth.png), or "
     "raw 8/16-bit gray frames with --size",
     {},
     kPositional | kRequired},
    {"trajectory", &TouchOptions::trajectory, "HIP trajectory CSV t,x,y,z (s, m)", {}, kRequired},
    {"out", &TouchOptions::out, "Force log CSV to write", {}, kRequired},
    {"size", &TouchOptions::size,
     "Raw depth frame size WxH (pixels); a raw file is at most 256 MiB"},
    {"fps", &TouchOptions::fps, "Frame rate of raw depth and image sequences (frames/s)"},
    {"near",
     &TouchOptions::nearM,
     "Near plane (m): 16-bit input is metric depth, converted to nearness (with --far)",
     {},
     kHideDefault},
    {"far", &TouchOptions::farM, "Far plane (m) of the metric depth conversion", {}, kHideDefault},
    {"depth-scale", &TouchOptions::depthScale, "Metres per metric depth unit (0.001: mm)"},
    {"depth-mapping", &TouchOptions::depthMapping, "Metric conversion: inverse_z | linear"},
    {"bits", &TouchOptions::bits, "Raw depth sample size: 8 or 16 (host byte order)"},
    {"rate", &TouchOptions::rate, "Haptic update rate (Hz, 100..10000)"},
    {"stiffness", &TouchOptions::stiffness, "Spring stiffness k (N/m, 100..3000)"},
    {"damping", &TouchOptions::damping, "Damping b (N·s/m, 0..1000)"},
    {"max-force", &TouchOptions::maxForce, "Device maximum force (N, up to 1000)"},
    {"box-width", &TouchOptions::boxWidth, "Scene box width (m)"},
    {"box-depth", &TouchOptions::boxDepth, "Scene box depth (m)"},
    {"method", &TouchOptions::method,
     "Haptic renderer, a row of the renderer table (docs/architecture.md)",
     oneOf(haptics::rendererChoiceWords())},
    {"no-correction", &TouchOptions::noCorrection, "Turn off fix (a), collision correction"},
    {"no-interpolation", &TouchOptions::noInterpolation, "Turn off fix (b), surface interpolation"},
    {"no-safety", &TouchOptions::noSafety, "Turn off fix (c), force-jump safety"},
    {"max-force-step", &TouchOptions::maxForceStep,
     "Force change per update that trips safety (N); the default 2 N never trips while stroking "
     "smooth surfaces at 1 m/s (k=800: <= 0.8 N/update) and always trips at a cut of half the box "
     "depth (16 N)"},
    {"reengage", &TouchOptions::reengage,
     "After a force-jump trip (scene cut): ramp (re-seat the proxy, ramp the force in) | release "
     "(paper IV.C); ramp is play's default too, so touch measures what play renders",
     oneOf("ramp release")},
    {"finger-contact", &TouchOptions::fingerContact,
     "How --method finger meets the surface: god-object (slides on from the last proxy) | penalty "
     "(the plane under the HIP) | adaptive (penalty while the HIP rests, god-object while it "
     "slides); god-object is the default, as in play",
     oneOf("god-object penalty adaptive")},
    {"quiet", &TouchOptions::quiet,
     "No summary of the run (on stdout; on stderr when --out is stdout)"},
    {"finger-radius",
     &TouchOptions::fingerRadius,
     "finger method: half-width of the surface patch the finger touches (m); default 0.015 x box "
     "width",
     {},
     kHideDefault},
    {"ramp-time", &TouchOptions::rampTime, "Ramp duration for --reengage ramp (s)"},
    {"static-friction", &TouchOptions::staticFriction,
     "Static friction coefficient on the proxy, 0..2 (finger, modified, proxy-graph): the proxy "
     "holds while the tangential force is within MU times the normal force"},
    {"dynamic-friction", &TouchOptions::dynamicFriction,
     "Dynamic friction coefficient, 0..2: a sliding proxy keeps the tangential force at MU times "
     "the normal force"},
    {"material", &TouchOptions::material,
     "Per-pixel haptic materials (docs/materials.md): an RGB code image (a still map), sequence or "
     "video, or a DepthTouch file (its material stream); frame k goes with depth frame k, the last "
     "holds. Overrides the friction options where it lies (finger, modified, proxy-graph)"},
};

std::atomic<bool> gTouchStop{false};

int fail(int code, const std::string &message)
{
    std::fprintf(stderr, "depthtouch touch: %s\n", message.c_str());
    return code;
}

/// Largest raw depth file (--size) and trajectory read into memory, bytes.
constexpr std::size_t kMaxRawDepthBytes = std::size_t{256} << 20;
constexpr std::size_t kMaxTrajectoryBytes = std::size_t{64} << 20;

/// Reads \a path whole (platform::readFileBounded: bounded size, a FIFO waits at most 10 s).
/// \return the bytes, or a one-line reason naming \a what and the path.
Result<std::vector<std::uint8_t>> readInput(const std::string &path, std::size_t maxBytes,
                                            const char *what, std::string &error)
{
    auto r = platform::readFileBounded(path, maxBytes);
    if (!r) {
        char buf[256];
        error = std::string("cannot read ") + what + " '" + path + "': " +
                (std::strcmp(r.error().what, "is larger than the limit") == 0
                     ? "it is larger than " + std::to_string(maxBytes >> 20) + " MiB"
                     : std::string(r.error().format(buf, sizeof buf)));
    }
    return r;
}

/// The depth input as a raw gray file (--size). Returns kExitOk, or the exit code after printing
/// the one error line.
int openRawDepth(const TouchOptions &o, std::unique_ptr<haptics::FrameProvider> &frames)
{
    using namespace depthtouch::haptics;
    int w = 0;
    int h = 0;
    char x = 0;
    std::istringstream ss(o.size);
    if (!(ss >> w >> x >> h) || x != 'x' || w < 2 || h < 2 || !ss.eof())
        return fail(kExitBadInput, "--size must be WxH with W, H >= 2");
    if (o.bits != 8 && o.bits != 16)
        return fail(kExitBadInput, "--bits must be 8 or 16");
    std::string error;
    auto bytes = readInput(o.depth, kMaxRawDepthBytes, "depth file", error);
    if (!bytes)
        return fail(kExitBadInput, error);
    auto raw = std::make_unique<RawVideoFrameProvider>(
        std::move(*bytes), w, h, o.bits == 8 ? SampleFormat::Gray8 : SampleFormat::Gray16, o.fps);
    if (auto v = raw->validate(); !v)
        return fail(kExitBadInput, std::string(v.error().what) + " ('" + o.depth + "')");
    frames = std::move(raw);
    return kExitOk;
}

/// The depth input through the ffmpeg backends, with the metric conversion of --near/--far (or
/// of the first frame's robust range, for an input that says nothing of depth). \a decoded
/// receives the provider (owned by \a frames). Returns kExitOk, or the exit code after printing
/// the one error line.
int openDecodedDepth(const TouchOptions &o, std::unique_ptr<haptics::FrameProvider> &frames,
                     const receiver::DepthFile *&decoded)
{
    if (!(o.fps > 0.0) || o.fps > 10'000.0)
        return fail(kExitBadInput, "--fps must be in (0, 10000]");
    if (!(o.depthScale > 0.0))
        return fail(kExitBadInput, "--depth-scale must be positive");
    auto mapping = depth::parseMapping(o.depthMapping);
    if (!mapping)
        return fail(kExitBadInput, "--depth-mapping must be inverse_z or linear");
    receiver::DepthFile::Metric unplanned;
    unplanned.convert.raw.metresPerUnit = o.depthScale;
    unplanned.convert.mapping = *mapping;
    unplanned.convert.vmax = 65535.0;
    std::optional<receiver::DepthFile::Metric> metric;
    if (o.nearM || o.farM) {
        if (!o.nearM || !o.farM || !(*o.nearM > 0.0) || !(*o.farM > *o.nearM))
            return fail(kExitBadInput,
                        "--near and --far must both be given with 0 < near < far (m)");
        metric = unplanned;
        metric->convert.range = depth::DepthRange{*o.nearM, *o.farM};
    }
    // The output contract is one error line on bad input: backend selection chatter (Info)
    // stays quiet unless the user asked for it with DT_LOG.
    if (std::getenv("DT_LOG") == nullptr)
        platform::setLogLevel(platform::LogLevel::Warning);
    // The ffmpeg backends, the source at the --fps of inputs that have none (image sequences).
    const std::string fpsOption = "fps=" + std::to_string(o.fps);
    hal::BackendConfig sourceConfig;
    sourceConfig.options = hal::OptionList(fpsOption);
    auto source = drivers::createMediaSource("ffmpeg", sourceConfig);
    if (!source)
        return fail(kExitBadInput,
                    std::string("no FFmpeg media source in this build: ") + source.error().what);
    auto decoder = drivers::createVideoDecoder("ffmpeg", hal::BackendConfig{});
    if (!decoder)
        return fail(kExitBadInput, std::string("no FFmpeg video decoder: ") + decoder.error().what);
    auto file =
        std::make_unique<receiver::DepthFile>(std::move(*source), std::move(*decoder), o.fps);
    std::string error;
    if (!file->open(o.depth, metric, unplanned, error))
        return fail(kExitBadInput, error);
    auto provider = std::make_unique<touch::DepthFileFrames>(std::move(file));
    decoded = &provider->file();
    frames = std::move(provider);
    return kExitOk;
}

/// One paragraph after a run: updates, time and rate, method, the share in contact, the largest
/// force and the safety trips, and where the force log went. On stdout, or on stderr when the
/// force log itself goes to stdout.
void printTouchSummary(const TouchOptions &o, const std::vector<haptics::ForceLogRow> &rows,
                       const std::string &readingNote)
{
    const haptics::ReplaySummary sum = haptics::summarizeReplay(rows);
    std::FILE *sink = o.out == "/dev/stdout" || o.out == "-" ? stderr : stdout;
    std::fprintf(
        sink,
        "touch: %zu updates over %.3f s at %g Hz (%s): %.0f %% in contact, max force %.2f N "
        "(device maximum %.2f N), %zu safety trips, energy into the hand %.3f mJ (peak %.3f mJ); "
        "force log %s\n",
        rows.size(), sum.seconds, o.rate, o.method.c_str(), sum.contactPercent, sum.maxForce,
        o.maxForce, sum.trips, 1e3 * sum.energy, 1e3 * sum.energyPeak, o.out.c_str());
    if (!readingNote.empty())
        std::fprintf(sink, "touch: depth: %s\n", readingNote.c_str());
}

int runTouch(const TouchOptions &o)
{
    using namespace depthtouch::haptics;
    auto method = parseMethod(o.method);
    if (!method)
        return fail(kExitBadInput, "--method must be " + rendererNames());
    if (o.reengage != "release" && o.reengage != "ramp")
        return fail(kExitBadInput, "--reengage must be release or ramp");
    const auto contact = parseFingerContact(o.fingerContact);
    if (!contact)
        return fail(kExitBadInput, "--finger-contact must be god-object, penalty or adaptive");
    ReplayOptions opt;
    opt.rate = o.rate;
    opt.method = *method;
    RendererConfig &c = opt.config;
    c.box = SceneBox{o.boxWidth, o.boxDepth};
    c.stiffness = o.stiffness;
    c.damping = o.damping;
    c.maxForce = o.maxForce;
    // The baselines run with every fix off; the --no-* flags turn single fixes off in `modified`.
    const RendererEntry &entry = rendererEntry(*method);
    const bool fixes = entry.fixes;
    c.correction = fixes && !o.noCorrection;
    c.interpolation = fixes && !o.noInterpolation;
    c.safety = fixes && !o.noSafety;
    c.maxForceStep = o.maxForceStep;
    c.reengage = o.reengage == "ramp" ? Reengage::Ramp : Reengage::Release;
    c.rampTime = o.rampTime;
    c.fingerRadius = o.fingerRadius;
    c.fingerContact = *contact;
    c.staticFriction = o.staticFriction;
    c.dynamicFriction = o.dynamicFriction;
    if (!entry.friction && (o.staticFriction > 0.0 || o.dynamicFriction > 0.0))
        return fail(kExitBadInput, std::string("--method ") + entry.name + " has no friction");
    if (!entry.friction && !o.material.empty())
        return fail(kExitBadInput, std::string("--method ") + entry.name + " has no materials");
    if (auto v = validateReplayOptions(opt); !v)
        return fail(kExitBadInput, v.error().what);
    // The output first: a directory, a FIFO without a reader or a missing folder fails before
    // the work, and only a regular file or a new path is ever replaced.
    if (auto p = platform::planOutput(o.out); !p)
        return fail(kExitBadInput, "cannot write '" + o.out + "': it " + p.error().what);
    if (const platform::OutputPathCheck same = platform::checkDistinctPaths(
            {{"the input", o.depth}, {"--trajectory", o.trajectory}, {"--material", o.material}},
            {{"--out", o.out}});
        same.exitCode != kExitOk)
        return fail(same.exitCode, same.message);

    // Depth input: a raw gray file with --size, else anything FFmpeg reads.
    std::unique_ptr<FrameProvider> frames;
    const receiver::DepthFile *decoded = nullptr;
    touch::MaterialFrameProvider *materialFrames = nullptr;
    if (const int rc =
            !o.size.empty() ? openRawDepth(o, frames) : openDecodedDepth(o, frames, decoded);
        rc != kExitOk)
        return rc;
    if (!o.material.empty()) {
        media::SourceOptions so;
        so.fps = o.fps;
        so.streamTitle = "material"; // a DepthTouch file gives its material stream
        // One error line on bad input: FFmpeg's own reason is in it, not logged beside it.
        const bool quietOpen = std::getenv("DT_LOG") == nullptr;
        if (quietOpen)
            platform::setLogLevel(platform::LogLevel::Off);
        auto source = media::openFrameSource(o.material, so, makeSourceProviders());
        if (quietOpen)
            platform::setLogLevel(platform::LogLevel::Warning);
        if (!source)
            return fail(kExitBadInput,
                        "cannot open material input '" + o.material + "': " + source.error().what);
        auto withMaterial =
            std::make_unique<touch::MaterialFrameProvider>(std::move(frames), std::move(*source));
        materialFrames = withMaterial.get();
        frames = std::move(withMaterial);
    }

    std::string readError;
    auto trajBytes = readInput(o.trajectory, kMaxTrajectoryBytes, "trajectory", readError);
    if (!trajBytes)
        return fail(kExitBadInput, readError);
    std::size_t line = 0;
    const std::string_view text(reinterpret_cast<const char *>(trajBytes->data()),
                                trajBytes->size());
    auto traj = parseTrajectoryCsv(text, &line);
    if (!traj)
        return fail(kExitBadInput,
                    o.trajectory + ":" + std::to_string(line) + ": " + traj.error().what);

    // A stop signal ends the replay (nothing is written) or, once the rows are made, lets the
    // output be written whole and renamed before the exit: never a temporary file left.
    gTouchStop.store(false);
    const platform::StopSignals signals(gTouchStop, true);
    touch::StoppableFrames stoppable(*frames, gTouchStop);
    auto rows = replay(stoppable, *traj, opt);
    if (gTouchStop.load() && !rows)
        return fail(kExitInterrupted,
                    std::string("interrupted by ") +
                        platform::stopSignalName(platform::StopSignals::caughtSignal()) +
                        "; nothing written");
    if (!rows)
        return fail(rows.error().code == Errc::Io ? kExitFailure : kExitBadInput,
                    rows.error().what);

    // A regular file or new path is written under a temporary name and renamed (never a partial
    // file); a device or a FIFO with a reader is written in place, never replaced.
    if (auto w = platform::writeOutputFile(o.out, formatForceLog(*rows)); !w) {
        char buf[256];
        return fail(w.error().code == Errc::Io ? kExitFailure : kExitBadInput,
                    "cannot write '" + o.out + "': " + w.error().format(buf, sizeof buf));
    }
    if (!o.quiet) {
        printTouchSummary(o, *rows, decoded != nullptr ? decoded->readingNote() : std::string());
        if (materialFrames != nullptr)
            std::fprintf(o.out == "/dev/stdout" || o.out == "-" ? stderr : stdout,
                         "touch: material: %lld frames read from '%s' (the last holds)\n",
                         materialFrames->framesRead(), o.material.c_str());
    }
    if (gTouchStop.load())
        return fail(kExitInterrupted,
                    std::string("interrupted by ") +
                        platform::stopSignalName(platform::StopSignals::caughtSignal()) + "; '" +
                        o.out + "' is complete");
    return kExitOk;
}

} // namespace

void registerTouchCommand(CLI::App &app, int &exitCode)
{
    addTableCommand<TouchOptions>(app, "touch", kAbout, kTouchRows, runTouch, exitCode);
}

} // namespace depthtouch::cli
