/// \file
/// \brief `depthtouch encode --color SRC --depth SRC -o OUT`: the sender. Reads color and depth
/// frames (image sequences, video files, anything FFmpeg reads; built-in CG scenes `synthetic:NAME`
/// and depth cameras `v4l2:DEVICE` through makeSourceProviders()), converts depth to nearness
/// (docs/architecture.md §3), optionally enhances it (paper §V.B) and writes color H.264 + depth
/// 4:0:0 into one MKV/MP4/MPEG-TS file or stream URL (docs/architecture.md §4), with an optional
/// material track (`--material SRC` or `--material-map labels.png --materials materials.toml`;
/// docs/materials.md). The pipeline is media::encodeStreams().
///
/// Bad input (missing, unreadable or silent source, no video stream, nonsense options, an output
/// path that is a directory or in a missing folder) prints one error line and exits 2 without
/// leaving an output file; a write of the output that fails (lost output) exits 1. SIGINT, SIGTERM,
/// SIGHUP, SIGQUIT, SIGUSR1 and SIGXFSZ (stop_signals.h) stop reading; the encoders are flushed and
/// the trailer written, so the file is playable; exit code 130. Progress (frames, fps, ETA) is
/// drawn on stderr only when stderr is a terminal.

#include <atomic>
#include <cerrno>
#include <cstring>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>

#include <unistd.h>

#include "commands.h"
#include "encode_inputs.h"
#include "encode_settings.h"
#include "option_cli.h"
#include "output_paths.h"
#include "source_providers.h"
#include "depthtouch/media/encode_job.h"
#include "depthtouch/media/encode_progress.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/material_map.h"
#include "depthtouch/media/named_source.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/stop_signals.h"
#include "depthtouch/receiver/stream_roles.h"

namespace depthtouch::cli {

namespace {

std::atomic<bool> gStop{false};

int fail(int code, const std::string &message)
{
    std::fprintf(stderr, "depthtouch encode: %s\n", message.c_str());
    return code;
}

std::string describe(const Error &e)
{
    char buf[256];
    return e.format(buf, sizeof buf);
}

/// How one input is opened: its role ("color" or "depth"), spec and forced demuxer settings.
struct InputSpec {
    const char *role;
    const std::string &spec;
    const std::string &format;
    const std::string &videoSize;
    const std::string &pixFmt;
};

/// \return the streams of input \a spec by role as play finds them (identifyInputStreams()), for a
/// file opened without a forced demuxer (\a format empty); nullopt otherwise.
std::optional<InputStreams> identify(const std::string &spec, const std::string &format,
                                     receiver::SingleStream single)
{
    return format.empty() ? identifyInputStreams(spec, single) : std::nullopt;
}

/// Opens one input, the stream \a ids finds in its role (a DepthTouch file of any container gives
/// its color, depth or material stream; the depth stream with its depth tags as play reads them),
/// else the one titled as its role; on failure sets `error` to the one error line and returns
/// nullptr.
std::unique_ptr<media::NamedSource>
openInput(const EncodeCliOptions &o, const media::SourceProviders &providers, const InputSpec &in,
          const std::optional<InputStreams> &ids, std::string &error)
{
    const std::string role = in.role;
    media::SourceOptions so;
    so.fps = o.fps;
    so.format = in.format;
    so.videoSize = in.videoSize;
    so.pixelFormat = in.pixFmt;
    so.loop = o.loop;
    so.streamTitle = role;
    if (ids) {
        so.streamIndex = ids->streamOf(role);
        if (role == "depth")
            so.tags = ids->depthTags();
    }
    auto s = media::openFrameSource(in.spec, so, providers);
    if (!s) {
        error = "cannot open " + role + " input '" + in.spec + "': " + describe(s.error());
        return nullptr;
    }
    return std::make_unique<media::NamedSource>(role, in.spec, std::move(*s));
}

/// Opens the material input of --material or --material-map (none without them); on failure
/// sets `error` and returns nullptr.
std::unique_ptr<media::NamedSource>
openMaterial(const EncodeCliOptions &o, const media::SourceProviders &providers, std::string &error)
{
    if (!o.material.empty()) {
        static const std::string kNone;
        return openInput(o, providers, {"material", o.material, kNone, kNone, kNone},
                         identify(o.material, kNone, receiver::SingleStream::Auto), error);
    }
    auto map = media::openMaterialMap(o.materialMap, o.materials, o.fps, error);
    return map ? std::make_unique<media::NamedSource>("material", o.materialMap, std::move(map))
               : nullptr;
}

/// Opens the color input, then (if that opened) the depth input, each identified as play
/// identifies its streams (\a depthIds: the depth input's streams, nullopt for an input that is no
/// file read twice); on failure sets `error`.
void openInputs(const EncodeCliOptions &o, const media::SourceProviders &providers,
                std::unique_ptr<media::NamedSource> &color,
                std::unique_ptr<media::NamedSource> &depthSrc,
                std::optional<InputStreams> &depthIds, std::string &error)
{
    // A camera or display backend that fails to open logs why at Error level; the one error line
    // below carries the same reason, so the backends stay quiet while opening (unless DT_LOG).
    const bool quietOpen = std::getenv("DT_LOG") == nullptr;
    if (quietOpen)
        platform::setLogLevel(platform::LogLevel::Off);
    color =
        openInput(o, providers, {"color", o.color, o.colorFormat, o.colorVideoSize, o.colorPixFmt},
                  identify(o.color, o.colorFormat, receiver::SingleStream::Color), error);
    depthIds = identify(o.depth, o.depthFormat, receiver::SingleStream::Depth);
    depthSrc = color ? openInput(o, providers,
                                 {"depth", o.depth, o.depthFormat, o.depthVideoSize, o.depthPixFmt},
                                 depthIds, error)
                     : nullptr;
    if (quietOpen)
        platform::setLogLevel(platform::LogLevel::Error);
}

/// The exit code of a failed encode, after its one error line: the input that failed, else the
/// output (an I/O error: lost output) or the encoder.
int encodeFailure(const EncodeCliOptions &o, const media::NamedSource &color,
                  const media::NamedSource &depthSrc, const media::NamedSource *material,
                  const Error &error)
{
    if (color.failed())
        return fail(kExitBadInput, color.message());
    if (depthSrc.failed())
        return fail(kExitBadInput, depthSrc.message());
    if (material != nullptr && material->failed())
        return fail(kExitBadInput, material->message());
    const Errc code = error.code;
    const std::string what = describe(error);
    // The inputs read fine: an I/O error is the output's, which is lost (exit 1).
    if (code == Errc::Io && media::isOutputUrl(o.output))
        return fail(kExitFailure,
                    "the stream to '" + o.output +
                        "' was lost (the receiver left or the network failed): " + what);
    if (code == Errc::Io)
        return fail(kExitFailure, "cannot write '" + o.output + "': " + what);
    return fail(code == Errc::OutOfResources ? kExitFailure : kExitBadInput, what);
}

/// Prints the enhancement line of the summary.
void printEnhanceTotals(const media::EnhanceTotals &t)
{
    const double scale = 255.0 / t.levelsMax;
    std::printf(
        "enhance: %lld frames, points kept %lld of %lld pixels (%.2f %%); depth error "
        "mean %.3f, rms %.3f, max %.1f levels (8-bit scale); flat roughness %.3f -> "
        "%.3f; edge contrast %.1f -> %.1f\n",
        t.frames, t.points, t.pixels,
        t.pixels > 0 ? 100.0 * static_cast<double>(t.points) / static_cast<double>(t.pixels) : 0.0,
        t.meanAbsError * scale, t.rmsError * scale, t.maxAbsError * scale, t.roughnessInput * scale,
        t.roughnessOutput * scale, t.edgeContrastInput * scale, t.edgeContrastOutput * scale);
}

/// Farthest depth a depth camera measures, m (time-of-flight and stereo sensors stop at about
/// 10 m): a far plane beyond it is worth a warning.
constexpr double kFarthestSensorRange = 12.0;
/// Median depth beyond which the whole scene, not a tail of it, is farther than cameras see, m: the
/// numbers then point to a wrong --depth-scale (TUM's 0.2 mm units read as mm put a room's median
/// at 5x, 10..15 m; metres read as mm at 1000x).
constexpr double kFarthestMedian = 0.5 * kFarthestSensorRange;

/// Says on stdout what a robust range left out (a sparse far tail) and on stderr when its far
/// plane is beyond what cameras measure: the scale alone is blamed only when the median is beyond
/// kFarthestMedian too; otherwise a dense far tail and the scale are both named, as the numbers
/// cannot tell them apart (a near scene at 5x reads like a room with a far background).
void reportRobustRange(const media::EncodeOptions &eo, const media::EncodeSummary &s)
{
    if (!s.metric || eo.range || !s.rangeEstimate)
        return;
    const depth::RangeEstimate &e = *s.rangeEstimate;
    if (e.tailCut)
        std::printf("depth: far tail left out of the range: %.1f %% of the valid samples read "
                    "%.4g..%.4g m (99 %% quantile %.4g m), under %.1f %% of them per 10 %% step of "
                    "depth: sparse far outliers (as active-stereo cameras give), coded at the far "
                    "plane (--far keeps them)\n",
                    100.0 * e.beyondFraction, s.range.farM, e.maxM, e.quantileFarM,
                    100.0 * depth::kTailDensity);
    if (s.range.farM <= kFarthestSensorRange)
        return;
    if (e.medianM > kFarthestMedian)
        std::fprintf(stderr,
                     "depthtouch encode: warning: the depth reaches %.4g m (median %.4g m), "
                     "beyond what depth cameras measure: check --depth-scale (%g m per unit now; "
                     "TUM RGB-D: 0.0002)\n",
                     s.range.farM, e.medianM, eo.raw.metresPerUnit);
    else
        std::fprintf(stderr,
                     "depthtouch encode: warning: the far plane is %.4g m, beyond what depth "
                     "cameras measure, while the median depth is %.4g m: a far tail too dense to "
                     "leave out (at least %.1f %% of the valid samples per 10 %% step of depth: "
                     "an active-stereo camera's noise on distant or low-texture surfaces, or a far "
                     "background), or a wrong --depth-scale (%g m per unit now); --far sets the "
                     "plane\n",
                     s.range.farM, e.medianM, 100.0 * depth::kTailDensity, eo.raw.metresPerUnit);
}

/// Prints the summary of a finished encode; returns its exit code (kExitInterrupted after a
/// stop signal, with a line on stderr). \a carried: the material track came from the depth
/// input (a DepthTouch file).
int reportEncode(const EncodeCliOptions &o, const media::EncodeOptions &eo,
                 const media::NamedSource &color, const media::EncodeSummary &s, bool carried)
{
    const bool ladder = !s.renditions.empty();
    const int w =
        ladder ? s.renditions.front().width : (eo.width > 0 ? eo.width : color.info().width);
    const int h =
        ladder ? s.renditions.front().height : (eo.height > 0 ? eo.height : color.info().height);
    std::printf("encoded %lld frame pairs %dx%d (%.2f s of video) in %.2f s: %.1f fps; color %.1f "
                "kB, depth %.1f kB (%d-bit); ended by %s\n",
                s.frames, w, h, s.duration, s.elapsed,
                s.elapsed > 0.0 ? static_cast<double>(s.frames) / s.elapsed : 0.0,
                static_cast<double>(s.colorBytes) / 1000.0,
                static_cast<double>(s.depthBytes) / 1000.0, s.depthBits, s.endedBy.c_str());
    if (s.metric && eo.fillHoles)
        std::printf("depth: metric, near %.4g m, far %.4g m (%s), %s mapping; %lld invalid samples "
                    "filled; %lld frames without valid depth repeated\n",
                    s.range.nearM, s.range.farM, eo.range ? "given" : "robust range of the data",
                    depth::mappingName(s.mapping), s.filledSamples, s.repeatedFrames);
    else if (eo.depthInputHoleBelow && s.holeSamples > 0)
        std::printf("depth: holes of '%s' kept, %.1f %% of the samples (%lld), coded below "
                    "depth_occupancy=%u\n",
                    o.depth.c_str(),
                    100.0 * static_cast<double>(s.holeSamples) /
                        static_cast<double>(s.depthSamples),
                    s.holeSamples, s.depthOccupancy);
    else if (eo.depthInputHoleBelow && eo.fillHoles && s.filledSamples > 0)
        std::printf("depth: %lld hole samples of '%s' filled (--fill-holes)\n", s.filledSamples,
                    o.depth.c_str());
    else if (s.metric)
        std::printf("depth: metric, near %.4g m, far %.4g m (%s), %s mapping; holes %.1f %% of the "
                    "samples (%lld), coded below depth_occupancy=%u\n",
                    s.range.nearM, s.range.farM, eo.range ? "given" : "robust range of the data",
                    depth::mappingName(s.mapping),
                    s.depthSamples > 0 ? 100.0 * static_cast<double>(s.holeSamples) /
                                             static_cast<double>(s.depthSamples)
                                       : 0.0,
                    s.holeSamples, s.depthOccupancy);
    reportRobustRange(eo, s);
    if (s.enhance)
        printEnhanceTotals(*s.enhance);
    if (!o.materialMap.empty()) // one still, coded once and used for every frame
        std::printf("material: %.1f kB lossless (the label map '%s', one still for every frame)\n",
                    static_cast<double>(s.materialBytes) / 1000.0, o.materialMap.c_str());
    else if (carried)
        std::printf("material: %.1f kB lossless (the material track carried over from '%s', %lld "
                    "frames)\n",
                    static_cast<double>(s.materialBytes) / 1000.0, o.depth.c_str(),
                    s.materialFrames);
    else if (!o.material.empty())
        std::printf("material: %.1f kB lossless (%lld frames read from '%s', the last held)\n",
                    static_cast<double>(s.materialBytes) / 1000.0, s.materialFrames,
                    o.material.c_str());
    if (!s.audio.empty())
        std::printf("audio: %s, %.1f kB\n", s.audio.c_str(),
                    static_cast<double>(s.audioBytes) / 1000.0);
    for (const media::RenditionSummary &r : s.renditions)
        std::printf("rendition %dx%d: %s, peak %.0f kbit/s, average %.0f kbit/s\n", r.width,
                    r.height, r.playlist.c_str(), static_cast<double>(r.peakBitRate) / 1000.0,
                    static_cast<double>(r.averageBitRate) / 1000.0);
    if (s.interrupted) {
        std::fprintf(stderr,
                     "depthtouch encode: interrupted by %s; '%s' holds the %lld frame pairs "
                     "encoded and is complete\n",
                     platform::stopSignalName(platform::StopSignals::caughtSignal()),
                     o.output.c_str(), s.frames);
        return kExitInterrupted;
    }
    return kExitOk;
}

/// Where --progress writes: stdout or stderr (pipe:1, pipe:2), or a file it opened.
class ProgressOut {
public:
    ProgressOut() = default;
    ProgressOut(const ProgressOut &) = delete;
    ProgressOut &operator=(const ProgressOut &) = delete;
    ~ProgressOut()
    {
        if (owned_)
            std::fclose(out_);
    }
    void set(std::FILE *out, bool owned)
    {
        out_ = out;
        owned_ = owned;
    }
    [[nodiscard]] std::FILE *get() const noexcept { return out_; }

private:
    std::FILE *out_ = nullptr;
    bool owned_ = false;
};

/// Opens --progress's target before any input is read (ffmpeg's pipe:1 and pipe:2, or a file the
/// output rules allow: not an input, a folder that takes files). \return kExitOk, or the exit
/// code after the error line.
int openProgress(const EncodeCliOptions &o, ProgressOut &out)
{
    if (o.progress.empty())
        return kExitOk;
    if (o.progress == "pipe:1" || o.progress == "pipe:") {
        out.set(stdout, false);
        return kExitOk;
    }
    if (o.progress == "pipe:2") {
        out.set(stderr, false);
        return kExitOk;
    }
    if (auto p = platform::planOutput(o.progress); !p)
        return fail(kExitBadInput, "cannot write '" + o.progress + "': it " + p.error().what);
    const platform::OutputPathCheck same = platform::checkDistinctPaths(
        {{"--color", o.color}, {"--depth", o.depth}, {"--audio", o.audio}},
        {{"-o", o.output}, {"--progress", o.progress}});
    if (same.exitCode != kExitOk)
        return fail(same.exitCode, same.message);
    std::FILE *f = std::fopen(o.progress.c_str(), "w");
    if (f == nullptr)
        return fail(kExitFailure, "cannot write '" + o.progress + "': " + std::strerror(errno));
    out.set(f, true);
    return kExitOk;
}

int runEncode(const EncodeCliOptions &o)
{
    // One error line on bad input: our log stays at errors unless the user asked with DT_LOG.
    if (std::getenv("DT_LOG") == nullptr)
        platform::setLogLevel(platform::LogLevel::Error);

    media::EncodeOptions eo;
    if (const int rc = encodeOptionsFrom(o, eo); rc != kExitOk)
        return rc;
    if (!o.material.empty() && !o.materialMap.empty())
        return fail(kExitBadInput, "--material and --material-map exclude each other");
    if (o.materialMap.empty() != o.materials.empty())
        return fail(kExitBadInput, "--material-map and --materials go together");

    ProgressOut progressOut;
    if (const int rc = openProgress(o, progressOut); rc != kExitOk)
        return rc;

    // One set of providers for both inputs: `synthetic:NAME` color and depth share one renderer,
    // `v4l2:DEVICE` color and depth one camera.
    const media::SourceProviders providers = makeSourceProviders();
    std::unique_ptr<media::NamedSource> color;
    std::unique_ptr<media::NamedSource> depthSrc;
    std::optional<InputStreams> depthIds;
    std::string error;
    openInputs(o, providers, color, depthSrc, depthIds, error);
    if (!color || !depthSrc)
        return fail(kExitBadInput, error);
    // A DepthTouch file as the depth input keeps its holes (its threshold as play reads it, for
    // frames read as encode reads them: 16-bit for a deep input, else 8-bit) and its material
    // track (unless --material or --material-map replace it).
    const bool depthTouch = depthIds && depthIds->depthTouch();
    if (depthTouch)
        eo.depthInputHoleBelow = receiver::depthHoleBelow(
            depthIds->depthStream, depthSrc->info().nativeFormat == media::PixelFormat::Gray16
                                       ? hal::PixelFormat::Gray16
                                       : hal::PixelFormat::Gray8);
    else if (depthSrc->info().tag("depth_occupancy") != nullptr && !o.fillHoles)
        std::fprintf(stderr,
                     "depthtouch encode: warning: the holes of depth input '%s' are not "
                     "kept (not a file encode can read twice): they become depth\n",
                     o.depth.c_str());
    const bool carried =
        depthTouch && depthIds->material >= 0 && o.material.empty() && o.materialMap.empty();
    std::unique_ptr<media::NamedSource> material;
    if (carried) {
        static const std::string kNone;
        if (material = openInput(o, providers, {"material", o.depth, kNone, kNone, kNone}, depthIds,
                                 error);
            !material)
            return fail(kExitBadInput, error);
    } else if (!o.material.empty() || !o.materialMap.empty()) {
        if (material = openMaterial(o, providers, error); !material)
            return fail(kExitBadInput, error);
    }

    media::ProgressLine progress(::isatty(STDERR_FILENO) == 1);
    media::ProgressReport report(progressOut.get());
    media::EncodeCallbacks callbacks;
    callbacks.progress = [&progress, &report](const media::EncodeProgress &p) {
        progress.update(p);
        report.update(p);
    };
    callbacks.warning = [&progress](const std::string &w) {
        progress.finish();
        std::fprintf(stderr, "depthtouch encode: warning: %s\n", w.c_str());
    };

    gStop.store(false);
    Result<media::EncodeSummary> summary = [&] {
        // Without SA_RESTART: a read blocked on an input returns, and the flag is seen.
        platform::StopSignals signals(gStop, false);
        return media::encodeStreams(*color, *depthSrc, material.get(), eo, &gStop, callbacks);
    }();
    progress.finish();
    if (!summary) {
        report.finish(media::EncodeProgress{});
        return encodeFailure(o, *color, *depthSrc, material.get(), summary.error());
    }
    const int rc = reportEncode(o, eo, *color, *summary, carried);
    const media::EncodeProgress last{summary->frames, 0, summary->elapsed, summary->duration};
    if (!report.finish(last) && rc == kExitOk)
        return fail(kExitFailure, "cannot write the progress to '" + o.progress + "'");
    return rc;
}

/// `--frames`: a whole number >= 0 (a CLI11 check, so that "1.5" or "-1" is refused at once).
std::string wholeFrameCount(std::string &v)
{
    char *end = nullptr;
    errno = 0;
    const long long n = std::strtoll(v.c_str(), &end, 10);
    const bool whole = end != v.c_str() && *end == '\0' && errno == 0 && n >= 0;
    return whole ? std::string() : "must be a whole number >= 0 (0: all), not " + v;
}

/// The options of `encode`, in `--help` order.
const OptionRow<EncodeCliOptions> kEncodeRows[] = {
    {"color",
     &EncodeCliOptions::color,
     "Color input: image sequence (frame-%06d.color.jpg, 'd/*.png'), video file, URL, "
     "v4l2:/dev/videoN[,color=/dev/videoM], synthetic:NAME[,size=WxH][,fps=F][,frames=N] (NAME: "
     "head, spheres, cut; default 720x486, --fps, 4 s; frames=0: endless)",
     {},
     kRequired},
    {"depth",
     &EncodeCliOptions::depth,
     "Depth input: 8-bit nearness or 16-bit metric depth (image sequence, video, ...); the depth "
     "of a v4l2: or synthetic: spec (give --color the same spec)",
     {},
     kRequired},
    {"output",
     &EncodeCliOptions::output,
     "Output file (.mkv, .mp4, .ts; .m3u8: HLS playlist and segments) or URL (udp://, srt://)",
     {},
     kRequired,
     'o'},
    {"overwrite",
     &EncodeCliOptions::overwrite,
     "Replace an output file that exists (ffmpeg's -y; without it encode refuses)",
     {},
     0,
     'y'},
    {"no-overwrite",
     &EncodeCliOptions::noOverwrite,
     "Never replace an output file that exists (ffmpeg's -n; the default)",
     {},
     0,
     'n'},
    {"progress", &EncodeCliOptions::progress,
     "Write progress as key=value blocks to a file, pipe:1 or pipe:2 (ffmpeg's -progress)"},
    {"format", &EncodeCliOptions::format,
     "Container: mkv | mp4 | ts | hls (default: by extension; mkv for files, ts for URLs)"},
    {"fps", &EncodeCliOptions::fps,
     "Frame rate of image sequences and raw inputs (frames/s, 0.1..1000)"},
    {"crf", &EncodeCliOptions::crf, "Color x264 constant rate factor 0..51"},
    {"preset", &EncodeCliOptions::preset, "x264 preset (ultrafast ... veryslow)"},
    {"depth-crf", &EncodeCliOptions::depthCrf, "Depth x264 constant rate factor 0..51 (lossy)"},
    {"gop",
     &EncodeCliOptions::gop,
     "Frames between key frames, the same pictures in every stream (ffmpeg -g; no scene-cut key "
     "frames); each is a tune-in point (0: 2 s for URLs, --loop and HLS, x264's 250 otherwise)",
     {},
     0,
     'g'},
    {"bitrate", &EncodeCliOptions::bitrate,
     "Color average bit rate in place of --crf (ffmpeg -b:v; bits/s: 500k, 4M)"},
    {"maxrate", &EncodeCliOptions::maxrate,
     "Color peak bit rate, with --bufsize (VBV; = --bitrate for constant bit rate)"},
    {"bufsize", &EncodeCliOptions::bufsize, "Color VBV buffer size (bits: 2M)"},
    {"depth-bitrate", &EncodeCliOptions::depthBitrate,
     "Depth average bit rate in place of --depth-crf (lossy depth)"},
    {"depth-maxrate", &EncodeCliOptions::depthMaxrate, "Depth peak bit rate, with --depth-bufsize"},
    {"depth-bufsize", &EncodeCliOptions::depthBufsize, "Depth VBV buffer size (bits)"},
    {"muxrate", &EncodeCliOptions::muxrate,
     "Constant MPEG-TS mux rate, null-packet padded (ffmpeg -muxrate; bits/s; TS outputs only)"},
    {"depth-lossless", &EncodeCliOptions::depthLossless,
     "Lossless depth (x264 qp 0, High 4:4:4 Predictive)"},
    {"depth-codec", &EncodeCliOptions::depthCodec,
     "Depth codec: h264 (4:0:0, 8 or 10 bits) | hevc (Main10 4:2:0, depth in luma, neutral "
     "chroma: what set-top hardware decoders take) | ffv1 (16-bit lossless, MKV); default h264, "
     "ffv1 with --depth-bits 16; docs/making-content.md compares them",
     oneOf("h264 hevc ffv1"), kHideDefault},
    {"depth-bits",
     &EncodeCliOptions::depthBits,
     "Depth samples: 8 or 10 (h264), 10 (hevc), 16 (ffv1); default: the codec's (h264 8)",
     {},
     kHideDefault},
    {"size", &EncodeCliOptions::size, "Output grid WxH (default: the color size)"},
    {"renditions", &EncodeCliOptions::renditions,
     "HLS rendition ladder: heights in pixels, tallest first (1080,720,480); each rendition "
     "carries every stream; -o names their multivariant playlist"},
    {"threads", &EncodeCliOptions::threads, "Encoder threads per stream (0: automatic)"},
    {"loop", &EncodeCliOptions::loop,
     "Loop the inputs forever: image sequences, pictures, video files (a live source; stop with "
     "--frames, --duration or Ctrl-C)"},
    {"realtime", &EncodeCliOptions::realtime,
     "Write at the media rate, as a live sender: auto (for URL outputs and --loop) | on | off",
     oneOf("auto on off")},
    {"frames",
     &EncodeCliOptions::frames,
     "Encode at most N frame pairs (0: all)",
     {},
     kHideDefault},
    {"duration", &EncodeCliOptions::duration, "Encode at most this many seconds (0: all)"},
    {"depth-scale", &EncodeCliOptions::depthScale,
     "Metres per unit of 16-bit metric depth (0.001: mm; TUM: 0.0002)"},
    {"depth-saturation", &EncodeCliOptions::depthSaturation,
     "16-bit depth values >= this are invalid (as 0 is)"},
    {"fill-holes", &EncodeCliOptions::fillHoles,
     "Fill invalid metric depth by push-pull interpolation instead of keeping it as holes "
     "(untouchable, not drawn; tag depth_occupancy)"},
    {"near",
     &EncodeCliOptions::nearM,
     "Near plane (m); default: robust range of the data",
     {},
     kHideDefault},
    {"far",
     &EncodeCliOptions::farM,
     "Far plane (m); default: robust range of the data",
     {},
     kHideDefault},
    {"depth-mapping", &EncodeCliOptions::depthMapping, "Metric → nearness: inverse_z | linear"},
    {"enhance", &EncodeCliOptions::enhance,
     "Depth enhancement (paper V.B): median, adaptive points, Delaunay, smoothing"},
    {"enhance-tolerance", &EncodeCliOptions::enhanceTolerance,
     "Enhancement error tolerance (nearness levels, 8-bit scale)"},
    {"color-format", &EncodeCliOptions::colorFormat, "Force the color demuxer (e.g. rawvideo)"},
    {"color-video-size", &EncodeCliOptions::colorVideoSize, "Raw color frame size WxH"},
    {"color-pix-fmt", &EncodeCliOptions::colorPixFmt, "Raw color pixel format (e.g. rgb24)"},
    {"depth-format", &EncodeCliOptions::depthFormat, "Force the depth demuxer (e.g. rawvideo)"},
    {"depth-video-size", &EncodeCliOptions::depthVideoSize, "Raw depth frame size WxH"},
    {"depth-pix-fmt", &EncodeCliOptions::depthPixFmt, "Raw depth pixel format (e.g. gray16le)"},
    {"material", &EncodeCliOptions::material,
     "Material codes (RGB: stiffness scale x64, static and dynamic friction x100; "
     "docs/materials.md): a still, an image sequence or a video; frame k goes with depth frame k, "
     "the last one holds"},
    {"material-map", &EncodeCliOptions::materialMap,
     "Label image (PNG; each colour one material of --materials), used for every frame"},
    {"materials", &EncodeCliOptions::materials,
     "TOML table of the --material-map labels: [name] label = \"#rrggbb\", preset, "
     "stiffness_scale, static_friction, dynamic_friction"},
    {"audio", &EncodeCliOptions::audio,
     "Sound from this file's first audio stream (default: the color input's, when it is a file; "
     "copied when the container carries its codec, else coded as AAC)"},
    {"no-audio", &EncodeCliOptions::noAudio, "Leave the sound out"},
};

} // namespace

void registerEncodeCommand(CLI::App &app, int &exitCode)
{
    CLI::App *cmd = addTableCommand<EncodeCliOptions>(
        app, "encode", "Encode color + depth into one file or stream (H.264 color, 4:0:0 depth)",
        kEncodeRows, runEncode, exitCode);
    // No description: --help shows "INT" and the row's own help says what it must be.
    addValueCheck(*cmd, "--frames", wholeFrameCount);
}

} // namespace depthtouch::cli
