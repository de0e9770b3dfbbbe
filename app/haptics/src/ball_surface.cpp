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

BallSurface::BallSurface(double radius, double softness) noexcept
    : radius_(radius), softness_(softness)
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

BallPoint BallSurface::at(const HeightField &field, double x, double y) const noexcept
{
    BallPoint b;
    const double step = radius_ / kPerRay;
    auto read = [&field](double u, double v) {
        if (!field.contains(u, v))
            return std::nan("");
        const double h = field.heightAt(u, v);
        return field.measured(h) ? h : std::nan("");
    };
    b.taps[0] = read(x, y);
    for (std::size_t k = 0; k < kRays; ++k)
        for (std::size_t j = 0; j < kPerRay; ++j) {
            const double rho = step * static_cast<double>(j + 1);
            b.taps[1 + k * kPerRay + j] =
                read(x + rho * direction_[k].x, y + rho * direction_[k].y);
        }
    // On each segment of a ray between two taps the surface is taken as linear in ρ, so the
    // highest H(ρ) + lift(ρ) on it is where the ball's underside has the segment's slope s:
    // ρ/√(r² − ρ²) = s, ρ = r·s/√(1 + s²), kept within the segment. A tap not measured ends its
    // segments; the taps beside it still count on their own.
    struct Best {
        double value;
        double rho;
        double h;
        std::size_t ray;
    };
    std::array<Best, kBallTaps> best{};
    std::size_t n = 0;
    double highest = -std::numeric_limits<double>::infinity();
    auto consider = [&](double value, double rho, double h, std::size_t ray) {
        best[n++] = {value, rho, h, ray};
        highest = std::max(highest, value);
    };
    if (b.taps[0] == b.taps[0])
        consider(b.taps[0], 0.0, b.taps[0], 0);
    for (std::size_t k = 0; k < kRays; ++k)
        for (std::size_t j = 0; j < kPerRay; ++j) {
            const double ha = j == 0 ? b.taps[0] : b.taps[k * kPerRay + j];
            const double hb = b.taps[1 + k * kPerRay + j];
            const double a = step * static_cast<double>(j);
            const double bRho = a + step;
            if (!(hb == hb))
                continue;
            if (!(ha == ha)) {
                consider(hb + lift(bRho), bRho, hb, k);
                continue;
            }
            const double slope = (hb - ha) / step;
            const double rho = std::clamp(
                slope > 0.0 ? radius_ * slope / std::sqrt(1.0 + slope * slope) : a, a, bRho);
            const double h = ha + slope * (rho - a);
            // The segment's start is the last segment's end (or the centre): counted there.
            if (rho > a)
                consider(h + lift(rho), rho, h, k);
        }
    if (n == 0) {
        b.height = std::nan("");
        return b;
    }
    b.height = highest;
    // The ball's centre rests r above the swept height; each contact within the softness of the
    // highest pulls the normal toward the direction from its surface point to that centre.
    glm::dvec3 sum{};
    for (std::size_t i = 0; i < n; ++i) {
        const double w = 1.0 - (highest - best[i].value) / softness_;
        if (w <= 0.0)
            continue;
        const glm::dvec2 across = best[i].rho * direction_[best[i].ray];
        const glm::dvec3 d(-across.x, -across.y, highest + radius_ - best[i].h);
        sum += w * d / glm::length(d);
    }
    const double norm = glm::length(sum);
    if (norm > 0.0)
        b.normal = sum / norm;
    return b;
}

} // namespace depthtouch::haptics
