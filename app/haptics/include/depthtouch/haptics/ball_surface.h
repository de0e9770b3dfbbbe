#pragma once
/// \file
/// \brief The fingertip's surface: the depth frame's height field as swept by a ball of radius r
/// (the fingertip), a stateless query. The ball renderer's first part (ball_renderer.h).
///
/// A ball of radius r whose lowest point is p rests on the height field H where it touches it
/// without entering it. Every pixel column is solid below its height, so the ball at p is clear
/// of the column at x–y u, |u − p.xy| = ρ ≤ r, while p.z + r − √(r² − ρ²) ≥ H(u). The lowest
/// clear p.z over an x–y is the swept height
///
///     S(x, y) = max over |u − (x, y)| ≤ r of  H(u) + √(r² − ρ²) − r,
///
/// a grey-scale dilation of H by a hemisphere (Serra, "Image Analysis and Mathematical
/// Morphology", 1982, ch. XII; the rolling-ball background of Sternberg 1983). On a plane S = H
/// plus r(1/cos θ − 1) for a slope θ; a gap narrower than the ball is bridged (the ball sinks by
/// r − √(r² − w²/4) into a gap w wide) and a single pixel read low (a time-of-flight dropout, an
/// 8-bit step) is covered by its neighbours; a step taller than r stays a vertical face, r in
/// front of the step. Holes and pixels off the frame are unknown: they hold the ball nowhere
/// (not as free space at a hole's border cliff: no tap of a hole counts at all).
///
/// The disc is sampled on 8 rays of 2 taps (at r/2 and r) and its centre, 17 taps, each read by
/// HeightField::heightAt() (bilinear in space, paper Eq. 1 in time). Along a ray the surface is
/// taken as linear between taps, and the highest point of H + √(r² − ρ²) − r on each segment is
/// found in closed form (where the ball's underside has the segment's slope), so S moves
/// continuously as an edge passes between taps instead of stepping by a ring's lift. The normal
/// is that of the least-squares plane through the same taps: on a plane exactly S's (S is then
/// the plane lifted by a constant), straight up where the ball rests on two rims alike, turned
/// away from a step that stands in the disc (a mean of the taps' contact normals leant toward +z
/// by half a slope's angle; S's own gradient by differences cost four more sweeps).
///
/// Units: m; positions in the scene-box frame (docs/architecture.md §3), z toward the viewer.
/// Thread-safety: BallSurface is immutable after construction; at() is reentrant and real-time
/// safe (no allocation, fixed work: kBallTaps height lookups).

#include <array>
#include <cstddef>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "depthtouch/haptics/height_field.h"

namespace depthtouch::haptics {

/// The rays of taps out from the ball's axis, and the taps on each (at r/2 and r).
inline constexpr std::size_t kBallRays = 8;
inline constexpr std::size_t kBallPerRay = 2;
/// The taps of the ball's disc: its centre and the rays'.
inline constexpr std::size_t kBallTaps = 1 + kBallRays * kBallPerRay;

/// \brief The swept surface at one x–y (BallSurface::at()).
struct BallPoint {
    /// S(x, y): the lowest the fingertip's lowest point may be there, m (box frame); NaN where no
    /// tap is measured (all holes or off the frame: nothing holds the ball, free space).
    double height = 0.0;
    /// The outward unit normal of the swept surface there (box frame; z ≥ 0); +z where NaN.
    glm::dvec3 normal{0.0, 0.0, 1.0};
    /// The height H at each tap, m; NaN for a tap not measured (a hole, off the frame).
    std::array<double, kBallTaps> taps{};

    /// \return whether some tap is measured (height is finite).
    [[nodiscard]] bool measured() const noexcept { return height == height; }
};

/// \brief The ball-swept height field query (the file comment).
class BallSurface {
public:
    /// \param radius the ball's radius r, m (> 0).
    explicit BallSurface(double radius) noexcept;

    /// \return the swept surface at (\a x, \a y) (m, box frame) over \a field at the time it was
    /// last set to (HeightField::setTime()): its height, normal and taps (kBallTaps lookups).
    [[nodiscard]] BallPoint at(const HeightField &field, double x, double y) const noexcept;

    [[nodiscard]] double radius() const noexcept { return radius_; }

private:
    /// \return √(r² − ρ²) − r: the ball's underside at ρ from its axis, m.
    [[nodiscard]] double lift(double rho) const noexcept;

    double radius_;
    std::array<glm::dvec2, kBallRays> direction_{}; ///< Each ray's unit x–y direction.
};

} // namespace depthtouch::haptics
