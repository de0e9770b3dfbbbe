/// \file
/// \brief Median, Sobel, Laplacian and max filters (see filters.h).

#include "depthtouch/depth/filters.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace depthtouch::depth {

Plane<float> medianFilter(const Plane<float> &src, int radius)
{
    if (radius <= 0 || src.empty())
        return src;
    Plane<float> out(src.width, src.height);
    const auto side = static_cast<std::size_t>(2 * radius + 1);
    std::vector<float> window(side * side);
    const auto mid = static_cast<std::ptrdiff_t>(window.size() / 2);
    for (int y = 0; y < src.height; ++y) {
        for (int x = 0; x < src.width; ++x) {
            std::size_t n = 0;
            for (int dy = -radius; dy <= radius; ++dy)
                for (int dx = -radius; dx <= radius; ++dx)
                    window[n++] = src.clamped(x + dx, y + dy);
            std::nth_element(window.begin(), window.begin() + mid, window.end());
            out.at(x, y) = window[static_cast<std::size_t>(mid)];
        }
    }
    return out;
}

Plane<float> gradientMagnitude(const Plane<float> &src)
{
    Plane<float> out(src.width, src.height);
    for (int y = 0; y < src.height; ++y) {
        for (int x = 0; x < src.width; ++x) {
            const auto s = [&src, x, y](int dx, int dy) {
                return static_cast<double>(src.clamped(x + dx, y + dy));
            };
            // Sobel kernels sum to 8× the per-pixel slope of a ramp.
            const double gx =
                (s(1, -1) + 2.0 * s(1, 0) + s(1, 1) - s(-1, -1) - 2.0 * s(-1, 0) - s(-1, 1)) / 8.0;
            const double gy =
                (s(-1, 1) + 2.0 * s(0, 1) + s(1, 1) - s(-1, -1) - 2.0 * s(0, -1) - s(1, -1)) / 8.0;
            out.at(x, y) = static_cast<float>(std::sqrt(gx * gx + gy * gy));
        }
    }
    return out;
}

Plane<float> laplacian(const Plane<float> &src)
{
    Plane<float> out(src.width, src.height);
    for (int y = 0; y < src.height; ++y)
        for (int x = 0; x < src.width; ++x)
            out.at(x, y) = 4.0f * src.at(x, y) - src.clamped(x - 1, y) - src.clamped(x + 1, y) -
                           src.clamped(x, y - 1) - src.clamped(x, y + 1);
    return out;
}

Plane<float> maxFilter(const Plane<float> &src, int radius)
{
    if (radius <= 0 || src.empty())
        return src;
    // Separable: rows, then columns.
    Plane<float> rows(src.width, src.height);
    for (int y = 0; y < src.height; ++y)
        for (int x = 0; x < src.width; ++x) {
            float m = src.at(x, y);
            for (int d = -radius; d <= radius; ++d)
                m = std::max(m, src.clamped(x + d, y));
            rows.at(x, y) = m;
        }
    Plane<float> out(src.width, src.height);
    for (int y = 0; y < src.height; ++y)
        for (int x = 0; x < src.width; ++x) {
            float m = rows.at(x, y);
            for (int d = -radius; d <= radius; ++d)
                m = std::max(m, rows.clamped(x, y + d));
            out.at(x, y) = m;
        }
    return out;
}

} // namespace depthtouch::depth
