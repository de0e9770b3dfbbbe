/// \file
/// \brief The ball-swept height field (ball_surface.h).

#include "depthtouch/haptics/ball_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

namespace depthtouch::haptics {

BallSurface::BallSurface(double radius) noexcept : radius_(radius)
{
    // Tap 0 is the centre; ray k's taps are 1 + k·kBallPerRay + j, j outward at (j + 1)·r/2.
    for (std::size_t k = 0; k < kBallRays; ++k) {
        const double a = 2.0 * std::numbers::pi * static_cast<double>(k) / kBallRays;
        direction_[k] = {std::cos(a), std::sin(a)};
    }
}

double BallSurface::lift(double rho) const noexcept
{
    return std::sqrt(std::max(0.0, radius_ * radius_ - rho * rho)) - radius_;
}

BallPoint BallSurface::at(const HeightField &field, double x, double y) const noexcept
{
    BallPoint b;
    std::array<double, kBallTaps> &taps = b.taps;
    const double step = radius_ / kBallPerRay;
    auto read = [&field](double u, double v) {
        if (!field.contains(u, v))
            return std::nan("");
        const double h = field.heightAt(u, v);
        return field.measured(h) ? h : std::nan("");
    };
    taps[0] = read(x, y);
    for (std::size_t k = 0; k < kBallRays; ++k)
        for (std::size_t j = 0; j < kBallPerRay; ++j) {
            const double rho = step * static_cast<double>(j + 1);
            taps[1 + k * kBallPerRay + j] =
                read(x + rho * direction_[k].x, y + rho * direction_[k].y);
        }
    // On each segment of a ray between two taps the surface is taken as linear in ρ, so the
    // highest H(ρ) + lift(ρ) on it is where the ball's underside has the segment's slope s:
    // ρ/√(r² − ρ²) = s, ρ = r·s/√(1 + s²), kept within the segment. A tap not measured ends its
    // segments; the taps beside it still count on their own. The same pass sums the least-squares
    // plane of the measured taps, h ≈ a + b·u + c·v (u, v their offsets): its slope (b, c).
    double highest = -std::numeric_limits<double>::infinity();
    double n = 0, su = 0, sv = 0, suu = 0, svv = 0, suv = 0, sh = 0, suh = 0, svh = 0;
    auto fit = [&](double u, double v, double h) {
        n += 1.0;
        su += u;
        sv += v;
        suu += u * u;
        svv += v * v;
        suv += u * v;
        sh += h;
        suh += u * h;
        svh += v * h;
    };
    if (taps[0] == taps[0]) {
        highest = taps[0];
        fit(0.0, 0.0, taps[0]);
    }
    for (std::size_t k = 0; k < kBallRays; ++k)
        for (std::size_t j = 0; j < kBallPerRay; ++j) {
            const double ha = j == 0 ? taps[0] : taps[k * kBallPerRay + j];
            const double hb = taps[1 + k * kBallPerRay + j];
            const double a = step * static_cast<double>(j);
            const double end = a + step;
            if (!(hb == hb))
                continue;
            fit(end * direction_[k].x, end * direction_[k].y, hb);
            if (!(ha == ha)) {
                highest = std::max(highest, hb + lift(end));
                continue;
            }
            const double slope = (hb - ha) / step;
            const double rho = std::clamp(
                slope > 0.0 ? radius_ * slope / std::sqrt(1.0 + slope * slope) : a, a, end);
            highest = std::max(highest, ha + slope * (rho - a) + lift(rho));
        }
    if (!(highest > -std::numeric_limits<double>::infinity())) {
        b.height = std::nan("");
        return b;
    }
    b.height = highest;
    // The plane's slope from the normal equations (GLM's inverse); +z where the measured taps do
    // not span a plane (fewer than three, or in a line).
    const glm::dmat3 normal(n, su, sv, su, suu, suv, sv, suv, svv); // symmetric: column = row
    const double det = glm::determinant(normal);
    if (std::fabs(det) > 1e-12 * std::pow(radius_, 4) * n) {
        const glm::dvec3 plane = glm::inverse(normal) * glm::dvec3(sh, suh, svh); // a, b, c
        b.normal = glm::normalize(glm::dvec3(-plane.y, -plane.z, 1.0));
    }
    return b;
}

} // namespace depthtouch::haptics
