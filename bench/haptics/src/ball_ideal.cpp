/// \file
/// \brief The ideal fingertip's rest height and force (ball_ideal.h).

#include "depthtouch/haptics/ball_ideal.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "depthtouch/haptics/feel.h"

namespace depthtouch::haptics::bench {

namespace {

/// \return \a field's height at (\a x, \a y), m, or −infinity where nothing was measured there
/// (off the grid, a hole or a hole's cliff).
double measured(const HeightField &field, double x, double y) noexcept
{
    if (!field.contains(x, y))
        return -std::numeric_limits<double>::infinity();
    const double z = field.heightAt(x, y);
    return std::isfinite(z) && !field.besideHole(z) ? z : -std::numeric_limits<double>::infinity();
}

} // namespace

double ballRestHeight(const HeightField &field, double x, double y, double radius) noexcept
{
    if (!field.contains(x, y))
        return std::nan("");
    // The supports are read at the vertices (the peaks and ridges of the field's triangles) and
    // under the lowest point itself. On a slope g the support lies between vertices and is missed
    // by at most about s²·(1 + g²)^1.5 / (4r), s the spacing: 15 µm at 45° on the feel bench's
    // grids (s ≈ 0.16 mm).
    double best = measured(field, x, y);
    const double r2 = radius * radius;
    const double reach = radius / field.spacing();
    const double u = field.xToColumn(x);
    const double v = field.yToRow(y);
    const int c0 = std::max(0, static_cast<int>(std::floor(u - reach)));
    const int c1 = std::min(field.columns() - 1, static_cast<int>(std::ceil(u + reach)));
    const int rw0 = std::max(0, static_cast<int>(std::floor(v - reach)));
    const int rw1 = std::min(field.rows() - 1, static_cast<int>(std::ceil(v + reach)));
    for (int rw = rw0; rw <= rw1; ++rw)
        for (int c = c0; c <= c1; ++c) {
            const double vx = field.columnToX(c);
            const double vy = field.rowToY(rw);
            const double d2 = (vx - x) * (vx - x) + (vy - y) * (vy - y);
            if (d2 > r2)
                continue;
            const double z = measured(field, vx, vy);
            if (z > -std::numeric_limits<double>::infinity())
                best = std::max(best, z + std::sqrt(r2 - d2) - radius);
        }
    return best > -std::numeric_limits<double>::infinity() ? best : std::nan("");
}

glm::dvec3 ballIdealPenalty(const HeightField &field, const glm::dvec3 &hip, double radius,
                            double stiffness, double ringStep, int directions) noexcept
{
    const double rest = ballRestHeight(field, hip.x, hip.y, radius);
    if (!(rest > hip.z))
        return glm::dvec3{0.0};
    // The nearest point on or above B (nearestSurface(), feel.h, on B); deeper than 2r it is
    // searched out to 2r only (ball_ideal.h).
    glm::dvec3 at{};
    nearestSurface([&](double x, double y) { return ballRestHeight(field, x, y, radius); }, hip,
                   rest - hip.z, &at, ringStep, directions, 2.0 * radius);
    return stiffness * (at - hip);
}

} // namespace depthtouch::haptics::bench
