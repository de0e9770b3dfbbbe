/// \file
/// \brief Push-pull hole filling (see fill.h).

#include "depthtouch/depth/fill.h"

#include <cmath>
#include <vector>

namespace depthtouch::depth {

namespace {

/// One pyramid level: the mean value of each cell and whether it holds data.
struct Level {
    Plane<float> value;
    Plane<std::uint8_t> has;
};

bool complete(const Level &l)
{
    for (const std::uint8_t h : l.has.samples)
        if (h == 0)
            return false;
    return true;
}

/// Pull: each coarse cell is the mean of its children that hold data.
Level pull(const Level &fine)
{
    const int w = (fine.value.width + 1) / 2;
    const int h = (fine.value.height + 1) / 2;
    Level coarse{Plane<float>(w, h, 0.0f), Plane<std::uint8_t>(w, h, 0)};
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            double sum = 0.0;
            int n = 0;
            for (int dy = 0; dy < 2; ++dy) {
                for (int dx = 0; dx < 2; ++dx) {
                    const int fx = 2 * x + dx;
                    const int fy = 2 * y + dy;
                    if (fx >= fine.value.width || fy >= fine.value.height ||
                        fine.has.at(fx, fy) == 0)
                        continue;
                    sum += static_cast<double>(fine.value.at(fx, fy));
                    ++n;
                }
            }
            if (n > 0) {
                coarse.value.at(x, y) = static_cast<float>(sum / n);
                coarse.has.at(x, y) = 1;
            }
        }
    }
    return coarse;
}

/// Push: empty cells of \a fine take the bilinear interpolation of the complete level \a coarse.
void push(Level &fine, const Level &coarse)
{
    const Plane<float> &c = coarse.value;
    for (int y = 0; y < fine.value.height; ++y) {
        // Centre of fine cell y in coarse cell coordinates.
        const double cy = (y + 0.5) / 2.0 - 0.5;
        const int y0 = static_cast<int>(std::floor(cy));
        const double ty = cy - y0;
        for (int x = 0; x < fine.value.width; ++x) {
            if (fine.has.at(x, y) != 0)
                continue;
            const double cx = (x + 0.5) / 2.0 - 0.5;
            const int x0 = static_cast<int>(std::floor(cx));
            const double tx = cx - x0;
            const auto at = [&c](int cx0, int cy0) {
                return static_cast<double>(c.clamped(cx0, cy0));
            };
            const double top = (1.0 - tx) * at(x0, y0) + tx * at(x0 + 1, y0);
            const double bottom = (1.0 - tx) * at(x0, y0 + 1) + tx * at(x0 + 1, y0 + 1);
            fine.value.at(x, y) = static_cast<float>((1.0 - ty) * top + ty * bottom);
            fine.has.at(x, y) = 1;
        }
    }
}

} // namespace

Result<std::size_t> fillInvalid(Plane<float> &nearness, const Plane<std::uint8_t> &valid)
{
    if (nearness.empty() || !nearness.sameSize(valid))
        return unexpected(Errc::InvalidArgument,
                          "Depth and validity planes are empty or differ in size");

    std::size_t holes = 0;
    for (const std::uint8_t v : valid.samples)
        holes += v == 0 ? 1u : 0u;
    if (holes == 0)
        return std::size_t{0};
    if (holes == valid.size())
        return unexpected(Errc::InvalidArgument, "No valid depth sample to fill holes from");

    std::vector<Level> pyramid;
    pyramid.push_back(Level{nearness, Plane<std::uint8_t>(valid.width, valid.height, 0)});
    for (std::size_t i = 0; i < valid.size(); ++i)
        pyramid[0].has.samples[i] = valid.samples[i] != 0 ? 1 : 0;
    // Terminates: each level halves the grid and a 1×1 level holding any valid sample is complete.
    while (!complete(pyramid.back()))
        pyramid.push_back(pull(pyramid.back()));
    for (std::size_t k = pyramid.size() - 1; k > 0; --k)
        push(pyramid[k - 1], pyramid[k]);

    nearness = std::move(pyramid[0].value);
    return holes;
}

} // namespace depthtouch::depth
