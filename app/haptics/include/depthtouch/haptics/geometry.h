#pragma once
/// \file
/// \brief Exact small geometry kernels of the haptic renderer (double precision, no allocation).
///
/// Thread-safety: reentrant pure functions.

#include <cstdint>

#include <glm/vec3.hpp>

namespace depthtouch::haptics {

/// \brief Which feature of a triangle ABC a closest point lies on (number of active constraints:
/// face 1, edge 2, vertex 3 in the god-object sense).
enum class TriangleRegion : std::uint8_t { Face, EdgeAB, EdgeBC, EdgeCA, VertexA, VertexB, VertexC };

/// \brief Closest point of triangle ABC to point \a p (Ericson, Real-Time Collision Detection §5.1.5).
/// \param[out] region the feature the point lies on.
/// \return the point, same frame and units as the inputs (m).
glm::dvec3 closestPointOnTriangle(const glm::dvec3 &p, const glm::dvec3 &a, const glm::dvec3 &b,
                                  const glm::dvec3 &c, TriangleRegion &region) noexcept;

/// \brief Exact segment–triangle test for a crossing from the upper (+z) side to the lower side.
///
/// The triangle is oriented so its normal points up (+z); the segment \a p0 → \a p1 crosses it when
/// it meets the triangle's plane at a parameter t ∈ [−tTol, 1] inside the triangle (barycentric
/// tolerance \a baryTol) while moving against the upward normal. Used by the brute-force reference
/// and the mesh-bvh baseline (plane crossing, then a barycentric test in the x–y projection).
/// \param[out] t crossing parameter along the segment when true.
/// \return true on a downward crossing.
bool segmentCrossesTriangleDownward(const glm::dvec3 &p0, const glm::dvec3 &p1, const glm::dvec3 &a,
                                    const glm::dvec3 &b, const glm::dvec3 &c, double baryTol,
                                    double tTol, double &t) noexcept;

} // namespace depthtouch::haptics
