#include "depthtouch/haptics/geometry.h"

#include <glm/geometric.hpp>

namespace depthtouch::haptics {

glm::dvec3 closestPointOnTriangle(const glm::dvec3 &p, const glm::dvec3 &a, const glm::dvec3 &b,
                                  const glm::dvec3 &c, TriangleRegion &region) noexcept
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

bool segmentCrossesTriangleDownward(const glm::dvec3 &p0, const glm::dvec3 &p1, const glm::dvec3 &a,
                                    const glm::dvec3 &b, const glm::dvec3 &c, double baryTol,
                                    double tTol, double &t) noexcept
{
    glm::dvec3 n = glm::cross(b - a, c - a);
    if (n.z < 0.0)
        n = -n;
    const glm::dvec3 d = p1 - p0;
    const double nd = glm::dot(n, d);
    if (!(nd < 0.0))
        return false; // parallel or moving up: not a crossing from above
    const double tt = glm::dot(n, a - p0) / nd;
    if (tt < -tTol || tt > 1.0 + tTol)
        return false;
    // Barycentric coordinates of the plane point in the triangle's x–y projection (the surface is a
    // height field, so the projection is never degenerate).
    const glm::dvec3 q = p0 + tt * d;
    const double x0 = b.x - a.x;
    const double y0 = b.y - a.y;
    const double x1 = c.x - a.x;
    const double y1 = c.y - a.y;
    const double det = x0 * y1 - x1 * y0;
    if (det == 0.0)
        return false;
    const double qx = q.x - a.x;
    const double qy = q.y - a.y;
    const double l1 = (qx * y1 - x1 * qy) / det;
    const double l2 = (x0 * qy - qx * y0) / det;
    if (l1 < -baryTol || l2 < -baryTol || l1 + l2 > 1.0 + baryTol)
        return false;
    if (tt > 1.0)
        return false;
    t = tt;
    return true;
}

} // namespace depthtouch::haptics
