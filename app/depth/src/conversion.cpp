/// \file
/// \brief Metric depth → nearness conversion (see conversion.h).

#include "depthtouch/depth/conversion.h"

#include "depthtouch/depth/fill.h"
#include "depthtouch/depth/resample.h"
#include "depthtouch/platform/enum_names.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace depthtouch::depth {

const char *mappingName(DepthMapping mapping) noexcept
{
    static constexpr std::array<const char *, 2> kNames = {"inverse_z", "linear"};
    return platform::enumName(mapping, kNames, "inverse_z");
}

Result<DepthMapping> parseMapping(std::string_view text) noexcept
{
    if (text == "inverse_z" || text == "inverse" || text == "1/z" || text == "mpeg")
        return DepthMapping::InverseZ;
    if (text == "linear")
        return DepthMapping::Linear;
    return unexpected(Errc::InvalidArgument, "Unknown depth mapping (use inverse_z or linear)");
}

double metresToNearness(double zM, DepthRange range, DepthMapping mapping, double vmax) noexcept
{
    double t = 0.0;
    if (mapping == DepthMapping::InverseZ)
        t = (1.0 / zM - 1.0 / range.farM) / (1.0 / range.nearM - 1.0 / range.farM);
    else
        t = (range.farM - zM) / (range.farM - range.nearM);
    return std::clamp(t, 0.0, 1.0) * vmax;
}

double nearnessToMetres(double v, DepthRange range, DepthMapping mapping, double vmax) noexcept
{
    const double t = std::clamp(v / vmax, 0.0, 1.0);
    if (mapping == DepthMapping::InverseZ)
        return 1.0 / (t * (1.0 / range.nearM - 1.0 / range.farM) + 1.0 / range.farM);
    return range.farM - t * (range.farM - range.nearM);
}

Result<RangeEstimate> estimateRange(const Plane<std::uint16_t> &raw, const RawDepthFormat &format,
                                    double lowFraction, double highFraction)
{
    if (!(lowFraction >= 0.0 && lowFraction < highFraction && highFraction <= 1.0))
        return unexpected(Errc::InvalidArgument,
                          "Depth range quantiles must satisfy 0 <= low < high <= 1");
    if (!(format.metresPerUnit > 0.0))
        return unexpected(Errc::InvalidArgument, "Depth scale must be positive");
    // below[v]: valid samples with a raw value < v (a histogram's prefix sums: O(n), exact).
    std::vector<std::size_t> below(65537, 0);
    for (const std::uint16_t v : raw.samples)
        if (format.isValid(v))
            ++below[static_cast<std::size_t>(v) + 1];
    for (std::size_t v = 1; v < below.size(); ++v)
        below[v] += below[v - 1];
    const std::size_t n = below.back();
    if (n == 0)
        return unexpected(Errc::InvalidArgument, "No valid depth sample to estimate near/far from");

    // The k-th smallest valid value (0-based): the v with below[v] <= k < below[v + 1].
    const auto kth = [&below](std::size_t k) {
        const auto it = std::upper_bound(below.begin(), below.end(), k);
        return static_cast<std::size_t>(it - below.begin()) - 1;
    };
    const auto quantile = [&](double f) {
        return kth(static_cast<std::size_t>(std::lround(f * static_cast<double>(n - 1))));
    };
    const std::size_t lowV = quantile(lowFraction);
    const std::size_t highV = quantile(highFraction);
    // The far plane: the farthest value z <= highV whose step (z/1.1, z] holds kTailDensity of the
    // samples; a sample s is in it when 11 s > 10 z.
    std::size_t farV = highV;
    const auto need = static_cast<double>(n) * kTailDensity;
    for (std::size_t z = highV; z >= lowV && z > 0; --z) {
        if (below[z + 1] == below[z])
            continue;                               // no sample at z
        const std::size_t from = (10 * z) / 11 + 1; // smallest s with 11 s > 10 z
        if (static_cast<double>(below[z + 1] - below[from]) >= need) {
            farV = z;
            break;
        }
    }
    RangeEstimate e;
    e.medianM = static_cast<double>(quantile(0.5)) * format.metresPerUnit;
    e.quantileFarM = static_cast<double>(highV) * format.metresPerUnit;
    e.maxM = static_cast<double>(kth(n - 1)) * format.metresPerUnit;
    e.beyondFraction = static_cast<double>(n - below[farV + 1]) / static_cast<double>(n);
    e.tailCut = farV < highV;
    e.range = DepthRange{static_cast<double>(lowV) * format.metresPerUnit,
                         static_cast<double>(farV) * format.metresPerUnit};
    if (e.range.farM <= e.range.nearM * 1.0001) {
        const double mid = 0.5 * (e.range.nearM + e.range.farM);
        e.range = DepthRange{mid * 0.99, mid * 1.01};
    }
    return e;
}

Result<DepthRange> robustRange(const Plane<std::uint16_t> &raw, const RawDepthFormat &format,
                               double lowFraction, double highFraction)
{
    auto e = estimateRange(raw, format, lowFraction, highFraction);
    if (!e)
        return unexpected(e.error());
    return e->range;
}

Result<NearnessFrame> metricToNearness(const Plane<std::uint16_t> &raw,
                                       const ConvertOptions &options)
{
    if (raw.empty() || raw.width <= 0 || raw.height <= 0)
        return unexpected(Errc::InvalidArgument, "Empty depth frame");
    if (!(options.vmax > 0.0))
        return unexpected(Errc::InvalidArgument, "Nearness scale vmax must be positive");
    if (!(options.raw.metresPerUnit > 0.0))
        return unexpected(Errc::InvalidArgument, "Depth scale must be positive");

    NearnessFrame frame;
    if (options.range) {
        if (!(options.range->nearM > 0.0 && options.range->nearM < options.range->farM))
            return unexpected(Errc::InvalidArgument, "Depth planes must satisfy 0 < near < far");
        frame.range = *options.range;
    } else {
        auto r = robustRange(raw, options.raw, options.lowFraction, options.highFraction);
        if (!r)
            return unexpected(r.error());
        frame.range = *r;
    }

    frame.nearness = Plane<float>(raw.width, raw.height, 0.0f);
    frame.valid = Plane<std::uint8_t>(raw.width, raw.height, 0);
    for (std::size_t i = 0; i < raw.size(); ++i) {
        const std::uint16_t v = raw.samples[i];
        if (!options.raw.isValid(v)) {
            ++frame.invalidCount;
            continue;
        }
        const double z = static_cast<double>(v) * options.raw.metresPerUnit;
        frame.nearness.samples[i] =
            static_cast<float>(metresToNearness(z, frame.range, options.mapping, options.vmax));
        frame.valid.samples[i] = 1;
    }
    return frame;
}

NearnessFrame nearnessFrom8Bit(const Plane<std::uint8_t> &nearness8)
{
    NearnessFrame frame;
    frame.nearness = Plane<float>(nearness8.width, nearness8.height);
    frame.valid = Plane<std::uint8_t>(nearness8.width, nearness8.height, 1);
    for (std::size_t i = 0; i < nearness8.size(); ++i)
        frame.nearness.samples[i] = static_cast<float>(nearness8.samples[i]);
    frame.range = DepthRange{};
    return frame;
}

Plane<std::uint16_t> quantize(const Plane<float> &nearness, double vmax)
{
    const double top = std::clamp(vmax, 0.0, 65535.0);
    Plane<std::uint16_t> out(nearness.width, nearness.height);
    for (std::size_t i = 0; i < nearness.size(); ++i) {
        const double v = std::clamp(std::round(static_cast<double>(nearness.samples[i])), 0.0, top);
        out.samples[i] = static_cast<std::uint16_t>(v);
    }
    return out;
}

Plane<std::uint16_t> quantizeOccupied(const Plane<float> &nearness,
                                      const Plane<std::uint8_t> &valid, double vmax,
                                      const Occupancy &occ, std::size_t &holes)
{
    const double top = std::clamp(vmax, 1.0, 65535.0);
    const bool masked = !valid.empty();
    Plane<std::uint16_t> out(nearness.width, nearness.height);
    holes = 0;
    for (std::size_t i = 0; i < nearness.size(); ++i) {
        if (masked && valid.samples[i] == 0) {
            ++holes;
            continue;
        }
        const double n = std::clamp(static_cast<double>(nearness.samples[i]), 0.0, top);
        out.samples[i] = static_cast<std::uint16_t>(std::round(occupiedLevel(n, top, occ)));
    }
    return out;
}

Result<Plane<std::uint16_t>> metricToLevels(const Plane<std::uint16_t> &raw,
                                            std::optional<DepthRange> &range, int width, int height,
                                            double vmax)
{
    ConvertOptions co;
    co.range = range;
    co.vmax = vmax;
    auto nf = metricToNearness(raw, co);
    if (!nf)
        return unexpected(nf.error());
    range = nf->range;
    if (nf->invalidCount > 0) {
        if (auto filled = fillInvalid(nf->nearness, nf->valid); !filled)
            return unexpected(filled.error());
    }
    auto resampled = resample(nf->nearness, width, height);
    if (!resampled)
        return unexpected(resampled.error());
    return quantize(*resampled, vmax);
}

} // namespace depthtouch::depth
