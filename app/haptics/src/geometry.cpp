#include "depthtouch/haptics/geometry.h"

#include <glm/geometric.hpp>

namespace depthtouch::haptics {

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
