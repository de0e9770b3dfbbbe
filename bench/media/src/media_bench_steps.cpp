#include "media_bench_steps.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <system_error>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/height_field.h"
#include "depthtouch/media/encode_job.h"
#include "depthtouch/media/encoder.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/cpu_time.h"
#include "depthtouch/platform/gnuplot.h"

namespace depthtouch::media::bench {

Result<Encoded> encodeDepthOnly(const Clip &clip, const std::string &path,
                                const std::string &preset, VideoCodec codec, int crf, bool lossless,
                                int threads)
{
    return encodeClip(clip, path,
                      EncodeSetting{.preset = preset,
                                    .depthCodec = codec,
                                    .withColor = false,
                                    .depthCrf = crf,
                                    .depthLossless = lossless,
                                    .threads = threads});
}

haptics::ReplayOptions paperReplay(const MediaBenchOptions &options, const scene::SceneBox &box)
{
    haptics::ReplayOptions ro;
    ro.rate = options.hapticRate;
    ro.method = haptics::Method::Modified;
    ro.config = haptics::RendererConfig::forMethod(haptics::Method::Modified);
    ro.config.box = box;
    return ro;
}

double kbps(long long bytes, std::size_t frames, double fps)
{
    const double seconds = static_cast<double>(frames) / fps;
    return seconds > 0.0 ? static_cast<double>(bytes) * 8.0 / seconds / 1000.0 : 0.0;
}

namespace {

/// The depth pictures of \a codec when it is not 8-bit: the clip's 16-bit nearness as it is
/// (FFV1) or rounded to 10 bits (Gray16 holding 0..1023); none for 8-bit H.264.
std::vector<Image> depthInputs(const Clip &clip, VideoCodec codec)
{
    std::vector<Image> out;
    if (codec == VideoCodec::H264Gray)
        return out;
    const double scale = codec == VideoCodec::Ffv1Gray16 ? 1.0 : 1023.0 / 65535.0;
    for (std::size_t i = 0; i < clip.frames(); ++i) {
        const Image &fine = clip.fineNearness(i);
        Image im = Image::make(fine.width, fine.height, PixelFormat::Gray16);
        for (int y = 0; y < fine.height; ++y)
            for (int x = 0; x < fine.width; ++x)
                im.setSample16(
                    x, y, static_cast<std::uint16_t>(std::lround(fine.sample16(x, y) * scale)));
        out.push_back(std::move(im));
    }
    return out;
}

} // namespace

Result<Encoded> encodeClip(const Clip &clip, const std::string &path, const EncodeSetting &s)
{
    MuxerOptions mo;
    mo.output = path;
    mo.container = Container::Matroska;
    const std::vector<Image> inputs = depthInputs(clip, s.depthCodec);
    const int bits = inputs.empty() ? 8 : s.depthCodec == VideoCodec::Ffv1Gray16 ? 16 : 10;
    const auto tags = depthTags(std::nullopt, depth::DepthMapping::InverseZ, bits);
    mo.tags = tags;
    auto muxer = Muxer::open(mo);
    if (!muxer)
        return unexpected(muxer.error());
    const VideoEncoderConfig cc =
        colorStreamConfig(clip.width, clip.height, clip.fps, s.colorCrf, s.preset, s.threads);
    std::unique_ptr<VideoEncoder> color;
    if (s.withColor) {
        auto c = VideoEncoder::create(cc, **muxer);
        if (!c)
            return unexpected(c.error());
        color = std::move(*c);
    }
    VideoEncoderConfig dc = cc;
    dc.codec = s.depthCodec;
    dc.crf = s.depthCrf;
    dc.lossless = s.depthLossless;
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
        DT_TRY((*depthEnc)->encode(inputs.empty() ? clip.nearness(i) : inputs[i], pts));
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
    const std::size_t frameBytes =
        static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
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
            const bool wide = f.depth && f.depth->image.format == hal::PixelFormat::Gray16;
            if (!f.depth || (f.depth->image.format != hal::PixelFormat::Gray8 && !wide) ||
                f.depth->image.width != width || f.depth->image.height != height ||
                (!out.depth.empty() && wide != (out.depthFormat == scene::SampleFormat::Gray16)))
                return unexpected(Errc::InvalidArgument,
                                  "decoded depth frame is not 8- or 16-bit gray of the clip size");
            out.depthFormat = wide ? scene::SampleFormat::Gray16 : scene::SampleFormat::Gray8;
            const std::size_t rowBytes = static_cast<std::size_t>(width) * (wide ? 2u : 1u);
            const std::size_t at = out.depth.size();
            out.depth.resize(at + frameBytes * (wide ? 2u : 1u));
            for (int y = 0; y < height; ++y)
                std::memcpy(out.depth.data() + at + static_cast<std::size_t>(y) * rowBytes,
                            f.depth->image.row(0, y), rowBytes);
        }
    }
    f = receiver::PairedFrame{};
    out.stats = (*rx)->stats();
    return out;
}

/// Views of W×H frames of \a format stored back to back, PTS i/fps.
std::vector<scene::DepthFrameView> viewsOf(const std::vector<std::uint8_t> &video, int width,
                                           int height, double fps, scene::SampleFormat format)
{
    const std::size_t rowBytes = static_cast<std::size_t>(width) * scene::bytesPerSample(format);
    const std::size_t frameBytes = rowBytes * static_cast<std::size_t>(height);
    std::vector<scene::DepthFrameView> views;
    for (std::size_t i = 0; frameBytes > 0 && (i + 1) * frameBytes <= video.size(); ++i) {
        scene::DepthFrameView v;
        v.data = video.data() + i * frameBytes;
        v.width = width;
        v.height = height;
        v.strideBytes = rowBytes;
        v.format = format;
        v.pts = static_cast<double>(i) / fps;
        views.push_back(v);
    }
    return views;
}

/// Index of the frame shown at haptic time \a t (s from the first PTS), as replay() picks it.
std::size_t frameAt(const std::vector<scene::DepthFrameView> &frames, double t)
{
    std::size_t i = 0;
    while (i + 1 < frames.size() && frames[i + 1].pts - frames.front().pts <= t)
        ++i;
    return i;
}

/// Updates of \a rows whose proxy ended below the surface the renderer saw (frames i, i+1
/// interpolated, paper Eq. 1) by more than a millionth of the sample spacing.
long countPopThroughs(const std::vector<scene::DepthFrameView> &frames,
                      const std::vector<haptics::ForceLogRow> &rows, const scene::SceneBox &box)
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
        if (surface.contains(p.x, p.y) &&
            p.z < surface.heightAt(p.x, p.y) - 1e-6 * surface.spacing())
            ++pops;
    }
    return pops;
}

namespace {

/// Frames stored back to back in memory that the caller keeps alive: no copy per replay.
class BorrowedFrames final : public haptics::FrameProvider {
public:
    explicit BorrowedFrames(std::vector<scene::DepthFrameView> views) : views_(std::move(views)) {}
    [[nodiscard]] std::size_t frameCount() const noexcept override { return views_.size(); }
    Result<scene::DepthFrameView> frame(std::size_t i) noexcept override
    {
        if (i >= views_.size())
            return unexpected(Errc::InvalidArgument, "depth frame index out of range");
        return views_[i];
    }

private:
    std::vector<scene::DepthFrameView> views_;
};

} // namespace

Result<std::vector<haptics::ForceLogRow>>
replayOn(const std::vector<std::uint8_t> &video, int width, int height, double fps,
         const std::vector<haptics::TrajectorySample> &stroke,
         const haptics::ReplayOptions &options, scene::SampleFormat format)
{
    BorrowedFrames frames(viewsOf(video, width, height, fps, format));
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

bool closeReport(platform::ReportFile &f, const std::string &path, std::string &error)
{
    if (f.close())
        return true;
    error = "cannot write " + path;
    return false;
}

bool closeAndPlot(platform::ReportFile &g, const std::string &script, std::string &error,
                  std::string &note)
{
    if (!closeReport(g, script, error))
        return false;
    note = platform::plotStatusNote(platform::runGnuplot(script));
    return true;
}

} // namespace depthtouch::media::bench
