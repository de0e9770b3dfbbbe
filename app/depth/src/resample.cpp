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

} // namespace depthtouch::depth
