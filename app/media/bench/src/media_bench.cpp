#include "depthtouch/media/media_bench.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <system_error>

#include <glm/geometric.hpp>

#include "depthtouch/depth/conversion.h"
#include "depthtouch/depth/fill.h"
#include "depthtouch/depth/resample.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/media/encode_job.h"
#include "depthtouch/media/encoder.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/image_io.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/cpu_time.h"
#include "depthtouch/platform/gnuplot.h"
#include "depthtouch/platform/percentile.h"

namespace depthtouch::media::bench {

using platform::percentile;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string framePath(const std::string &dir, int n, const char *kind)
{
    char name[64];
    std::snprintf(name, sizeof name, "/frame-%06d.%s", n, kind);
    return dir + name;
}

double kbps(long long bytes, std::size_t frames, double fps)
{
    const double seconds = static_cast<double>(frames) / fps;
    return seconds > 0.0 ? static_cast<double>(bytes) * 8.0 / seconds / 1000.0 : 0.0;
}

/// One encode: color (optional) and depth of every clip frame into one MKV.
struct EncodeSetting {
    std::string preset;
    bool withColor = true;
    int colorCrf = 23;
    int depthCrf = 18;
    bool depthLossless = false;
    int threads = 1;
};

struct Encoded {
    long long colorBytes = 0;
    long long depthBytes = 0;
    double seconds = 0.0;    ///< First encode() to the muxer's finish(), flush included.
    double cpuSeconds = 0.0; ///< Process CPU time of the same.
};

Result<Encoded> encodeClip(const Clip &clip, const std::string &path, const EncodeSetting &s)
{
    MuxerOptions mo;
    mo.output = path;
    mo.container = Container::Matroska;
    const auto tags = depthTags(std::nullopt, depth::DepthMapping::InverseZ, 8);
    mo.tags = tags;
    auto muxer = Muxer::open(mo);
    if (!muxer)
        return unexpected(muxer.error());
    std::unique_ptr<VideoEncoder> color;
    if (s.withColor) {
        VideoEncoderConfig cc;
        cc.codec = VideoCodec::H264Yuv420p;
        cc.width = clip.width;
        cc.height = clip.height;
        cc.fps = clip.fps;
        cc.crf = s.colorCrf;
        cc.preset = s.preset;
        cc.threads = s.threads;
        cc.title = "color";
        auto c = VideoEncoder::create(cc, **muxer);
        if (!c)
            return unexpected(c.error());
        color = std::move(*c);
    }
    VideoEncoderConfig dc;
    dc.codec = VideoCodec::H264Gray;
    dc.width = clip.width;
    dc.height = clip.height;
    dc.fps = clip.fps;
    dc.crf = s.depthCrf;
    dc.lossless = s.depthLossless;
    dc.preset = s.preset;
    dc.threads = s.threads;
    dc.title = "depth";
    dc.tags = tags;
    auto depthEnc = VideoEncoder::create(dc, **muxer);
    if (!depthEnc)
        return unexpected(depthEnc.error());
    DT_TRY((*muxer)->start());

    platform::SteadyClock &clock = platform::SteadyClock::instance();
    const platform::TimePoint t0 = clock.now();
    const platform::Duration cpu0 = platform::processCpuTime();
    for (std::size_t i = 0; i < clip.frames(); ++i) {
        const double pts = static_cast<double>(i) / clip.fps;
        if (color)
            DT_TRY(color->encode(clip.color(i), pts));
        DT_TRY((*depthEnc)->encode(clip.nearness(i), pts));
    }
    if (color)
        DT_TRY(color->flush());
    DT_TRY((*depthEnc)->flush());
    DT_TRY((*muxer)->finish());
    Encoded out;
    out.seconds = platform::toSeconds(clock.now() - t0);
    out.cpuSeconds = platform::toSeconds(platform::processCpuTime() - cpu0);
    out.colorBytes = color ? color->bytes() : 0;
    out.depthBytes = (*depthEnc)->bytes();
    return out;
}

/// One pass of the receiver over a file.
struct Decoded {
    std::vector<double> frameSeconds; ///< Time of each next() that gave a paired frame.
    double seconds = 0.0;             ///< Their sum.
    double cpuSeconds = 0.0;          ///< Process CPU time of the same calls.
    receiver::ReceiverStats stats;
    std::vector<std::uint8_t> depth; ///< Depth frames back to back (when captured), W×H each.
};

Result<Decoded> decodeFile(const std::string &path, const ReceiverBackends &backends,
                           bool depthOnly, bool capture, int width, int height)
{
    if (!backends.makeSource || !backends.makeDecoder)
        return unexpected(Errc::InvalidArgument, "no media source or decoder backend given");
    auto src = backends.makeSource();
    if (!src)
        return unexpected(src.error());
    receiver::ReceiverConfig cfg;
    cfg.requireDepth = true;
    cfg.requireColor = !depthOnly;
    cfg.single = depthOnly ? receiver::SingleStream::Depth : receiver::SingleStream::Auto;
    auto rx = receiver::Receiver::open(std::move(*src), path.c_str(), backends.makeDecoder, cfg);
    if (!rx)
        return unexpected(rx.error());
    Decoded out;
    const std::size_t frameBytes = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    platform::SteadyClock &clock = platform::SteadyClock::instance();
    receiver::PairedFrame f;
    for (;;) {
        const platform::Duration cpu0 = platform::processCpuTime();
        const platform::TimePoint t0 = clock.now();
        auto got = (*rx)->next(f);
        const platform::TimePoint t1 = clock.now();
        const platform::Duration cpu1 = platform::processCpuTime();
        if (!got)
            return unexpected(got.error());
        if (!*got)
            break;
        const double s = platform::toSeconds(t1 - t0);
        out.frameSeconds.push_back(s);
        out.seconds += s;
        out.cpuSeconds += platform::toSeconds(cpu1 - cpu0);
        if (capture) {
            if (!f.depth || f.depth->image.format != hal::PixelFormat::Gray8 ||
                f.depth->image.width != width || f.depth->image.height != height)
                return unexpected(Errc::InvalidArgument, "decoded depth frame is not 8-bit gray of the clip size");
            const std::size_t at = out.depth.size();
            out.depth.resize(at + frameBytes);
            for (int y = 0; y < height; ++y)
                std::memcpy(out.depth.data() + at + static_cast<std::size_t>(y) * static_cast<std::size_t>(width),
                            f.depth->image.row(0, y), static_cast<std::size_t>(width));
        }
    }
    f = receiver::PairedFrame{};
    out.stats = (*rx)->stats();
    return out;
}

/// Views of W×H Gray8 frames stored back to back, PTS i/fps.
std::vector<haptics::DepthFrameView> viewsOf(const std::vector<std::uint8_t> &video, int width,
                                            int height, double fps)
{
    const std::size_t frameBytes = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    std::vector<haptics::DepthFrameView> views;
    for (std::size_t i = 0; frameBytes > 0 && (i + 1) * frameBytes <= video.size(); ++i) {
        haptics::DepthFrameView v;
        v.data = video.data() + i * frameBytes;
        v.width = width;
        v.height = height;
        v.strideBytes = static_cast<std::size_t>(width);
        v.format = haptics::SampleFormat::Gray8;
        v.pts = static_cast<double>(i) / fps;
        views.push_back(v);
    }
    return views;
}

/// Index of the frame shown at haptic time \a t (s from the first PTS), as replay() picks it.
std::size_t frameAt(const std::vector<haptics::DepthFrameView> &frames, double t)
{
    std::size_t i = 0;
    while (i + 1 < frames.size() && frames[i + 1].pts - frames.front().pts <= t)
        ++i;
    return i;
}

/// Updates of \a rows whose proxy ended below the surface the renderer saw (frames i, i+1
/// interpolated, paper Eq. 1) by more than a millionth of the sample spacing.
long countPopThroughs(const std::vector<haptics::DepthFrameView> &frames,
                      const std::vector<haptics::ForceLogRow> &rows, const haptics::SceneBox &box)
{
    haptics::HeightField surface(box);
    std::size_t current = frames.size();
    long pops = 0;
    for (const haptics::ForceLogRow &row : rows) {
        const std::size_t i = frameAt(frames, row.t);
        if (i != current) {
            current = i;
            if (!surface.setFrames(frames[i], i + 1 < frames.size() ? &frames[i + 1] : nullptr))
                return -1;
        }
        surface.setTime(frames.front().pts + row.t, true);
        const glm::dvec3 &p = row.out.proxy;
        if (surface.contains(p.x, p.y) && p.z < surface.heightAt(p.x, p.y) - 1e-6 * surface.spacing())
            ++pops;
    }
    return pops;
}

/// Frames stored back to back in memory that the caller keeps alive: no copy per replay.
class BorrowedFrames final : public haptics::FrameProvider {
public:
    explicit BorrowedFrames(std::vector<haptics::DepthFrameView> views) : views_(std::move(views)) {}
    [[nodiscard]] std::size_t frameCount() const noexcept override { return views_.size(); }
    Result<haptics::DepthFrameView> frame(std::size_t i) noexcept override
    {
        if (i >= views_.size())
            return unexpected(Errc::InvalidArgument, "depth frame index out of range");
        return views_[i];
    }

private:
    std::vector<haptics::DepthFrameView> views_;
};

Result<std::vector<haptics::ForceLogRow>> replayOn(const std::vector<std::uint8_t> &video, int width,
                                                   int height, double fps,
                                                   const std::vector<haptics::TrajectorySample> &stroke,
                                                   const haptics::ReplayOptions &options)
{
    BorrowedFrames frames(viewsOf(video, width, height, fps));
    return haptics::replay(frames, stroke, options);
}

std::string tempName(const MediaBenchOptions &o, const std::string &name)
{
    return (std::filesystem::path(o.workDir.empty() ? "." : o.workDir) / name).string();
}

void removeUnlessKept(const MediaBenchOptions &o, const std::string &path)
{
    if (!o.keepFiles) {
        std::error_code ec;
        std::filesystem::remove(path, ec);
    }
}

std::string sizeText(int w, int h)
{
    return std::to_string(w) + "x" + std::to_string(h);
}

std::string psnrText(double db)
{
    if (std::isinf(db))
        return "inf";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", db);
    return buf;
}

std::string settingText(const RateRow &r)
{
    return r.lossless ? std::string("lossless") : "crf" + std::to_string(r.crf);
}

} // namespace

// ---------------------------------------------------------------------------------------------
// Content

Result<Clip> loadKitchenClip(const std::string &sceneDir, int frames, int width, int height)
{
    if (frames < 2 || width < 2 || height < 2 || width % 2 != 0 || height % 2 != 0)
        return unexpected(Errc::InvalidArgument, "clip needs >= 2 frames and an even size >= 2x2");
    std::error_code ec;
    if (!std::filesystem::exists(framePath(sceneDir, 0, "depth.png"), ec) ||
        !std::filesystem::exists(framePath(sceneDir, 0, "color.jpg"), ec))
        return unexpected(Errc::Io, "no frame-000000.depth.png / .color.jpg in the scene folder");
    int stored = 0;
    while (stored < frames && std::filesystem::exists(framePath(sceneDir, stored, "depth.png"), ec) &&
           std::filesystem::exists(framePath(sceneDir, stored, "color.jpg"), ec))
        ++stored;

    Clip clip;
    clip.width = width;
    clip.height = height;
    clip.fps = 30.0;
    SourceOptions so;
    so.fps = clip.fps;
    auto colorSource = openFfmpegFrameSource(sceneDir + "/frame-%06d.color.jpg", so);
    if (!colorSource)
        return unexpected(colorSource.error());
    std::optional<depth::DepthRange> range;
    int nativeW = 0;
    int nativeH = 0;
    for (int n = 0; n < stored; ++n) {
        auto color = (*colorSource)->next(PixelFormat::Rgb24, width, height);
        if (!color)
            return unexpected(color.error());
        nativeW = (*colorSource)->info().width;
        nativeH = (*colorSource)->info().height;
        auto raw = readImage(framePath(sceneDir, n, "depth.png"), PixelFormat::Gray16);
        if (!raw)
            return unexpected(raw.error());
        depth::ConvertOptions co;
        co.range = range; // the first frame's robust range for the whole clip, as the sender does
        auto nf = depth::metricToNearness(toPlane16(*raw), co);
        if (!nf)
            return unexpected(nf.error());
        range = nf->range;
        if (nf->invalidCount > 0) {
            if (auto filled = depth::fillInvalid(nf->nearness, nf->valid); !filled)
                return unexpected(filled.error());
        }
        auto resampled = depth::resample(nf->nearness, width, height);
        if (!resampled)
            return unexpected(resampled.error());
        const depth::Plane<std::uint16_t> q = depth::quantize(*resampled, 255.0);
        Image near = Image::make(width, height, PixelFormat::Gray8);
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                near.row(y)[x] = static_cast<std::uint8_t>(q.at(x, y));
        clip.colors.push_back(std::move(color->image));
        clip.nearnesses.push_back(std::move(near));
    }
    // Forward, then backward, then forward…: a longer clip without a cut.
    const std::size_t period = stored > 1 ? 2u * static_cast<std::size_t>(stored) - 2u : 1u;
    for (int i = 0; i < frames; ++i) {
        const std::size_t k = static_cast<std::size_t>(i) % period;
        clip.order.push_back(k < static_cast<std::size_t>(stored) ? k : period - k);
    }
    char text[256];
    std::snprintf(text, sizeof text,
                  "7-Scenes redkitchen: %d frames%s of %dx%d (JPEG color, mm depth -> 8-bit 1/Z "
                  "nearness %.2f..%.2f m, holes filled) stretched to %dx%d",
                  frames, stored < frames ? " (played forward and back)" : "", nativeW, nativeH,
                  range ? range->nearM : 0.0, range ? range->farM : 0.0, width, height);
    clip.description = text;
    return clip;
}

Clip makeSyntheticClip(int width, int height, int frames, double fps)
{
    Clip clip;
    clip.width = width;
    clip.height = height;
    clip.fps = fps;
    const double r1 = 0.22 * std::min(width, height);
    const double r2 = 0.15 * std::min(width, height);
    for (int n = 0; n < frames; ++n) {
        const double t = static_cast<double>(n) / fps;
        const double c1x = width * (0.35 + 0.10 * std::sin(2.0 * kPi * 0.5 * t));
        const double c1y = height * 0.45;
        const double c2x = width * 0.70;
        const double c2y = height * (0.50 + 0.15 * std::cos(2.0 * kPi * 0.4 * t));
        Image near = Image::make(width, height, PixelFormat::Gray8);
        Image color = Image::make(width, height, PixelFormat::Rgb24);
        const int shift = n * 2;
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                double v = 40.0 + 70.0 * x / (width - 1) + 30.0 * y / (height - 1);
                const double d1 = std::hypot(x - c1x, y - c1y);
                const double d2 = std::hypot(x - c2x, y - c2y);
                if (d1 < r1)
                    v = std::max(v, 110.0 + 100.0 * std::sqrt(1.0 - (d1 * d1) / (r1 * r1)));
                if (d2 < r2)
                    v = std::max(v, 150.0 + 90.0 * std::sqrt(1.0 - (d2 * d2) / (r2 * r2)));
                const auto level = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
                near.row(y)[x] = level;
                const bool check = (((x + shift) / 8) + (y / 8)) % 2 == 0;
                std::uint8_t *px = color.row(y) + 3 * x;
                px[0] = static_cast<std::uint8_t>(255 * x / width);
                px[1] = check ? 190 : 70;
                px[2] = level;
            }
        }
        clip.colors.push_back(std::move(color));
        clip.nearnesses.push_back(std::move(near));
        clip.order.push_back(static_cast<std::size_t>(n));
    }
    clip.description = "synthetic: tilted plane with two moving spheres, " + std::to_string(frames) +
                       " frames " + sizeText(width, height);
    return clip;
}

// ---------------------------------------------------------------------------------------------
// Measurements

Result<std::vector<ThroughputRow>> measureThroughput(const Clip &clip,
                                                     const ReceiverBackends &backends,
                                                     const MediaBenchOptions &options)
{
    if (clip.frames() < 2)
        return unexpected(Errc::InvalidArgument, "clip has fewer than 2 frames");
    if (options.decodeRuns < 1)
        return unexpected(Errc::InvalidArgument, "decode runs must be >= 1");
    std::vector<ThroughputRow> rows;
    for (const std::string &preset : options.presets) {
        const std::string path =
            tempName(options, "throughput-" + sizeText(clip.width, clip.height) + "-" + preset + ".mkv");
        EncodeSetting es;
        es.preset = preset;
        es.colorCrf = options.colorCrf;
        es.depthCrf = options.depthCrf;
        es.threads = options.encodeThreads;
        auto enc = encodeClip(clip, path, es);
        if (!enc)
            return unexpected(enc.error());
        ThroughputRow row;
        row.width = clip.width;
        row.height = clip.height;
        row.preset = preset;
        row.frames = clip.frames();
        row.colorKbps = kbps(enc->colorBytes, clip.frames(), clip.fps);
        row.depthKbps = kbps(enc->depthBytes, clip.frames(), clip.fps);
        row.encodeSeconds = enc->seconds;
        row.encodeFps = enc->seconds > 0.0 ? static_cast<double>(clip.frames()) / enc->seconds : 0.0;
        row.encodeCpuFps =
            enc->cpuSeconds > 0.0 ? static_cast<double>(clip.frames()) / enc->cpuSeconds : 0.0;
        std::vector<double> perFrame;
        std::vector<double> cpuFps;
        for (int run = 0; run < options.decodeRuns; ++run) {
            auto dec = decodeFile(path, backends, false, false, clip.width, clip.height);
            if (!dec) {
                removeUnlessKept(options, path);
                return unexpected(dec.error());
            }
            if (dec->frameSeconds.size() != clip.frames()) {
                removeUnlessKept(options, path);
                return unexpected(Errc::InvalidArgument, "paired frame count differs from the frames encoded");
            }
            row.decodeRunFps.push_back(static_cast<double>(dec->frameSeconds.size()) / dec->seconds);
            cpuFps.push_back(dec->cpuSeconds > 0.0
                                 ? static_cast<double>(dec->frameSeconds.size()) / dec->cpuSeconds
                                 : 0.0);
            perFrame.insert(perFrame.end(), dec->frameSeconds.begin(), dec->frameSeconds.end());
            row.depthDuplicated = dec->stats.depthDuplicated;
            row.depthMissing = dec->stats.depthMissing;
        }
        removeUnlessKept(options, path);
        row.decodeFps = percentile(row.decodeRunFps, 0.5);
        row.decodeMedianMs = 1000.0 * percentile(perFrame, 0.5);
        row.decodeP99Ms = 1000.0 * percentile(perFrame, 0.99);
        row.decodeRealtime = row.decodeFps / clip.fps;
        row.decodeCpuFps = percentile(cpuFps, 0.5);
        row.decodeCpuRealtime = row.decodeCpuFps / clip.fps;
        rows.push_back(std::move(row));
    }
    return rows;
}

namespace {

/// Force logs of every stroke on one depth video, for both renderer settings.
struct StrokeForces {
    std::vector<std::vector<haptics::ForceLogRow>> safety;   ///< Per stroke, fixes a–c on.
    std::vector<std::vector<haptics::ForceLogRow>> noSafety; ///< Per stroke, fix (c) off.
};

Result<StrokeForces> replayStrokes(const std::vector<std::uint8_t> &video, const Clip &clip,
                                   const std::vector<std::vector<haptics::TrajectorySample>> &strokes,
                                   const haptics::ReplayOptions &withSafety)
{
    haptics::ReplayOptions withoutSafety = withSafety;
    withoutSafety.config.safety = false;
    StrokeForces out;
    for (const auto &stroke : strokes) {
        auto a = replayOn(video, clip.width, clip.height, clip.fps, stroke, withSafety);
        if (!a)
            return unexpected(a.error());
        auto b = replayOn(video, clip.width, clip.height, clip.fps, stroke, withoutSafety);
        if (!b)
            return unexpected(b.error());
        out.safety.push_back(std::move(*a));
        out.noSafety.push_back(std::move(*b));
    }
    return out;
}

/// Pooled force error of logs \a test against \a reference, stroke by stroke.
ForceError pooledError(const std::vector<std::vector<haptics::ForceLogRow>> &reference,
                       const std::vector<std::vector<haptics::ForceLogRow>> &test)
{
    double sq = 0.0;
    std::size_t n = 0;
    ForceError e;
    for (std::size_t k = 0; k < reference.size() && k < test.size(); ++k) {
        const ForceError one = compareForces(reference[k], test[k]);
        const std::size_t rows = std::min(reference[k].size(), test[k].size());
        sq += one.rmsN * one.rmsN * static_cast<double>(rows);
        n += rows;
        e.maxN = std::max(e.maxN, one.maxN);
    }
    e.rmsN = n > 0 ? std::sqrt(sq / static_cast<double>(n)) : 0.0;
    return e;
}

} // namespace

Result<RateAccuracy> measureRateAccuracy(const Clip &clip, const ReceiverBackends &backends,
                                         const MediaBenchOptions &options)
{
    if (clip.frames() < 2)
        return unexpected(Errc::InvalidArgument, "clip has fewer than 2 frames");
    std::vector<std::uint8_t> source;
    for (std::size_t i = 0; i < clip.frames(); ++i) {
        const Image &im = clip.nearness(i);
        for (int y = 0; y < im.height; ++y)
            source.insert(source.end(), im.row(y), im.row(y) + im.width);
    }

    const haptics::SceneBox box{};
    haptics::ReplayOptions ro;
    ro.rate = options.hapticRate;
    ro.method = haptics::Method::Modified;
    ro.config = haptics::RendererConfig::forMethod(haptics::Method::Modified);
    ro.config.box = box;

    // Each setting: encode depth only, decode it through the receiver, compare with lossless.
    struct Setting {
        bool lossless;
        int crf;
    };
    std::vector<Setting> settings{{true, 0}};
    for (const int crf : options.depthCrfs) {
        if (crf < 0)
            continue; // lossless is always measured first
        if (crf > 51)
            return unexpected(Errc::InvalidArgument, "depth CRF must be in 0..51");
        settings.push_back({false, crf});
    }
    RateAccuracy result;
    std::vector<std::uint8_t> reference;
    std::vector<std::vector<haptics::TrajectorySample>> strokes;
    std::vector<std::vector<haptics::TrajectorySample>> presses;
    StrokeForces referenceForces;
    StrokeForces referencePresses;
    for (const Setting &s : settings) {
        const std::string path = tempName(
            options, "rate-" + sizeText(clip.width, clip.height) + "-" +
                         (s.lossless ? std::string("lossless") : "crf" + std::to_string(s.crf)) + ".mkv");
        EncodeSetting es;
        es.preset = options.ratePreset;
        es.withColor = false;
        es.depthCrf = s.crf;
        es.depthLossless = s.lossless;
        es.threads = options.encodeThreads;
        auto enc = encodeClip(clip, path, es);
        if (!enc)
            return unexpected(enc.error());
        auto dec = decodeFile(path, backends, true, true, clip.width, clip.height);
        removeUnlessKept(options, path);
        if (!dec)
            return unexpected(dec.error());
        if (dec->depth.size() != source.size())
            return unexpected(Errc::InvalidArgument, "decoded depth frame count differs from the frames encoded");
        RateRow row;
        row.lossless = s.lossless;
        row.crf = s.crf;
        row.depthKbps = kbps(enc->depthBytes, clip.frames(), clip.fps);
        if (s.lossless) {
            result.losslessExact = dec->depth == source;
            reference = std::move(dec->depth);
            const auto views = viewsOf(reference, clip.width, clip.height, clip.fps);
            const std::vector<double> lanes = strokeLanes(clip.width, clip.height, box);
            for (const double lane : lanes) {
                strokes.push_back(makeStroke(views, box, lane));
                for (const double x : {-0.3, -0.15, 0.0, 0.15, 0.3})
                    presses.push_back(makePress(views, box, x * box.width, lane));
            }
            char text[300];
            std::snprintf(text, sizeof text,
                          "%zu strokes (lanes y = %.1f..%+.1f mm), each %.0f mm left to right in "
                          "%.2f s, 2 mm below the lossless surface; %zu presses (5 per lane) 2 mm "
                          "into it; replayed at %.0f Hz",
                          lanes.size(), 1000.0 * *std::min_element(lanes.begin(), lanes.end()),
                          1000.0 * *std::max_element(lanes.begin(), lanes.end()), 800.0 * box.width,
                          strokes.front().back().t, presses.size(), options.hapticRate);
            result.stroke = text;
        }
        const std::vector<std::uint8_t> &video = s.lossless ? reference : dec->depth;
        auto replayed = replayStrokes(video, clip, strokes, ro);
        if (!replayed)
            return unexpected(replayed.error());
        auto pressed = replayStrokes(video, clip, presses, ro);
        if (!pressed)
            return unexpected(pressed.error());
        if (s.lossless) {
            // The lossless row compares them with themselves: zero error.
            referenceForces = *replayed;
            referencePresses = *pressed;
        }
        const StrokeForces *forces = &*replayed;
        const ForceError press = pooledError(referencePresses.safety, pressed->safety);
        row.pressRmsN = press.rmsN;
        row.pressMaxN = press.maxN;
        row.psnrDb = psnr8(reference, video);
        const ForceError withSafety = pooledError(referenceForces.safety, forces->safety);
        const ForceError noSafety = pooledError(referenceForces.noSafety, forces->noSafety);
        row.forceRmsN = withSafety.rmsN;
        row.forceMaxN = withSafety.maxN;
        row.forceRmsNoSafetyN = noSafety.rmsN;
        row.forceMaxNoSafetyN = noSafety.maxN;
        const auto views = viewsOf(video, clip.width, clip.height, clip.fps);
        double sq = 0.0;
        for (std::size_t k = 0; k < forces->safety.size(); ++k) {
            for (const haptics::ForceLogRow &r : forces->safety[k])
                row.releases += r.out.released ? 1 : 0;
            row.popThroughs += countPopThroughs(views, forces->safety[k], box);
            row.updates += forces->safety[k].size();
            for (const haptics::ForceLogRow &r : referenceForces.safety[k])
                sq += glm::dot(r.out.force, r.out.force);
        }
        row.forceRefRmsN = row.updates > 0 ? std::sqrt(sq / static_cast<double>(row.updates)) : 0.0;
        result.rows.push_back(row);
    }
    return result;
}

double psnr8(const std::vector<std::uint8_t> &reference, const std::vector<std::uint8_t> &test)
{
    if (reference.size() != test.size() || reference.empty())
        return std::numeric_limits<double>::quiet_NaN();
    double sq = 0.0;
    for (std::size_t i = 0; i < reference.size(); ++i) {
        const double d = static_cast<double>(reference[i]) - static_cast<double>(test[i]);
        sq += d * d;
    }
    if (sq == 0.0)
        return std::numeric_limits<double>::infinity();
    const double mse = sq / static_cast<double>(reference.size());
    return 10.0 * std::log10(255.0 * 255.0 / mse);
}

ForceError compareForces(const std::vector<haptics::ForceLogRow> &a,
                         const std::vector<haptics::ForceLogRow> &b)
{
    ForceError e;
    const std::size_t n = std::min(a.size(), b.size());
    if (n == 0)
        return e;
    double sq = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double d = glm::length(a[i].out.force - b[i].out.force);
        sq += d * d;
        e.maxN = std::max(e.maxN, d);
    }
    e.rmsN = std::sqrt(sq / static_cast<double>(n));
    return e;
}

namespace {

/// HIP path from (x0, y) to (x1, y) (m) with a sway of \a sway m in y, following the surface of
/// \a frames 2 mm below it after an approach from 8 mm above (see makeStroke()).
std::vector<haptics::TrajectorySample> followSurface(const std::vector<haptics::DepthFrameView> &frames,
                                                     const haptics::SceneBox &box, double x0, double x1,
                                                     double y, double sway, double rowPeriod)
{
    std::vector<haptics::TrajectorySample> out;
    if (frames.size() < 2 || !(rowPeriod > 0.0))
        return out;
    const double tEnd = frames.back().pts - frames.front().pts;
    const double approach = std::min(0.25, 0.25 * tEnd);
    haptics::HeightField surface(box);
    std::size_t current = frames.size();
    const auto rows = static_cast<std::size_t>(std::ceil(tEnd / rowPeriod - 1e-9));
    for (std::size_t k = 0; k <= rows; ++k) {
        const double t = std::min(static_cast<double>(k) * rowPeriod, tEnd);
        const std::size_t i = frameAt(frames, t);
        if (i != current) {
            current = i;
            (void)surface.setFrames(frames[i], i + 1 < frames.size() ? &frames[i + 1] : nullptr);
        }
        surface.setTime(frames.front().pts + t, true);
        const double u = t <= approach ? 0.0 : (t - approach) / (tEnd - approach);
        haptics::TrajectorySample s;
        s.t = t;
        s.x = x0 + (x1 - x0) * u;
        s.y = y + sway * std::sin(3.0 * kPi * u);
        const double h = surface.contains(s.x, s.y) ? surface.heightAt(s.x, s.y) : 0.0;
        s.z = t < approach ? h + 0.008 - 0.010 * (t / approach) : h - 0.002;
        out.push_back(s);
    }
    return out;
}

} // namespace

std::vector<haptics::TrajectorySample> makeStroke(const std::vector<haptics::DepthFrameView> &frames,
                                                  const haptics::SceneBox &box, double laneY,
                                                  double rowPeriod)
{
    return followSurface(frames, box, -0.4 * box.width, 0.4 * box.width, laneY, 0.001, rowPeriod);
}

std::vector<haptics::TrajectorySample> makePress(const std::vector<haptics::DepthFrameView> &frames,
                                                 const haptics::SceneBox &box, double x, double y,
                                                 double rowPeriod)
{
    return followSurface(frames, box, x, x, y, 0.0, rowPeriod);
}

std::vector<double> strokeLanes(int width, int height, const haptics::SceneBox &box)
{
    const double halfHeight = width > 1 ? 0.5 * box.width * (height - 1) / (width - 1) : 0.0;
    std::vector<double> lanes{0.0};
    for (int k = 1; k <= 8; ++k) {
        lanes.push_back(0.1 * k * halfHeight);
        lanes.push_back(-0.1 * k * halfHeight);
    }
    return lanes;
}

// ---------------------------------------------------------------------------------------------
// Report

double realtimeGoal(int width, int height) noexcept
{
    if (width == 720 && height == 486)
        return 10.0;
    if (width == 1920 && height == 1080)
        return 2.0;
    return 0.0;
}

void printReport(const MediaBenchReport &r)
{
    std::printf("content: %s\n", r.content.c_str());
    std::printf("decode + pairing: receiver on %s, on the calling thread; x RT = multiple of real "
                "time at %.0f fps\n",
                r.backends.c_str(), r.fps);
    if (r.loadBefore >= 0.0)
        std::printf("machine load (1-min average) before / after: %.2f / %.2f; 'cpu' figures divide "
                    "by the process's CPU time (one core's worth of work), 'wall' by elapsed time\n",
                    r.loadBefore, r.loadAfter);
    std::printf("\n%-9s %-9s %6s %8s %8s %8s %8s %8s %8s %7s %7s %8s %8s\n", "size", "preset",
                "frames", "color", "depth", "enc fps", "enc fps", "dec fps", "dec fps", "med ms",
                "p99 ms", "dec xRT", "dec xRT");
    std::printf("%-9s %-9s %6s %8s %8s %8s %8s %8s %8s %7s %7s %8s %8s\n", "", "", "", "kbit/s",
                "kbit/s", "wall", "cpu", "wall", "cpu", "wall", "wall", "wall", "cpu");
    for (const ThroughputRow &t : r.throughput)
        std::printf("%-9s %-9s %6zu %8.0f %8.0f %8.1f %8.1f %8.1f %8.1f %7.2f %7.2f %8.1f %8.1f\n",
                    sizeText(t.width, t.height).c_str(), t.preset.c_str(), t.frames, t.colorKbps,
                    t.depthKbps, t.encodeFps, t.encodeCpuFps, t.decodeFps, t.decodeCpuFps,
                    t.decodeMedianMs, t.decodeP99Ms, t.decodeRealtime, t.decodeCpuRealtime);
    if (!r.rate.empty()) {
        std::printf("\nrate vs haptic accuracy at %s: depth only (x264 gray); force error = the same "
                    "strokes replayed (modified proxy graph) on the decoded vs the lossless depth\n",
                    sizeText(r.rateWidth, r.rateHeight).c_str());
        std::printf("strokes: %s\n", r.stroke.c_str());
        std::printf("lossless depth decoded bit-exact: %s\n", r.losslessExact ? "yes" : "NO");
        std::printf("%-9s %8s %8s | %-19s | %-37s | %-9s\n", "", "", "", "presses", "strokes, as `touch` runs them",
                    "strokes");
        std::printf("%-9s %8s %8s | %-19s | %-37s | %-9s\n", "", "", "", "force error", "force error",
                    "no safety");
        std::printf("%-9s %8s %8s | %9s %9s | %9s %9s %8s %8s | %9s\n", "depth", "kbit/s", "PSNR dB",
                    "RMS N", "max N", "RMS N", "max N", "releases", "pops", "RMS N");
        for (const RateRow &q : r.rate)
            std::printf("%-9s %8.1f %8s | %9.4f %9.3f | %9.4f %9.3f %8ld %8ld | %9.4f\n",
                        settingText(q).c_str(), q.depthKbps, psnrText(q.psnrDb).c_str(), q.pressRmsN,
                        q.pressMaxN, q.forceRmsN, q.forceMaxN, q.releases, q.popThroughs,
                        q.forceRmsNoSafetyN);
        std::printf("(RMS of |F| on the lossless strokes: %.3f N; %zu updates per setting on the strokes; "
                    "pops: updates ending with the proxy below the decoded surface, e.g. after a "
                    "release)\n",
                    r.rate.front().forceRefRmsN, r.rate.front().updates);
    }
    std::printf("\ngoals (decode + pairing of color + depth on one core, x real time at %.0f fps; "
                "worst preset's file):\n",
                r.fps);
    bool any = false;
    for (std::size_t k = 0; k < r.throughput.size(); ++k) {
        const ThroughputRow &t = r.throughput[k];
        const double goal = realtimeGoal(t.width, t.height);
        bool first = true;
        for (std::size_t j = 0; j < k; ++j)
            if (r.throughput[j].width == t.width && r.throughput[j].height == t.height)
                first = false;
        if (goal <= 0.0 || !first)
            continue;
        any = true;
        const ThroughputRow *worst = &t;
        for (const ThroughputRow &u : r.throughput)
            if (u.width == t.width && u.height == t.height && u.decodeCpuRealtime < worst->decodeCpuRealtime)
                worst = &u;
        std::printf("  %s >= %.0fx: %s: %.1fx on CPU time (%s file); %.1fx on the wall clock\n",
                    sizeText(t.width, t.height).c_str(), goal,
                    worst->decodeCpuRealtime >= goal ? "met" : "NOT met", worst->decodeCpuRealtime,
                    worst->preset.c_str(), worst->decodeRealtime);
    }
    if (!any)
        std::printf("  (no goal for the sizes measured: goals are for 720x486 and 1920x1080)\n");
}

bool writeReport(const MediaBenchReport &r, const std::string &dir, std::string &error, std::string &note)
{
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) {
        error = "cannot create " + dir + ": " + ec.message();
        return false;
    }
    const fs::path base(dir);
    const std::string throughputCsv = (base / "media_throughput.csv").string();
    const std::string rateCsv = (base / "rate_accuracy.csv").string();
    {
        std::FILE *f = std::fopen(throughputCsv.c_str(), "w");
        if (f == nullptr) {
            error = "cannot write " + throughputCsv;
            return false;
        }
        std::fprintf(f, "size,preset,frames,color_kbps,depth_kbps,encode_fps,encode_cpu_fps,"
                        "decode_fps,decode_cpu_fps,decode_median_ms,decode_p99_ms,decode_realtime_x,"
                        "decode_cpu_realtime_x,goal_x,goal_met\n");
        for (const ThroughputRow &t : r.throughput) {
            const double goal = realtimeGoal(t.width, t.height);
            std::fprintf(f, "%s,%s,%zu,%.1f,%.1f,%.2f,%.2f,%.1f,%.1f,%.3f,%.3f,%.2f,%.2f,%g,%s\n",
                         sizeText(t.width, t.height).c_str(), t.preset.c_str(), t.frames, t.colorKbps,
                         t.depthKbps, t.encodeFps, t.encodeCpuFps, t.decodeFps, t.decodeCpuFps,
                         t.decodeMedianMs, t.decodeP99Ms, t.decodeRealtime, t.decodeCpuRealtime, goal,
                         goal <= 0.0 ? "" : (t.decodeCpuRealtime >= goal ? "yes" : "no"));
        }
        const bool ok = std::ferror(f) == 0;
        if (std::fclose(f) != 0 || !ok) {
            error = "cannot write " + throughputCsv;
            return false;
        }
    }
    {
        std::FILE *f = std::fopen(rateCsv.c_str(), "w");
        if (f == nullptr) {
            error = "cannot write " + rateCsv;
            return false;
        }
        std::fprintf(f, "depth,crf,depth_kbps,psnr_db,force_rms_n,force_max_n,releases,pop_throughs,"
                        "force_rms_no_safety_n,force_max_no_safety_n,press_rms_n,press_max_n,"
                        "force_ref_rms_n,updates\n");
        for (const RateRow &q : r.rate)
            std::fprintf(f, "%s,%s,%.2f,%s,%.6f,%.6f,%ld,%ld,%.6f,%.6f,%.6f,%.6f,%.6f,%zu\n",
                         settingText(q).c_str(), q.lossless ? "" : std::to_string(q.crf).c_str(),
                         q.depthKbps, psnrText(q.psnrDb).c_str(), q.forceRmsN, q.forceMaxN,
                         q.releases, q.popThroughs, q.forceRmsNoSafetyN, q.forceMaxNoSafetyN,
                         q.pressRmsN, q.pressMaxN, q.forceRefRmsN, q.updates);
        const bool ok = std::ferror(f) == 0;
        if (std::fclose(f) != 0 || !ok) {
            error = "cannot write " + rateCsv;
            return false;
        }
    }

    const std::string script = (base / "media_bench.gp").string();
    {
        std::FILE *g = std::fopen(script.c_str(), "w");
        if (g == nullptr) {
            error = "cannot write " + script;
            return false;
        }
        std::fprintf(g,
                     "set terminal pngcairo size 1000,680 noenhanced\n"
                     "set datafile separator ','\n"
                     "set output '%s'\n"
                     "set title 'Depth rate vs accuracy, %s, x264 gray: PSNR and haptic force error "
                     "vs lossless depth'\n"
                     "set logscale x\nset grid\n"
                     "set xlabel 'depth bitrate (kbit/s, log scale)'\n"
                     "set ylabel 'depth PSNR vs lossless (dB, 8-bit nearness)'\n"
                     "set y2label 'force RMS error vs lossless depth (N)'\n"
                     "set ytics nomirror\nset y2tics\nset y2range [0:*]\n"
                     "set key below\n"
                     "plot '%s' skip 1 using 3:(strcol(4) eq 'inf' ? NaN : $4) axes x1y1 with "
                     "linespoints pt 7 lw 2 title 'PSNR (dB, left)', \\\n"
                     "     '' skip 1 using 3:5 axes x1y2 with linespoints pt 5 lw 2 title 'force RMS "
                     "error, strokes as touch runs them (N, right)', \\\n"
                     "     '' skip 1 using 3:9 axes x1y2 with linespoints pt 9 lw 2 dt 2 title 'force "
                     "RMS error, strokes, safety off (N, right)', \\\n"
                     "     '' skip 1 using 3:11 axes x1y2 with linespoints pt 11 lw 2 title 'force "
                     "RMS error, presses (N, right)', \\\n"
                     "     '' skip 1 using 3:(strcol(4) eq 'inf' ? NaN : $4):1 axes x1y1 with labels "
                     "offset 0,1 font ',8' notitle\n",
                     (base / "rate_vs_accuracy.png").string().c_str(),
                     sizeText(r.rateWidth, r.rateHeight).c_str(), rateCsv.c_str());
        std::fprintf(g,
                     "reset\nset datafile separator ','\n"
                     "set terminal pngcairo size 1000,560 noenhanced\n"
                     "set output '%s'\n"
                     "set title 'Color + depth throughput, one core: x real time at %.0f fps "
                     "(goals: decode 10x at 720x486, 2x at 1920x1080)'\n"
                     "set style data histograms\nset style histogram clustered gap 1\n"
                     "set style fill solid 0.8 border -1\nset boxwidth 0.9\n"
                     "set logscale y\nset grid ytics\nset ylabel 'x real time (log scale)'\n"
                     "set xtics rotate by -20 font ',9'\nset key top right\n"
                     "plot '%s' skip 1 using ($7/%g):xtic(stringcolumn(1).' '.stringcolumn(2)) "
                     "title 'encode (cpu)', '' skip 1 using 13 title 'decode + pairing (cpu)', "
                     "'' skip 1 using 12 title 'decode + pairing (wall)'\n",
                     (base / "media_throughput.png").string().c_str(), r.fps, throughputCsv.c_str(),
                     r.fps);
        const bool ok = std::ferror(g) == 0;
        if (std::fclose(g) != 0 || !ok) {
            error = "cannot write " + script;
            return false;
        }
    }
    note = platform::plotStatusNote(platform::runGnuplot(script));
    return true;
}

} // namespace depthtouch::media::bench
