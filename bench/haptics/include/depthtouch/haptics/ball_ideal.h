#pragma once
/// \file
/// \brief The ideal fingertip: a ball of the renderer's radius on the reference surface, the
/// yardstick a fingertip renderer's force can be read against where the point's ideal
/// (nearestSurface(), feel.h) is not what a finger feels: ridges finer than a fingertip (a
/// keyboard's keys), gaps it cannot enter, tops narrower than it (docs/benchmarks.md, "Keys finer
/// than a fingertip").
///
/// The ball's lowest point stands for the HIP. It rests on a height field h at
/// B(x, y) = max over the grid vertices v within r of (x, y) of h(v) + √(r² − |v − (x, y)|²) − r,
/// and on h(x, y) itself: the height field dilated by the ball (the Minkowski sum of the solid
/// under h with a ball, as a height field of the ball's lowest point). Its god-object (Zilles &
/// Salisbury 1995) is the point nearest the HIP on or above B; its spring k·(that − HIP) is the
/// force of the potential ½·k·distance², passive on a still surface, as the point's is. Holes
/// (HeightField::besideHole()) are nothing measured and hold no ball up.
///
/// Units: m, N, N/m; the frame is the HeightField's (docs/architecture.md §3). Cost: one
/// ballRestHeight() reads about π·(r/s)² vertices (s: the grid spacing), a few hundred at the
/// feel bench's scenes; ballIdealPenalty() calls it on rings out to the HIP's depth, at most 2r
/// (up to 10⁵ lookups an update): a tool for `bench feel --dump --dump-ball-ideal`'s strokes, not
/// the suite. Thread-safety: reentrant; reads \a field only.

#include <glm/vec3.hpp>

#include "depthtouch/haptics/height_field.h"

namespace depthtouch::haptics::bench {

/// \return B(\a x, \a y): the height (m) of the lowest point of a ball of \a radius (m) resting
/// on \a field over (x, y); NaN off the grid or where nothing within the ball's reach was
/// measured. \pre field.valid(), radius > 0.
double ballRestHeight(const HeightField &field, double x, double y, double radius) noexcept;

/// \return the ideal ball's force on \a hip (m) at \a stiffness (N/m), N: k·(Q − HIP), Q the
/// point nearest the HIP on or above ballRestHeight(), searched on rings \a ringStep (m) apart
/// in \a directions directions out to the HIP's depth under B or 2·radius, whichever is less
/// (a HIP more than 2r under B whose way out lies farther to the side is pushed straight up);
/// zero where the HIP is above B or B is NaN. \pre field.valid(), radius > 0, ringStep > 0,
/// directions > 0.
glm::dvec3 ballIdealPenalty(const HeightField &field, const glm::dvec3 &hip, double radius,
                            double stiffness, double ringStep = 0.05e-3,
                            int directions = 48) noexcept;

} // namespace depthtouch::haptics::bench
