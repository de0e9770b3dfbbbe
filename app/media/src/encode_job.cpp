/// \file
/// \brief The sender's encode pipeline (see encode_job.h).

#include "depthtouch/media/encode_job.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <utility>
#include <vector>

#include "depthtouch/media/material_track.h"
#include "depthtouch/platform/clock.h"
#include "depth_pipeline.h"
#include "encode_outputs.h"

namespace depthtouch::media {

namespace {

constexpr std::size_t kMaxRenditions = 8; ///< Apple's ladders have up to 8 or 9 video rungs.

std::string number(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

/// The rate options of one stream (\a depth: the --depth- ones).
Result<void> validateRate(const RateControl &r, bool depth)
{
    if (r.bitRate < 0 || r.maxRate < 0 || r.bufSize < 0)
        return unexpected(Errc::InvalidArgument, "Bit rates and buffer sizes must be >= 0");
    if (r.maxRate > 0 && r.bufSize == 0)
        return unexpected(Errc::InvalidArgument,
                          depth ? "--depth-maxrate needs --depth-bufsize (the VBV buffer it drains)"
                                : "--maxrate needs --bufsize (the VBV buffer it drains)");
    if (r.bufSize > 0 && r.maxRate == 0)
        return unexpected(Errc::InvalidArgument, depth ? "--depth-bufsize needs --depth-maxrate"
                                                       : "--bufsize needs --maxrate");
    if (r.maxRate > 0 && r.bitRate > r.maxRate)
        return unexpected(Errc::InvalidArgument,
                          depth ? "--depth-maxrate must be at least --depth-bitrate"
                                : "--maxrate must be at least --bitrate");
    return ok();
}

/// The bit-rate options together: each stream's, lossless depth's, the mux rate's container and
/// its floor (the streams' peak rates, when both are bounded).
Result<void> validateRates(const EncodeOptions &o, Container c)
{
    if (o.gop < 0 || o.gop > 100000)
        return unexpected(Errc::InvalidArgument, "--gop must be in 0..100000 frames");
    if (auto v = validateRate(o.colorRate, false); !v)
        return v;
    if (auto v = validateRate(o.depthRate, true); !v)
        return v;
    const RateControl &d = o.depthRate;
    if ((d.bitRate > 0 || d.maxRate > 0) &&
        (o.depthLossless || o.depthCodec == VideoCodec::Ffv1Gray16))
        return unexpected(Errc::InvalidArgument, "--depth-bitrate and --depth-maxrate apply to "
                                                 "lossy depth only (not --depth-lossless or "
                                                 "--depth-bits 16)");
    if (o.muxRate < 0)
        return unexpected(Errc::InvalidArgument, "--muxrate must be >= 0");
    if (o.muxRate > 0 && c != Container::MpegTs)
        return unexpected(Errc::InvalidArgument,
                          "--muxrate needs an MPEG-TS output (.ts, udp://, srt://)");
    const long long colorPeak = o.colorRate.maxRate;
    const long long depthPeak = d.maxRate;
    if (o.muxRate > 0 && colorPeak > 0 && depthPeak > 0 && o.muxRate <= colorPeak + depthPeak)
        return unexpected(
            Errc::InvalidArgument,
            "--muxrate must exceed --maxrate + --depth-maxrate (and the TS overhead)");
    return ok();
}

/// The ladder's heights: even, tallest first, distinct, for an HLS file output.
Result<void> validateRenditions(const std::vector<int> &heights, const std::string &output,
                                Container c)
{
    if (heights.empty())
        return ok();
    if (c != Container::Hls || isOutputUrl(output))
        return unexpected(Errc::InvalidArgument,
                          "--renditions needs an HLS output file (.m3u8, not a URL)");
    if (heights.size() > kMaxRenditions)
        return unexpected(Errc::InvalidArgument, "--renditions takes at most 8 heights");
    for (std::size_t i = 0; i < heights.size(); ++i) {
        if (heights[i] < 16 || heights[i] > 8192 || heights[i] % 2 != 0)
            return unexpected(Errc::InvalidArgument,
                              "--renditions heights must be even, 16..8192 pixels");
        if (i > 0 && heights[i] >= heights[i - 1])
            return unexpected(Errc::InvalidArgument,
                              "--renditions heights must be given tallest first, each once");
    }
    return ok();
}

} // namespace

Result<void> EncodeOptions::validate() const
{
    if (output.empty())
        return unexpected(Errc::InvalidArgument, "No output given");
    if (crf < 0 || crf > 51)
        return unexpected(Errc::InvalidArgument, "--crf must be in 0..51");
    if (depthCrf < 0 || depthCrf > 51)
        return unexpected(Errc::InvalidArgument, "--depth-crf must be in 0..51");
    if (threads < 0)
        return unexpected(Errc::InvalidArgument, "--threads must be >= 0");
    if (width < 0 || height < 0 || (width == 0) != (height == 0) || width % 2 != 0 ||
        height % 2 != 0)
        return unexpected(Errc::InvalidArgument, "--size must be WxH, even");
    if (width > 0 && !isEncodableSize(width, height))
        return unexpected(Errc::InvalidArgument,
                          "--size is beyond H.264's largest frame (139264 macroblocks, e.g. "
                          "8192x4352)");
    if (maxFrames < 0)
        return unexpected(Errc::InvalidArgument, "--frames must be >= 0");
    if (!(maxDuration >= 0.0) || !std::isfinite(maxDuration))
        return unexpected(Errc::InvalidArgument, "--duration must be >= 0 seconds");
    if (!(raw.metresPerUnit > 0.0) || !std::isfinite(raw.metresPerUnit))
        return unexpected(Errc::InvalidArgument, "--depth-scale must be positive");
    if (range && !(range->nearM > 0.0 && range->nearM < range->farM && std::isfinite(range->farM)))
        return unexpected(Errc::InvalidArgument, "--near and --far must satisfy 0 < near < far");
    if (rangeFrames < 1)
        return unexpected(Errc::InvalidArgument, "The robust range needs at least one frame");
    if (depthCodec == VideoCodec::H264Yuv420p || depthCodec == VideoCodec::H264Rgb)
        return unexpected(Errc::InvalidArgument,
                          "Depth codec must be gray, gray10, hevc main10 or ffv1");
    if (enhance && !(enhanceOptions.sampling.tolerance > 0.0f))
        return unexpected(Errc::InvalidArgument, "--enhance-tolerance must be positive");
    const Container c = container.value_or(containerForOutput(output));
    if (auto v = validateRenditions(renditions, output, c); !v)
        return v;
    if (depthCodec == VideoCodec::Ffv1Gray16 && c != Container::Matroska)
        return unexpected(Errc::InvalidArgument, "FFV1 gray16 depth needs an MKV output");
    return validateRates(*this, c);
}

std::vector<std::pair<std::string, std::string>>
depthTags(const std::optional<depth::DepthRange> &range, depth::DepthMapping mapping, int bits,
          std::uint32_t occupancy)
{
    std::vector<std::pair<std::string, std::string>> tags = {
        {"depth_near", range ? number(range->nearM) : std::string("unknown")},
        {"depth_far", range ? number(range->farM) : std::string("unknown")},
        {"depth_mapping", depth::mappingName(mapping)},
        {"depth_bits", std::to_string(bits)},
    };
    if (occupancy > 0)
        tags.emplace_back("depth_occupancy", std::to_string(occupancy));
    return tags;
}

namespace {

using detail::ColorShape;

/// A color and a depth frame read together.
struct Pair {
    SourceFrame color;
    SourceFrame depth;
};

/// \return the encoded size (--size or the color's) and rate of \a color, checked for 4:2:0
/// H.264.
Result<ColorShape> colorShape(FrameSource &color, const EncodeOptions &options)
{
    int width = options.width > 0 ? options.width : color.info().width;
    int height = options.height > 0 ? options.height : color.info().height;
    if (!options.renditions.empty() && height > 0) {
        // A ladder is encoded at its tallest rendition; the others are made from that.
        auto plans = detail::planRenditions(options.output, options.renditions, width, height);
        if (!plans)
            return unexpected(plans.error());
        width = plans->front().width;
        height = plans->front().height;
    }
    if (width % 2 != 0 || height % 2 != 0)
        return unexpected(Errc::InvalidArgument,
                          "Color is an odd size; 4:2:0 needs even sizes (use --size)");
    if (width <= 0 || height <= 0)
        return unexpected(Errc::InvalidArgument, "Color has no size");
    if (!isEncodableSize(width, height))
        return unexpected(Errc::InvalidArgument,
                          "The color input is beyond H.264's largest frame (139264 macroblocks, "
                          "e.g. 8192x4352): give a smaller --size");
    const double fps = color.info().fps > 0.0 ? color.info().fps : 30.0;
    if (!(fps >= kMinEncodeFps) || fps > kMaxEncodeFps)
        return unexpected(Errc::InvalidArgument,
                          "The color input's frame rate is outside 0.1..1000 frames/s");
    return ColorShape{width, height, fps};
}

/// Reads the next color and depth frame into \a out. \return false at the end of an input, with
/// \a endedBy naming it ("color" or "depth").
Result<bool> readPair(FrameSource &color, FrameSource &depth, const ColorShape &shape,
                      PixelFormat depthLayout, std::deque<Pair> &out, const char *&endedBy)
{
    auto c = color.next(PixelFormat::Rgb24, shape.width, shape.height);
    if (!c && c.error().code == Errc::EndOfStream) {
        endedBy = "color";
        return false;
    }
    if (!c)
        return unexpected(c.error());
    auto d = depth.next(depthLayout);
    if (!d && d.error().code == Errc::EndOfStream) {
        endedBy = "depth";
        return false;
    }
    if (!d)
        return unexpected(d.error());
    out.push_back(Pair{std::move(*c), std::move(*d)});
    return true;
}

/// Nearness from a DepthTouch file keeps the planes and mapping it was made with: sets \a range
/// and \a mapping from the tags of \a depth when they are valid.
void rangeFromTags(const FrameSource &depth, std::optional<depth::DepthRange> &range,
                   depth::DepthMapping &mapping)
{
    const std::string *nearTag = depth.info().tag("depth_near");
    const std::string *farTag = depth.info().tag("depth_far");
    const std::string *mapTag = depth.info().tag("depth_mapping");
    char *endNear = nullptr;
    char *endFar = nullptr;
    if (nearTag != nullptr && farTag != nullptr) {
        const double n = std::strtod(nearTag->c_str(), &endNear);
        const double f = std::strtod(farTag->c_str(), &endFar);
        if (*endNear == '\0' && *endFar == '\0' && n > 0.0 && n < f && std::isfinite(f))
            range = depth::DepthRange{n, f};
    }
    if (range && mapTag != nullptr) {
        if (auto m = depth::parseMapping(*mapTag))
            mapping = *m;
    }
}

/// \return the robust near/far planes of the metric depth frames of \a ahead, taken together.
Result<depth::RangeEstimate> robustRangeOf(const std::deque<Pair> &ahead,
                                           const EncodeOptions &options)
{
    depth::Plane<std::uint16_t> all;
    for (const Pair &p : ahead) {
        const depth::Plane<std::uint16_t> raw = toPlane16(p.depth.image);
        all.samples.insert(all.samples.end(), raw.samples.begin(), raw.samples.end());
    }
    all.width = static_cast<int>(all.samples.size());
    all.height = 1;
    auto r = depth::estimateRange(all, options.raw);
    if (!r)
        return unexpected(Errc::InvalidArgument,
                          "The first depth frames have no valid sample to take near/far from");
    return *r;
}

/// Reads up to \a count pairs (no more than --frames) into \a ahead. Errors: InvalidArgument
/// when an input has no frame.
Result<void> lookAhead(FrameSource &color, FrameSource &depth, const EncodeOptions &options,
                       const ColorShape &shape, PixelFormat depthLayout, int count,
                       std::deque<Pair> &ahead)
{
    for (int i = 0; i < count; ++i) {
        if (options.maxFrames > 0 && i >= options.maxFrames)
            break;
        const char *endedBy = nullptr;
        auto read = readPair(color, depth, shape, depthLayout, ahead, endedBy);
        if (!read)
            return unexpected(read.error());
        if (!*read)
            break;
    }
    if (ahead.empty())
        return unexpected(Errc::InvalidArgument, "An input has no frame");
    return ok();
}

/// Completes \a range and \a mapping when the options leave them open: from the tags of a
/// nearness input, or from the robust range of the metric frames of \a ahead (\a estimate: what
/// that range was taken from).
Result<void> chooseRange(const FrameSource &depth, const std::deque<Pair> &ahead,
                         const EncodeOptions &options, bool metric,
                         std::optional<depth::DepthRange> &range, depth::DepthMapping &mapping,
                         std::optional<depth::RangeEstimate> &estimate)
{
    if (!metric && !range)
        rangeFromTags(depth, range, mapping);
    if (metric && !range) {
        auto r = robustRangeOf(ahead, options);
        if (!r)
            return unexpected(r.error());
        range = r->range;
        estimate = *r;
    }
    return ok();
}

/// Calls the progress callback of \a callbacks.
void reportProgress(const EncodeCallbacks &callbacks, long long frames, long long expected,
                    double elapsed, double pts)
{
    EncodeProgress p;
    p.frames = frames;
    p.totalFrames = expected;
    p.elapsed = elapsed;
    p.pts = pts;
    callbacks.progress(p);
}

/// Waits until \a pts seconds after \a start (the media rate of a paced output), in steps of at
/// most 50 ms so that \a stopped() ends the wait promptly. \return false when stopped.
template <class Stopped>
bool waitForMediaTime(platform::Clock &clock, platform::TimePoint start, double pts,
                      const Stopped &stopped)
{
    for (;;) {
        if (stopped())
            return false;
        const double ahead = pts - platform::toSeconds(clock.now() - start);
        if (ahead <= 0.0)
            return true;
        clock.sleepFor(platform::fromSeconds(std::min(ahead, 0.05)));
    }
}

/// \return the frames the encode is expected to write (for progress), 0 or less when unknown.
long long expectedFrames(FrameSource &color, FrameSource &depth, const EncodeOptions &options,
                         double fps)
{
    long long expected = std::min(color.info().frameCount, depth.info().frameCount);
    if (expected <= 0)
        expected = std::max(color.info().frameCount, depth.info().frameCount);
    if (options.maxFrames > 0 && (expected <= 0 || options.maxFrames < expected))
        expected = options.maxFrames;
    if (options.maxDuration > 0.0) {
        const auto byDuration = static_cast<long long>(std::ceil(options.maxDuration * fps));
        if (expected <= 0 || byDuration < expected)
            expected = byDuration;
    }
    return expected;
}

} // namespace

Result<EncodeSummary> encodeStreams(FrameSource &color, FrameSource &depth,
                                    const EncodeOptions &options, const std::atomic<bool> *stop,
                                    const EncodeCallbacks &callbacks)
{
    return encodeStreams(color, depth, nullptr, options, stop, callbacks);
}

Result<EncodeSummary> encodeStreams(FrameSource &color, FrameSource &depth, FrameSource *material,
                                    const EncodeOptions &options, const std::atomic<bool> *stop,
                                    const EncodeCallbacks &callbacks)
{
    DT_TRY(options.validate());
    platform::SteadyClock &clock = platform::SteadyClock::instance();
    const platform::TimePoint start = clock.now();
    const auto stopped = [stop] {
        return stop != nullptr && stop->load(std::memory_order_relaxed);
    };

    EncodeSummary summary;
    auto shapeOk = colorShape(color, options);
    if (!shapeOk)
        return unexpected(shapeOk.error());
    const ColorShape shape = *shapeOk;
    const double fps = shape.fps;

    // Depth layout: 16-bit samples are metric depth, or a DepthTouch file's deep nearness read as
    // 16 bits; anything else gives 8-bit nearness (the luma of a color-format depth video).
    const bool deep = depth.info().nativeFormat == PixelFormat::Gray16;
    const bool metric = deep && !options.depthInputHoleBelow;
    const PixelFormat depthLayout = deep ? PixelFormat::Gray16 : PixelFormat::Gray8;

    // Look ahead: the first frames decide the near/far planes once for the whole file.
    std::deque<Pair> ahead;
    const int lookahead = metric && !options.range ? options.rangeFrames : 1;
    DT_TRY(lookAhead(color, depth, options, shape, depthLayout, lookahead, ahead));

    std::optional<depth::DepthRange> range = options.range;
    depth::DepthMapping mapping = options.mapping;
    DT_TRY(chooseRange(depth, ahead, options, metric, range, mapping, summary.rangeEstimate));
    summary.metric = metric;
    if (range)
        summary.range = *range;

    detail::DepthPipeline pipeline(options, shape.width, shape.height, metric, range, callbacks);
    summary.depthBits = pipeline.bits();
    summary.depthOccupancy = pipeline.occupancy().threshold;

    // Output: container tags and streams, then the header.
    const auto tags = depthTags(range, mapping, pipeline.bits(), pipeline.occupancy().threshold);
    summary.mapping = mapping;
    detail::EncodeOutputs out;
    DT_TRY(out.open(options, shape, tags, material != nullptr, metric, range));
    std::optional<MaterialTrack> materials;
    if (material != nullptr)
        materials.emplace(*material);
    const long long expected = expectedFrames(color, depth, options, fps);

    double lastPts = -1.0;
    // A paced output leaves pair n at its PTS after the first pair left.
    platform::TimePoint paceOrigin = start;
    double firstPts = 0.0;
    for (;;) {
        if (stopped()) {
            summary.interrupted = true;
            summary.endedBy = "stop";
            break;
        }
        if (options.maxFrames > 0 && summary.frames >= options.maxFrames) {
            summary.endedBy = "frames";
            break;
        }
        if (ahead.empty()) {
            const char *endedBy = nullptr;
            auto read = readPair(color, depth, shape, depthLayout, ahead, endedBy);
            if (!read)
                return unexpected(read.error());
            if (!*read) {
                summary.endedBy = endedBy;
                break;
            }
        }
        Pair pair = std::move(ahead.front());
        ahead.pop_front();
        double pts = pair.color.pts;
        if (options.maxDuration > 0.0 && pts >= options.maxDuration - 1e-9) {
            summary.endedBy = "duration";
            break;
        }
        if (pts <= lastPts)
            pts = lastPts + 1.0 / fps;
        if (summary.frames == 0) {
            paceOrigin = clock.now();
            firstPts = pts;
        }
        if (options.paced && !waitForMediaTime(clock, paceOrigin, pts - firstPts, stopped)) {
            summary.interrupted = true;
            summary.endedBy = "stop";
            break;
        }
        auto depthImage = pipeline.process(pair.depth.image, summary);
        if (!depthImage)
            return unexpected(depthImage.error());
        std::optional<Image> materialImage;
        if (materials) {
            auto m = materials->next(shape.width, shape.height);
            if (!m)
                return unexpected(m.error());
            materialImage = std::move(*m);
        }
        lastPts = pts;
        summary.duration = pts + 1.0 / fps;
        DT_TRY(out.encode(pair.color.image, pair.depth.image, *depthImage,
                          materialImage ? &*materialImage : nullptr, pts, summary.duration));
        ++summary.frames;
        if (callbacks.progress)
            reportProgress(callbacks, summary.frames, expected,
                           platform::toSeconds(clock.now() - start), pts);
    }
    if (summary.frames == 0)
        return unexpected(Errc::InvalidArgument, "Nothing to encode (no frame pair)");
    DT_TRY(out.finish(summary, summary.duration));
    if (materials)
        summary.materialFrames = materials->framesRead();
    summary.elapsed = platform::toSeconds(clock.now() - start);
    return summary;
}

} // namespace depthtouch::media
