/// \file
/// \brief The ball-swept height field (ball_surface.h).

#include "depthtouch/haptics/ball_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/geometric.hpp>

namespace depthtouch::haptics {

namespace {

/// Rays of taps out from the centre, and taps on each (at r/3, 2r/3 and r).
constexpr std::size_t kRays = 12;
constexpr std::size_t kPerRay = 3;
static_assert(1 + kRays * kPerRay == kBallTaps);

} // namespace

BallSurface::BallSurface(double radius) noexcept : radius_(radius)
{
    // Tap 0 is the centre; ray k's taps are 1 + k·kPerRay + j, j outward.
    for (std::size_t k = 0; k < kRays; ++k) {
        const double a = 2.0 * std::numbers::pi * static_cast<double>(k) / kRays;
        direction_[k] = {std::cos(a), std::sin(a)};
    }
}

double BallSurface::lift(double rho) const noexcept
{
    return std::sqrt(std::max(0.0, radius_ * radius_ - rho * rho)) - radius_;
}

double BallSurface::height(const HeightField &field, double x, double y,
                           std::array<double, kBallTaps> &taps) const noexcept
{
    const double step = radius_ / kPerRay;
    auto read = [&field](double u, double v) {
        if (!field.contains(u, v))
            return std::nan("");
        const double h = field.heightAt(u, v);
        return field.measured(h) ? h : std::nan("");
    };
    taps[0] = read(x, y);
    for (std::size_t k = 0; k < kRays; ++k)
        for (std::size_t j = 0; j < kPerRay; ++j) {
            const double rho = step * static_cast<double>(j + 1);
            taps[1 + k * kPerRay + j] = read(x + rho * direction_[k].x, y + rho * direction_[k].y);
        }
    // On each segment of a ray between two taps the surface is taken as linear in ρ, so the
    // highest H(ρ) + lift(ρ) on it is where the ball's underside has the segment's slope s:
    // ρ/√(r² − ρ²) = s, ρ = r·s/√(1 + s²), kept within the segment. A tap not measured ends its
    // segments; the taps beside it still count on their own.
    double highest = -std::numeric_limits<double>::infinity();
    if (taps[0] == taps[0])
        highest = taps[0];
    for (std::size_t k = 0; k < kRays; ++k)
        for (std::size_t j = 0; j < kPerRay; ++j) {
            const double ha = j == 0 ? taps[0] : taps[k * kPerRay + j];
            const double hb = taps[1 + k * kPerRay + j];
            const double a = step * static_cast<double>(j);
            const double b = a + step;
            if (!(hb == hb))
                continue;
            if (!(ha == ha)) {
                highest = std::max(highest, hb + lift(b));
                continue;
            }
            const double slope = (hb - ha) / step;
            const double rho = std::clamp(
                slope > 0.0 ? radius_ * slope / std::sqrt(1.0 + slope * slope) : a, a, b);
            highest = std::max(highest, ha + slope * (rho - a) + lift(rho));
        }
    return highest > -std::numeric_limits<double>::infinity() ? highest : std::nan("");
}

double BallSurface::height(const HeightField &field, double x, double y) const noexcept
{
    std::array<double, kBallTaps> taps{};
    return height(field, x, y, taps);
}

glm::dvec3 BallSurface::normal(const HeightField &field, double x, double y,
                               double s) const noexcept
{
    // S's gradient by central differences over ±r/6 (one side where the other is not measured):
    // exact on a plane whatever the taps' pattern (S is then the plane lifted by a constant),
    // within r/(6R)² of the slope on a surface curved with radius R, and straight up where the
    // ball rests on two rims alike (a groove narrower than it). Across a face of S (a step taller
    // than r) the difference is the face's: a normal nearly horizontal, as the ball's against it.
    if (!(s == s))
        return {0.0, 0.0, 1.0};
    const double h = radius_ / 6.0;
    auto slope = [&](double dx, double dy) {
        const double ahead = height(field, x + dx, y + dy);
        const double behind = height(field, x - dx, y - dy);
        if (ahead == ahead && behind == behind)
            return (ahead - behind) / (2.0 * h);
        if (ahead == ahead)
            return (ahead - s) / h;
        return behind == behind ? (s - behind) / h : 0.0;
    };
    return glm::normalize(glm::dvec3(-slope(h, 0.0), -slope(0.0, h), 1.0));
}

BallPoint BallSurface::at(const HeightField &field, double x, double y) const noexcept
{
    BallPoint b;
    b.height = height(field, x, y, b.taps);
    b.normal = normal(field, x, y, b.height);
    return b;
}

} // namespace depthtouch::haptics
