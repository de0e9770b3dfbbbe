/// \file
/// \brief The depth half of the encode pipeline (see depth_pipeline.h).

#include "depth_pipeline.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "depthtouch/depth/fill.h"
#include "depthtouch/depth/resample.h"
#include "depthtouch/scene/depth_frame.h"

namespace depthtouch::media::detail {

namespace {

/// \return the nearness (levels of 0..\a vmax) and holes of \a frame, a DepthTouch file's depth
/// (Gray8 or Gray16 codes) with hole threshold \a holeBelow in its units, read as play reads it
/// (scene::DepthFrameView): a code below holeBelow is a hole (nearness 0, valid 0), measured
/// codes farCode()..v_max span nearness 0..\a vmax (codes in the guard band are the far plane).
/// Errors: InvalidArgument for an empty frame or a threshold that leaves no measured code.
Result<depth::NearnessFrame> nearnessOfCodes(const Image &frame, std::uint32_t holeBelow,
                                             double vmax)
{
    scene::DepthFrameView v;
    v.data = frame.data.data();
    v.width = frame.width;
    v.height = frame.height;
    v.strideBytes = frame.stride;
    v.format = frame.format == PixelFormat::Gray16 ? scene::SampleFormat::Gray16
                                                   : scene::SampleFormat::Gray8;
    v.holeBelow = holeBelow;
    if (frame.empty() || frame.format == PixelFormat::Rgb24)
        return unexpected(Errc::InvalidArgument, "Empty depth frame");
    DT_TRY(v.validate());
    const auto far = static_cast<double>(v.farCode());
    const double k = vmax / (scene::maxSampleValue(v.format) - far);
    depth::NearnessFrame n;
    n.nearness = depth::Plane<float>(v.width, v.height);
    n.valid = depth::Plane<std::uint8_t>(v.width, v.height);
    for (int r = 0; r < v.height; ++r)
        for (int c = 0; c < v.width; ++c) {
            const bool measured = v.measured(c, r);
            const double code = static_cast<double>(v.sample(c, r));
            n.nearness.at(c, r) =
                measured ? static_cast<float>(std::max(0.0, code - far) * k) : 0.f;
            n.valid.at(c, r) = measured ? 1 : 0;
            n.invalidCount += measured ? 0u : 1u;
        }
    return n;
}

} // namespace

int depthBitsOf(VideoCodec codec) noexcept
{
    switch (codec) {
    case VideoCodec::H264Gray10:
    case VideoCodec::HevcMain10:
        return 10;
    case VideoCodec::Ffv1Gray16:
        return 16;
    default:
        return 8;
    }
}

DepthPipeline::DepthPipeline(const EncodeOptions &o, int width, int height, bool metric,
                             std::optional<depth::DepthRange> range, const EncodeCallbacks &cb)
    : options_(o), callbacks_(cb), width_(width), height_(height), metric_(metric),
      inputHoleBelow_(metric ? 0u : o.depthInputHoleBelow.value_or(0u)),
      bits_(depthBitsOf(o.depthCodec)), vmax_(std::ldexp(1.0, bits_) - 1.0), range_(range)
{
    if ((metric_ || inputHoleBelow_ > 0) && !o.fillHoles)
        occ_ =
            depth::occupancyFor(bits_, o.depthLossless || o.depthCodec == VideoCodec::Ffv1Gray16);
    const auto k = static_cast<float>(vmax_ / 255.0);
    enhance_ = o.enhanceOptions;
    enhance_.sampling.tolerance *= k;
    enhance_.smoothing.edgeThreshold *= k;
    enhance_.measure.flatGradient *= k;
    enhance_.measure.edgeGradient *= k;
}

Result<bool> DepthPipeline::toNearness(const Image &frame, depth::Plane<float> &nearness,
                                       depth::Plane<std::uint8_t> &valid, EncodeSummary &summary)
{
    if (!metric_ && (inputHoleBelow_ > 0 || frame.format == PixelFormat::Gray16)) {
        auto n = nearnessOfCodes(frame, inputHoleBelow_, vmax_);
        if (!n)
            return unexpected(n.error());
        return keepOrFill(*n, nearness, valid, summary);
    }
    if (!metric_) {
        const depth::Plane<std::uint8_t> p8 = toPlane8(frame);
        if (p8.empty())
            return unexpected(Errc::InvalidArgument, "Empty depth frame");
        nearness = depth::Plane<float>(p8.width, p8.height);
        const auto k = static_cast<float>(vmax_ / 255.0);
        for (std::size_t i = 0; i < p8.size(); ++i)
            nearness.samples[i] = static_cast<float>(p8.samples[i]) * k;
        return true;
    }
    depth::ConvertOptions co;
    co.raw = options_.raw;
    co.mapping = options_.mapping;
    co.vmax = vmax_;
    co.range = range_;
    auto n = depth::metricToNearness(toPlane16(frame), co);
    if (!n)
        return unexpected(n.error());
    return keepOrFill(*n, nearness, valid, summary);
}

Result<bool> DepthPipeline::keepOrFill(depth::NearnessFrame &n, depth::Plane<float> &nearness,
                                       depth::Plane<std::uint8_t> &valid, EncodeSummary &summary)
{
    const bool keepHoles = occ_.threshold > 0;
    if (n.invalidCount == n.valid.size() && !keepHoles) {
        // Nothing to fill from: hold the last good depth rather than invent a far plane.
        if (last_.empty())
            return unexpected(Errc::InvalidArgument, "The first depth frame has no valid sample");
        ++summary.repeatedFrames;
        return false;
    }
    if (n.invalidCount > 0 && keepHoles) {
        valid = std::move(n.valid);
    } else if (n.invalidCount > 0) {
        auto filled = depth::fillInvalid(n.nearness, n.valid);
        if (!filled)
            return unexpected(filled.error());
        summary.filledSamples += static_cast<long long>(*filled);
    }
    nearness = std::move(n.nearness);
    return true;
}

Result<void> DepthPipeline::resampleToGrid(depth::Plane<float> &nearness,
                                           depth::Plane<std::uint8_t> &valid,
                                           EncodeSummary &summary)
{
    if (nearness.width == width_ && nearness.height == height_)
        return ok();
    if (!summary.depthResampled && callbacks_.warning)
        callbacks_.warning("depth is " + std::to_string(nearness.width) + "x" +
                           std::to_string(nearness.height) + ", resampled to the " +
                           std::to_string(width_) + "x" + std::to_string(height_) +
                           " output grid (edge-aware)");
    summary.depthResampled = true;
    const auto edge = static_cast<float>(4.0 * vmax_ / 255.0);
    if (!valid.empty()) {
        depth::Plane<std::uint8_t> validOut;
        auto r = depth::resampleMasked(nearness, valid, width_, height_, edge, validOut);
        if (!r)
            return unexpected(r.error());
        nearness = std::move(*r);
        valid = std::move(validOut);
        return ok();
    }
    auto r = depth::resample(nearness, width_, height_, depth::ResampleMethod::EdgeAware, edge);
    if (!r)
        return unexpected(r.error());
    nearness = std::move(*r);
    return ok();
}

Result<void> DepthPipeline::enhanceFrame(depth::Plane<float> &nearness,
                                         const depth::Plane<std::uint8_t> &valid,
                                         EncodeSummary &summary)
{
    const bool holes = !valid.empty();
    if (holes && std::find(valid.samples.begin(), valid.samples.end(), 1) == valid.samples.end())
        return ok(); // all holes: no surface to enhance
    if (holes) {
        // The filter needs a surface everywhere: fill a copy, enhance it, keep the holes after
        // (quantizeOccupied() writes them as holes whatever the enhanced value there).
        if (auto filled = depth::fillInvalid(nearness, valid); !filled)
            return unexpected(filled.error());
    }
    auto e = depth::enhance(nearness, enhance_);
    if (!e)
        return unexpected(e.error());
    accumulate(e->report, summary);
    nearness = std::move(e->depth);
    return ok();
}

Result<Image> DepthPipeline::process(const Image &frame, EncodeSummary &summary)
{
    depth::Plane<float> nearness;
    depth::Plane<std::uint8_t> valid; // empty: no hole
    auto fresh = toNearness(frame, nearness, valid, summary);
    if (!fresh)
        return unexpected(fresh.error());
    if (!*fresh)
        return last_;
    DT_TRY(resampleToGrid(nearness, valid, summary));
    if (options_.enhance)
        DT_TRY(enhanceFrame(nearness, valid, summary));
    std::size_t holes = 0;
    const depth::Plane<std::uint16_t> q =
        depth::quantizeOccupied(nearness, valid, vmax_, occ_, holes);
    summary.holeSamples += static_cast<long long>(holes);
    summary.depthSamples += static_cast<long long>(q.size());
    Image out;
    if (bits_ == 8) {
        out = Image::make(q.width, q.height, PixelFormat::Gray8);
        for (int y = 0; y < q.height; ++y) {
            std::uint8_t *row = out.row(y);
            for (int x = 0; x < q.width; ++x)
                row[x] = static_cast<std::uint8_t>(q.at(x, y));
        }
    } else {
        out = fromPlane(q);
    }
    last_ = out;
    return out;
}

void DepthPipeline::accumulate(const depth::EnhanceReport &r, EncodeSummary &summary)
{
    if (!summary.enhance) {
        summary.enhance = EnhanceTotals{};
        summary.enhance->levelsMax = vmax_;
    }
    EnhanceTotals &t = *summary.enhance;
    const auto n = static_cast<double>(t.frames);
    const auto px = static_cast<double>(r.pixels);
    const double prevPx = static_cast<double>(t.pixels);
    // Pixel-weighted means of the error; frame means of the surface measures.
    t.meanAbsError = (t.meanAbsError * prevPx + r.meanAbsError * px) / (prevPx + px);
    const double sq = t.rmsError * t.rmsError * prevPx + r.rmsError * r.rmsError * px;
    t.rmsError = std::sqrt(sq / (prevPx + px));
    t.maxAbsError = std::max(t.maxAbsError, r.maxAbsError);
    t.roughnessInput = (t.roughnessInput * n + r.input.roughness) / (n + 1.0);
    t.roughnessOutput = (t.roughnessOutput * n + r.enhanced.roughness) / (n + 1.0);
    t.edgeContrastInput = (t.edgeContrastInput * n + r.input.edgeContrast) / (n + 1.0);
    t.edgeContrastOutput = (t.edgeContrastOutput * n + r.enhanced.edgeContrast) / (n + 1.0);
    t.pixels += static_cast<long long>(r.pixels);
    t.points += static_cast<long long>(r.points);
    ++t.frames;
}

} // namespace depthtouch::media::detail
