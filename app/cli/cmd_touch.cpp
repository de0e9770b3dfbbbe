/// \file
/// \brief `depthtouch touch DEPTH --trajectory traj.csv --out forces.csv`: replays a HIP trajectory
/// against a depth video at the haptic rate and writes the force log CSV (docs/architecture.md §4),
/// deterministically. Bad input prints one error line and exits 2 without leaving an output file.
///
/// DEPTH is a raw gray file (with --size) or anything FFmpeg reads: a video file, a URL or an image
/// sequence pattern (`frame-%06d.depth.png`, frame rate --fps). The depth stream (or the only
/// stream, its luma when it is YUV) is decoded through the `ffmpeg` media source and decoder
/// backends; frame times come from the PTS. 16-bit samples of a depth stream (titled depth, or
/// carrying depth metadata) are nearness unless --near/--far are given: then they are metric depth
/// (--depth-scale metres per unit, 0 = invalid), converted to 16-bit nearness
/// (docs/architecture.md §3) with the holes filled. The 16-bit samples of an input that says
/// nothing of depth (an image sequence from a depth camera) are metric depth: without --near/--far
/// its planes are the robust range of the first frame (as `encode` takes it), named in the summary.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <memory>
#include <new>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/geometric.hpp>

#include "commands.h"
#include "option_cli.h"
#include "depthtouch/depth/conversion.h"
#include "depthtouch/depth/fill.h"
#include "depthtouch/drivers/backends.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/haptics/replay.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/log.h"

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
    std::string reengage = "release";
    double fingerRadius = std::nan(""); ///< m; NaN: 0.015 x box width
    double staticFriction = 0.0;        ///< μs of the friction cone
    double dynamicFriction = 0.0;       ///< μd
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
    {"stiffness", &TouchOptions::stiffness, "Spring stiffness k (N/m, up to 100000)"},
    {"damping", &TouchOptions::damping, "Damping b (N·s/m, 0..1000)"},
    {"max-force", &TouchOptions::maxForce, "Device maximum force (N, up to 1000)"},
    {"box-width", &TouchOptions::boxWidth, "Scene box width (m)"},
    {"box-depth", &TouchOptions::boxDepth, "Scene box depth (m)"},
    {"method", &TouchOptions::method, "finger | modified | proxy-graph | mesh-bvh"},
    {"no-correction", &TouchOptions::noCorrection, "Turn off fix (a), collision correction"},
    {"no-interpolation", &TouchOptions::noInterpolation, "Turn off fix (b), surface interpolation"},
    {"no-safety", &TouchOptions::noSafety, "Turn off fix (c), force-jump safety"},
    {"max-force-step", &TouchOptions::maxForceStep,
     "Force change per update that trips safety (N); the default 2 N never trips while stroking "
     "smooth surfaces at 1 m/s (k=800: <= 0.8 N/update) and always trips at a cut of half the box "
     "depth (16 N)"},
    {"reengage", &TouchOptions::reengage, "After a trip: release | ramp"},
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
};

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

/// \brief Depth frames decoded by the `ffmpeg` backends, lazily and in order (the replay asks for
/// increasing indices and holds two frames): keeps the last few converted frames only.
class DecodedFrameProvider final : public haptics::FrameProvider {
public:
    struct Metric {
        depth::ConvertOptions convert;
    };

    /// Opens \a url; \a error receives a one-line message on failure. \a metric: the given
    /// planes (--near/--far), or nullopt; \a unplanned: the conversion used, with its range taken
    /// from the first frame, when \a metric is nullopt and the input's 16-bit samples are metric
    /// (it says nothing of depth).
    bool open(const std::string &url, double fps, std::optional<Metric> metric,
              const Metric &unplanned, std::string &error)
    {
        metric_ = std::move(metric);
        fps_ = fps;
        fpsOption_ = "fps=" + std::to_string(fps);
        hal::BackendConfig cfg;
        cfg.options = hal::OptionList(fpsOption_);
        auto src = drivers::createMediaSource("ffmpeg", cfg);
        if (!src) {
            error = std::string("no FFmpeg media source in this build: ") + src.error().what;
            return false;
        }
        source_ = std::move(*src);
        // The frames are counted first, then decoded: a FIFO cannot be read twice (and opening one
        // would wait for a writer).
        if (const auto kind = platform::pathKind(url.c_str());
            kind == platform::PathKind::Fifo || kind == platform::PathKind::Directory ||
            kind == platform::PathKind::Socket) {
            error = "cannot read depth input '" + url + "': it is " + platform::pathKindName(kind) +
                    " (touch reads the depth video twice: give a file)";
            return false;
        }
        if (auto r = source_->open(url.c_str()); !r) {
            error = "cannot read depth input '" + url + "': " + r.error().what + " (" +
                    errcName(r.error().code) + ")";
            return false;
        }
        if (!source_->info().seekable && url.find("://") == std::string::npos) {
            // The frames are counted first, then decoded: a pipe cannot be read twice.
            error =
                "depth input '" + url + "' cannot be read twice (a pipe): save it to a file first";
            return false;
        }
        const auto &streams = source_->info().streams;
        for (const hal::StreamInfo &s : streams)
            if (s.kind == hal::StreamKind::Depth && stream_ < 0)
                stream_ = s.index;
        if (stream_ < 0 && streams.size() == 1)
            stream_ = streams[0].index;
        if (stream_ < 0) {
            error = "no depth stream in '" + url + "' (several streams, none titled depth)";
            return false;
        }
        const hal::StreamInfo &si = streams[static_cast<std::size_t>(stream_)];
        // Nothing says depth (no title, no metadata: a depth camera's image sequence): 16-bit
        // samples are its metric depth.
        if (!metric_ && si.format == hal::PixelFormat::Gray16 && si.title.empty() &&
            si.depth.nearMetres == 0.0)
            metric_ = unplanned;
        config_ = hal::StreamConfig::fromStream(si);
        config_.kind = hal::StreamKind::Depth;
        if (config_.format != hal::PixelFormat::Gray8 &&
            config_.format != hal::PixelFormat::Gray10 &&
            config_.format != hal::PixelFormat::Gray16)
            config_.format = hal::PixelFormat::Gray8; // luma of a YUV/RGB stream, as is
        if (metric_ && config_.format == hal::PixelFormat::Gray8) {
            error = "--near/--far convert 16-bit metric depth; '" + url + "' has 8-bit samples";
            return false;
        }
        // Count the frames (demux only) so the replay knows the last one.
        for (;;) {
            auto p = source_->readPacket();
            if (!p) {
                if (p.error().code != Errc::EndOfStream) {
                    error = "cannot read depth input '" + url + "': " + p.error().what;
                    return false;
                }
                break;
            }
            if (p->streamIndex == stream_)
                ++count_;
        }
        if (count_ == 0) {
            error = "depth input '" + url + "' has no frames";
            return false;
        }
        if (auto r = source_->seek(hal::Pts{0}); !r) {
            source_->close();
            if (auto o = source_->open(url.c_str()); !o) {
                error = "cannot reopen depth input '" + url + "'";
                return false;
            }
        }
        auto dec = drivers::createVideoDecoder("ffmpeg", hal::BackendConfig{});
        if (!dec) {
            error = std::string("no FFmpeg video decoder: ") + dec.error().what;
            return false;
        }
        decoder_ = std::move(*dec);
        if (auto r = decoder_->configure(config_); !r) {
            error = "cannot decode depth input '" + url + "': " + r.error().what;
            return false;
        }
        url_ = url;
        return true;
    }

    [[nodiscard]] std::size_t frameCount() const noexcept override { return count_; }

    /// \return how the depth was read when the input said nothing of depth and no planes were
    /// given ("metric depth, near … m, far … m, the robust range of the first frame"); empty
    /// otherwise.
    [[nodiscard]] std::string readingNote() const
    {
        if (!rangeTaken_ || !metric_ || !metric_->convert.range)
            return {};
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "16-bit samples read as metric depth (%g m per unit), near %.4g m, far "
                      "%.4g m: the robust range of the first frame (--near/--far set them)",
                      metric_->convert.raw.metresPerUnit, metric_->convert.range->nearM,
                      metric_->convert.range->farM);
        return buf;
    }

    Result<haptics::DepthFrameView> frame(std::size_t i) noexcept override
    {
        try {
            while (decoded_ <= i) {
                auto r = decodeNext();
                if (!r)
                    return unexpected(r.error());
            }
            const std::size_t first = decoded_ - frames_.size();
            if (i < first)
                return unexpected(Errc::InvalidArgument, "depth frame requested out of order");
            const Stored &f = frames_[i - first];
            haptics::DepthFrameView v;
            v.data = f.bytes.data();
            v.width = config_.width;
            v.height = config_.height;
            v.format = f.format;
            v.strideBytes =
                static_cast<std::size_t>(config_.width) * haptics::bytesPerSample(f.format);
            v.pts = f.pts;
            return v;
        } catch (const std::bad_alloc &) {
            return unexpected(Errc::OutOfResources, "out of memory decoding the depth video");
        }
    }

private:
    struct Stored {
        std::vector<std::uint8_t> bytes;
        haptics::SampleFormat format = haptics::SampleFormat::Gray8;
        double pts = 0.0;
    };

    Result<void> decodeNext()
    {
        const platform::TimePoint now = platform::SteadyClock::instance().now();
        for (int guard = 0; guard < 1'000'000; ++guard) {
            auto f = decoder_->dequeueFrame(now);
            if (f)
                return store(**f);
            const Errc e = f.error().code;
            if (e == Errc::EndOfStream)
                return unexpected(Errc::InvalidArgument,
                                  "the depth video ended early (damaged or truncated)");
            if (e == Errc::Io)
                return unexpected(Errc::InvalidArgument, "a depth frame failed to decode");
            if (e != Errc::Timeout && e != Errc::InvalidState)
                return unexpected(f.error());
            // Needs input.
            if (eos_)
                continue;
            auto p = source_->readPacket();
            if (!p) {
                if (p.error().code != Errc::EndOfStream)
                    return unexpected(Errc::InvalidArgument, "cannot read the depth input");
                eos_ = true;
                DT_TRY(decoder_->queuePacket(hal::Packet::endOfStream(stream_)));
                continue;
            }
            if (p->streamIndex != stream_)
                continue;
            if (auto q = decoder_->queuePacket(*p); !q)
                return unexpected(Errc::InvalidArgument, "the decoder refused a depth packet");
        }
        return unexpected(Errc::InvalidArgument, "the depth decoder makes no progress");
    }

    Result<void> store(const hal::Frame &frame)
    {
        Stored s;
        s.pts = frame.pts == hal::kNoPts ? static_cast<double>(decoded_) / fps_
                                         : std::chrono::duration<double>(frame.pts).count();
        const hal::ImageView &img = frame.image;
        const int w = img.width;
        const int h = img.height;
        if (img.format == hal::PixelFormat::Gray8) {
            s.format = haptics::SampleFormat::Gray8;
            s.bytes.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
            for (int y = 0; y < h; ++y)
                std::memcpy(s.bytes.data() +
                                static_cast<std::size_t>(y) * static_cast<std::size_t>(w),
                            img.row(0, y), static_cast<std::size_t>(w));
        } else {
            depth::Plane<std::uint16_t> raw(w, h);
            const double scale =
                img.format == hal::PixelFormat::Gray10 && !metric_ ? 65535.0 / 1023.0 : 1.0;
            for (int y = 0; y < h; ++y) {
                const std::uint8_t *row = img.row(0, y);
                for (int x = 0; x < w; ++x) {
                    std::uint16_t v;
                    std::memcpy(&v, row + 2 * x, sizeof v);
                    raw.at(x, y) = scale == 1.0 ? v
                                                : static_cast<std::uint16_t>(
                                                      std::lround(static_cast<double>(v) * scale));
                }
            }
            if (metric_) {
                if (!metric_->convert.range) {
                    auto r =
                        depth::robustRange(raw, metric_->convert.raw, metric_->convert.lowFraction,
                                           metric_->convert.highFraction);
                    if (!r)
                        return unexpected(Errc::InvalidArgument,
                                          "the first depth frame has no valid metric sample");
                    metric_->convert.range = *r;
                    rangeTaken_ = true;
                }
                auto n = depth::metricToNearness(raw, metric_->convert);
                if (!n)
                    return unexpected(n.error());
                if (n->invalidCount > 0 && n->invalidCount < n->valid.size()) {
                    if (auto filled = depth::fillInvalid(n->nearness, n->valid); !filled)
                        return unexpected(filled.error());
                }
                raw = depth::quantize(n->nearness, metric_->convert.vmax);
            }
            s.format = haptics::SampleFormat::Gray16;
            s.bytes.resize(raw.size() * 2u);
            std::memcpy(s.bytes.data(), raw.samples.data(), s.bytes.size());
        }
        frames_.push_back(std::move(s));
        if (frames_.size() > 4)
            frames_.pop_front();
        ++decoded_;
        return ok();
    }

    std::unique_ptr<hal::MediaSource> source_;
    std::unique_ptr<hal::VideoDecoder> decoder_;
    hal::StreamConfig config_;
    std::optional<Metric> metric_;
    std::string fpsOption_;
    std::string url_;
    double fps_ = 30.0;
    int stream_ = -1;
    std::size_t count_ = 0;
    std::size_t decoded_ = 0;
    bool eos_ = false;
    bool rangeTaken_ = false; ///< The planes are the first frame's robust range.
    std::deque<Stored> frames_;
};

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
                     DecodedFrameProvider *&decoded)
{
    if (!(o.fps > 0.0) || o.fps > 10'000.0)
        return fail(kExitBadInput, "--fps must be in (0, 10000]");
    if (!(o.depthScale > 0.0))
        return fail(kExitBadInput, "--depth-scale must be positive");
    auto mapping = depth::parseMapping(o.depthMapping);
    if (!mapping)
        return fail(kExitBadInput, "--depth-mapping must be inverse_z or linear");
    DecodedFrameProvider::Metric unplanned;
    unplanned.convert.raw.metresPerUnit = o.depthScale;
    unplanned.convert.mapping = *mapping;
    unplanned.convert.vmax = 65535.0;
    std::optional<DecodedFrameProvider::Metric> metric;
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
    auto provider = std::make_unique<DecodedFrameProvider>();
    std::string error;
    if (!provider->open(o.depth, o.fps, metric, unplanned, error))
        return fail(kExitBadInput, error);
    decoded = provider.get();
    frames = std::move(provider);
    return kExitOk;
}

/// One paragraph after a run: updates, time and rate, method, the share in contact, the largest
/// force and the safety trips, and where the force log went. On stdout, or on stderr when the
/// force log itself goes to stdout.
void printTouchSummary(const TouchOptions &o, const std::vector<haptics::ForceLogRow> &rows,
                       const std::string &readingNote)
{
    std::size_t contact = 0;
    std::size_t trips = 0;
    double maxForce = 0.0;
    for (const haptics::ForceLogRow &r : rows) {
        contact += r.out.contact ? 1u : 0u;
        trips += r.out.released ? 1u : 0u;
        maxForce = std::max(maxForce, glm::length(r.out.force));
    }
    const double seconds = rows.empty() ? 0.0 : rows.back().t - rows.front().t;
    const double share =
        rows.empty() ? 0.0
                     : 100.0 * static_cast<double>(contact) / static_cast<double>(rows.size());
    std::FILE *sink = o.out == "/dev/stdout" || o.out == "-" ? stderr : stdout;
    std::fprintf(
        sink,
        "touch: %zu updates over %.3f s at %g Hz (%s): %.0f %% in contact, max force %.2f N "
        "(device maximum %.2f N), %zu safety trips; force log %s\n",
        rows.size(), seconds, o.rate, o.method.c_str(), share, maxForce, o.maxForce, trips,
        o.out.c_str());
    if (!readingNote.empty())
        std::fprintf(sink, "touch: depth: %s\n", readingNote.c_str());
}

int runTouch(const TouchOptions &o)
{
    using namespace depthtouch::haptics;
    auto method = parseMethod(o.method);
    if (!method)
        return fail(kExitBadInput, "--method must be finger, modified, proxy-graph or mesh-bvh");
    if (o.reengage != "release" && o.reengage != "ramp")
        return fail(kExitBadInput, "--reengage must be release or ramp");
    ReplayOptions opt;
    opt.rate = o.rate;
    opt.method = *method;
    RendererConfig &c = opt.config;
    c.box = SceneBox{o.boxWidth, o.boxDepth};
    c.stiffness = o.stiffness;
    c.damping = o.damping;
    c.maxForce = o.maxForce;
    // The baselines run with every fix off; the --no-* flags turn single fixes off in `modified`.
    const bool fixes = *method == Method::Modified || *method == Method::Finger;
    c.correction = fixes && !o.noCorrection;
    c.interpolation = fixes && !o.noInterpolation;
    c.safety = fixes && !o.noSafety;
    c.maxForceStep = o.maxForceStep;
    c.reengage = o.reengage == "ramp" ? Reengage::Ramp : Reengage::Release;
    c.rampTime = o.rampTime;
    c.fingerRadius = o.fingerRadius;
    c.staticFriction = o.staticFriction;
    c.dynamicFriction = o.dynamicFriction;
    if (*method == Method::MeshBvh && (o.staticFriction > 0.0 || o.dynamicFriction > 0.0))
        return fail(kExitBadInput, "--method mesh-bvh has no friction");
    if (auto v = validateReplayOptions(opt); !v)
        return fail(kExitBadInput, v.error().what);
    // The output first: a directory, a FIFO without a reader or a missing folder fails before
    // the work, and only a regular file or a new path is ever replaced.
    if (auto p = platform::planOutput(o.out); !p)
        return fail(kExitBadInput, "cannot write '" + o.out + "': it " + p.error().what);

    // Depth input: a raw gray file with --size, else anything FFmpeg reads.
    std::unique_ptr<FrameProvider> frames;
    DecodedFrameProvider *decoded = nullptr;
    if (const int rc =
            !o.size.empty() ? openRawDepth(o, frames) : openDecodedDepth(o, frames, decoded);
        rc != kExitOk)
        return rc;

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

    auto rows = replay(*frames, *traj, opt);
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
    if (!o.quiet)
        printTouchSummary(o, *rows, decoded != nullptr ? decoded->readingNote() : std::string());
    return kExitOk;
}

} // namespace

void registerTouchCommand(CLI::App &app, int &exitCode)
{
    addTableCommand<TouchOptions>(app, "touch", kAbout, kTouchRows, runTouch, exitCode);
}

} // namespace depthtouch::cli
