#pragma once
/// \file
/// \brief Exact small geometry kernels of the haptic renderer (double precision, no allocation).
///
/// Thread-safety: reentrant pure functions.

#include <cstdint>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace depthtouch::haptics {

/// \brief Which feature of a triangle ABC a closest point lies on (number of active constraints:
/// face 1, edge 2, vertex 3 in the god-object sense).
enum class TriangleRegion : std::uint8_t {
    Face,
    EdgeAB,
    EdgeBC,
    EdgeCA,
    VertexA,
    VertexB,
    VertexC
};

/// \brief Closest point of triangle ABC to point \a p (Ericson, Real-Time Collision Detection
/// §5.1.5). \param[out] region the feature the point lies on. \return the point, same frame and
/// units as the inputs (m). Inline: the proxy descent calls it for every triangle it tries.
inline glm::dvec3 closestPointOnTriangle(const glm::dvec3 &p, const glm::dvec3 &a,
                                         const glm::dvec3 &b, const glm::dvec3 &c,
                                         TriangleRegion &region) noexcept
{
    // Ericson, Real-Time Collision Detection, §5.1.5 (Voronoi regions of the features).
    const glm::dvec3 ab = b - a;
    const glm::dvec3 ac = c - a;
    const glm::dvec3 ap = p - a;
    const double d1 = glm::dot(ab, ap);
    const double d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) {
        region = TriangleRegion::VertexA;
        return a;
    }
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp);
    const double d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) {
        region = TriangleRegion::VertexB;
        return b;
    }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        region = TriangleRegion::EdgeAB;
        return a + (d1 / (d1 - d3)) * ab;
    }
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp);
    const double d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) {
        region = TriangleRegion::VertexC;
        return c;
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        region = TriangleRegion::EdgeCA;
        return a + (d2 / (d2 - d6)) * ac;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        region = TriangleRegion::EdgeBC;
        return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
    }
    region = TriangleRegion::Face;
    const double denom = 1.0 / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}


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
