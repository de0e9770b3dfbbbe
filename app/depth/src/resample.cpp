/// \file
/// \brief Depth resampling (see resample.h).

#include "depthtouch/depth/resample.h"

#include <algorithm>
#include <cmath>

namespace depthtouch::depth {

Result<Plane<float>> resample(const Plane<float> &src, int width, int height, ResampleMethod method,
                              float edgeThreshold)
{
    if (src.empty() || width <= 0 || height <= 0)
        return unexpected(Errc::InvalidArgument,
                          "Cannot resample an empty depth map or to an empty size");
    if (method == ResampleMethod::Nearest)
        return resampleNearest(src, width, height);

    Plane<float> out(width, height);
    const double sxScale = static_cast<double>(src.width) / width;
    const double syScale = static_cast<double>(src.height) / height;
    for (int y = 0; y < height; ++y) {
        const double sy = (y + 0.5) * syScale - 0.5;
        const int y0 = static_cast<int>(std::floor(sy));
        const double ty = sy - y0;
        for (int x = 0; x < width; ++x) {
            const double sx = (x + 0.5) * sxScale - 0.5;
            const int x0 = static_cast<int>(std::floor(sx));
            const double tx = sx - x0;
            const float a = src.clamped(x0, y0);
            const float b = src.clamped(x0 + 1, y0);
            const float c = src.clamped(x0, y0 + 1);
            const float d = src.clamped(x0 + 1, y0 + 1);
            const float lo = std::min({a, b, c, d});
            const float hi = std::max({a, b, c, d});
            if (hi - lo <= edgeThreshold) {
                const double top =
                    (1.0 - tx) * static_cast<double>(a) + tx * static_cast<double>(b);
                const double bottom =
                    (1.0 - tx) * static_cast<double>(c) + tx * static_cast<double>(d);
                out.at(x, y) = static_cast<float>((1.0 - ty) * top + ty * bottom);
            } else {
                out.at(x, y) = src.clamped(static_cast<int>(std::lround(sx)),
                                           static_cast<int>(std::lround(sy)));
            }
        }
    }
    return out;
}

namespace {

/// The EdgeAware value at source position (\a sx, \a sy) from the measured ones of its 2×2
/// neighbours (at least one is measured).
float maskedValue(const Plane<float> &src, const Plane<std::uint8_t> &valid, double sx, double sy,
                  float edgeThreshold)
{
    const int x0 = static_cast<int>(std::floor(sx));
    const int y0 = static_cast<int>(std::floor(sy));
    const double tx = sx - x0;
    const double ty = sy - y0;
    const int xs[4] = {x0, x0 + 1, x0, x0 + 1};
    const int ys[4] = {y0, y0, y0 + 1, y0 + 1};
    const double w[4] = {(1.0 - tx) * (1.0 - ty), tx * (1.0 - ty), (1.0 - tx) * ty, tx * ty};
    float lo = 0.0f;
    float hi = 0.0f;
    double sum = 0.0;
    double weights = 0.0;
    int best = -1;
    for (int k = 0; k < 4; ++k) {
        if (valid.clamped(xs[k], ys[k]) == 0)
            continue;
        const float v = src.clamped(xs[k], ys[k]);
        lo = best < 0 ? v : std::min(lo, v);
        hi = best < 0 ? v : std::max(hi, v);
        if (best < 0 || w[k] > w[best])
            best = k;
        sum += w[k] * static_cast<double>(v);
        weights += w[k];
    }
    if (best < 0)
        return 0.0f;
    if (hi - lo <= edgeThreshold && weights > 0.0)
        return static_cast<float>(sum / weights);
    return src.clamped(xs[best], ys[best]);
}

} // namespace

Result<Plane<float>> resampleMasked(const Plane<float> &src, const Plane<std::uint8_t> &valid,
                                    int width, int height, float edgeThreshold,
                                    Plane<std::uint8_t> &validOut)
{
    if (src.empty() || width <= 0 || height <= 0 || !src.sameSize(valid))
        return unexpected(Errc::InvalidArgument,
                          "Cannot resample an empty depth map, its mask of another size or to an "
                          "empty size");
    validOut = resampleNearest(valid, width, height);
    Plane<float> out(width, height);
    const double sxScale = static_cast<double>(src.width) / width;
    const double syScale = static_cast<double>(src.height) / height;
    for (int y = 0; y < height; ++y) {
        const double sy = (y + 0.5) * syScale - 0.5;
        for (int x = 0; x < width; ++x) {
            if (validOut.at(x, y) == 0)
                continue;
            out.at(x, y) = maskedValue(src, valid, (x + 0.5) * sxScale - 0.5, sy, edgeThreshold);
        }
    }
    return out;
}

} // namespace depthtouch::depth
