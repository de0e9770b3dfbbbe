/// \file
/// \brief The encode's outputs and its rendition ladder (see encode_outputs.h).

#include "encode_outputs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "depthtouch/platform/file_access.h"

namespace depthtouch::media::detail {

namespace {

/// \return \a r with every rate and the buffer times \a k (a smaller rendition's share).
RateControl scaled(RateControl r, double k)
{
    const auto times = [k](long long v) {
        return v > 0 ? std::max(1LL, std::llround(static_cast<double>(v) * k)) : 0;
    };
    r.bitRate = times(r.bitRate);
    r.maxRate = times(r.maxRate);
    r.bufSize = times(r.bufSize);
    return r;
}

/// Bits per pixel and frame of color and depth together, for a rendition's BANDWIDTH before its
/// first segment is measured: a guess on the high side (the kitchen's depth alone needs 0.074 at
/// 1080p and CRF 18, docs/benchmarks.md "The depth codecs compared"; the synthetic head's ladder
/// here measured 0.05 to 0.07 for both streams), replaced once a segment is complete.
constexpr double kEstimatedBitsPerPixel = 0.3;

} // namespace

int keyFrameInterval(const EncodeOptions &options, Container container, double fps)
{
    // A live stream and HLS segments: a key frame every segment (where a receiver can join, where
    // a segment can end).
    if (options.gop == 0 && (options.paced || container == Container::Hls))
        return std::max(1, static_cast<int>(std::lround(MuxerOptions::kHlsSegmentSeconds * fps)));
    return options.gop;
}

Result<void> openOutputs(const EncodeOptions &options, const std::string &output,
                         const ColorShape &shape, double rateScale,
                         const std::vector<std::pair<std::string, std::string>> &tags,
                         bool material, Outputs &out)
{
    MuxerOptions mo;
    mo.output = output;
    mo.container = options.container.value_or(containerForOutput(options.output));
    mo.tags = tags;
    mo.live = options.paced;
    mo.muxRate = options.muxRate;
    auto muxer = Muxer::open(mo);
    if (!muxer)
        return unexpected(muxer.error());
    out.muxer = std::move(*muxer);

    VideoEncoderConfig cc = colorStreamConfig(shape.width, shape.height, shape.fps, options.crf,
                                              options.preset, options.threads);
    cc.gop = keyFrameInterval(options, mo.container, shape.fps);
    cc.rate = scaled(options.colorRate, rateScale);
    auto colorEnc = VideoEncoder::create(cc, *out.muxer);
    if (!colorEnc)
        return unexpected(colorEnc.error());
    out.color = std::move(*colorEnc);

    VideoEncoderConfig dc = cc;
    dc.codec = options.depthCodec;
    dc.crf = options.depthCrf;
    dc.lossless = options.depthLossless;
    dc.rate = scaled(options.depthRate, rateScale);
    dc.title = "depth";
    dc.tags = tags;
    auto depthEnc = VideoEncoder::create(dc, *out.muxer);
    if (!depthEnc)
        return unexpected(depthEnc.error());
    out.depth = std::move(*depthEnc);
    if (material) {
        auto materialEnc = VideoEncoder::create(materialStreamConfig(cc), *out.muxer);
        if (!materialEnc)
            return unexpected(materialEnc.error());
        out.material = std::move(*materialEnc);
    }
    if (!options.audioSource.empty()) {
        auto audio = AudioTrack::open(options.audioSource, options.audioFromPicture, *out.muxer);
        if (!audio)
            return unexpected(audio.error());
        if (!*audio && options.audioRequired)
            return unexpected(Errc::InvalidArgument, "The --audio source has no audio stream");
        out.audio = std::move(*audio);
    }
    return out.muxer->start();
}

EncodeOutputs::~EncodeOutputs()
{
    if (!finished_ && !master_.empty())
        (void)std::remove(master_.c_str());
}

Result<void> EncodeOutputs::open(const EncodeOptions &options, const ColorShape &shape,
                                 const std::vector<std::pair<std::string, std::string>> &tags,
                                 bool material, bool metric,
                                 const std::optional<depth::DepthRange> &range)
{
    shape_ = shape;
    std::vector<RenditionPlan> plans;
    if (options.renditions.empty()) {
        plans.push_back(RenditionPlan{shape.width, shape.height, options.output, options.output});
    } else {
        auto planned =
            planRenditions(options.output, options.renditions, shape.width, shape.height);
        if (!planned)
            return unexpected(planned.error());
        plans = std::move(*planned);
        master_ = options.output;
        // The HLS muxer ends a segment at the first key frame at least kHlsSegmentSeconds in.
        const double keyInterval = keyFrameInterval(options, Container::Hls, shape.fps) / shape.fps;
        segmentSeconds_ =
            std::ceil(MuxerOptions::kHlsSegmentSeconds / keyInterval - 1e-9) * keyInterval;
    }
    static const EncodeCallbacks kQuiet{};
    renditions_ = std::vector<Rendition>(plans.size());
    for (std::size_t i = 0; i < plans.size(); ++i) {
        Rendition &r = renditions_[i];
        r.plan = plans[i];
        const ColorShape own{r.plan.width, r.plan.height, shape.fps};
        const double scale = static_cast<double>(own.width) * own.height /
                             (static_cast<double>(shape.width) * shape.height);
        if (own.width != shape.width || own.height != shape.height)
            r.pipeline = std::make_unique<DepthPipeline>(options, own.width, own.height, metric,
                                                         range, kQuiet);
        DT_TRY(openOutputs(options, r.plan.playlist, own, scale, tags, material, r.out));
    }
    if (!master_.empty())
        DT_TRY(writeMultivariant(0.0, false));
    return ok();
}

Result<void> EncodeOutputs::encode(const Image &color, const Image &depthFrame, const Image &depth,
                                   const Image *material, double pts, double until)
{
    for (Rendition &r : renditions_) {
        const int w = r.plan.width;
        const int h = r.plan.height;
        if (!r.pipeline) {
            DT_TRY(r.out.color->encode(color, pts));
            DT_TRY(r.out.depth->encode(depth, pts));
            if (material != nullptr)
                DT_TRY(r.out.material->encode(*material, pts));
        } else {
            auto c = r.colorScaler.convert(color, PixelFormat::Rgb24, w, h);
            if (!c)
                return unexpected(c.error());
            DT_TRY(r.out.color->encode(*c, pts));
            auto d = r.pipeline->process(depthFrame, r.scratch);
            if (!d)
                return unexpected(d.error());
            DT_TRY(r.out.depth->encode(*d, pts));
            if (material != nullptr) {
                auto m = r.materialScaler.resize(*material, w, h);
                if (!m)
                    return unexpected(m.error());
                DT_TRY(r.out.material->encode(*m, pts));
            }
        }
        if (r.out.audio)
            DT_TRY(r.out.audio->writeUntil(until));
    }
    if (!master_.empty()) {
        long long segments = 0;
        for (const Rendition &r : renditions_)
            segments += r.out.muxer->segmentsCompleted();
        if (segments != segmentsSeen_) {
            segmentsSeen_ = segments;
            DT_TRY(writeMultivariant(until, false));
        }
    }
    return ok();
}

Result<void> EncodeOutputs::finish(EncodeSummary &summary, double duration)
{
    for (Rendition &r : renditions_) {
        DT_TRY(r.out.color->flush());
        DT_TRY(r.out.depth->flush());
        summary.colorBytes += r.out.color->bytes();
        summary.depthBytes += r.out.depth->bytes();
        if (r.out.material) {
            DT_TRY(r.out.material->flush());
            summary.materialBytes += r.out.material->bytes();
        }
        if (r.out.audio) {
            DT_TRY(r.out.audio->finish(duration));
            summary.audio = r.out.audio->description();
            summary.audioBytes += r.out.audio->bytes();
        }
        // The encoders refer to the muxer's streams: they go first.
        r.out.color.reset();
        r.out.depth.reset();
        r.out.material.reset();
        r.out.audio.reset();
        DT_TRY(r.out.muxer->finish());
    }
    if (!master_.empty())
        DT_TRY(writeMultivariant(duration, true));
    finished_ = true;
    for (std::size_t i = 0; i < renditions_.size() && !master_.empty(); ++i) {
        const RenditionPlan &p = renditions_[i].plan;
        summary.renditions.push_back(
            RenditionSummary{p.width, p.height, p.playlist, rates_[i].peak, rates_[i].average});
    }
    return ok();
}

Result<void> EncodeOutputs::writeMultivariant(double duration, bool final)
{
    rates_.assign(renditions_.size(), RenditionRate{});
    for (std::size_t i = 0; i < renditions_.size(); ++i) {
        const Rendition &r = renditions_[i];
        const std::vector<long long> bytes = r.out.muxer->segmentBytes();
        std::vector<double> seconds(bytes.size(), segmentSeconds_);
        if (final && !seconds.empty()) // the last segment: what the duration leaves of its own
            seconds.back() = std::max(
                duration - segmentSeconds_ * (std::ceil(duration / segmentSeconds_ - 1e-9) - 1.0),
                1e-3);
        RenditionRate &rate = rates_[i];
        rate.peak = peakBitRate(bytes, seconds, segmentSeconds_);
        double total = 0.0;
        double span = 0.0;
        for (std::size_t k = 0; k < bytes.size(); ++k) {
            total += 8.0 * static_cast<double>(bytes[k]);
            span += seconds[k];
        }
        if (span > 0.0)
            rate.average = std::llround(total / span);
        if (rate.peak == 0) // before its first segment: an estimate
            rate.peak =
                std::llround(kEstimatedBitsPerPixel * r.plan.width * r.plan.height * shape_.fps);
    }
    std::vector<RenditionPlan> plans;
    for (const Rendition &r : renditions_)
        plans.push_back(r.plan);
    auto written =
        platform::writeOutputFile(master_, multivariantPlaylist(plans, rates_, shape_.fps));
    if (!written)
        return unexpected(Errc::Io, "Failed to write the multivariant playlist",
                          written.error().sysErrno);
    return ok();
}

} // namespace depthtouch::media::detail
