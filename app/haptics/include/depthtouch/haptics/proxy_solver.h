#pragma once
/// \file
/// \brief The god-object proxy update on an implicit grid surface (paper III; Zilles & Salisbury,
/// Ruspini): from the triangle where the proxy met the surface, the proxy slides to the surface point
/// closest to the HIP, across faces, edges and vertices, within one update.
///
/// Method: local descent over triangles. The closest point of the current triangle to the HIP is
/// computed exactly; if it lies on an edge or a vertex, the triangles sharing that edge or vertex are
/// tried, and the proxy moves to the one whose closest point is nearer. It stops when no neighbour is
/// nearer: on a face (1 active constraint plane), on a convex or concave edge (2) or at a vertex or a
/// concave corner (3 or more). The result satisfies the god-object's optimality conditions; every
/// intermediate point is on the surface, so the proxy never ends below it.
/// Works on the same grid-surface types as collision.h. Thread-safety: reentrant; no allocation.

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "depthtouch/haptics/geometry.h"
#include "depthtouch/haptics/height_field.h"

namespace depthtouch::haptics {

/// \brief Where the proxy ended.
struct ProxySolution {
    glm::dvec3 point{};       ///< Proxy on the surface, m (scene-box frame).
    TriangleId triangle{};    ///< Triangle the proxy lies on.
    int constraints = 1;      ///< Active constraint planes: 1 face, 2 edge, 3 vertex/corner.
    int steps = 0;            ///< Triangles moved across.
};

/// Relative tolerance (of the pixel spacing) for "nearer" in the descent.
inline constexpr double kDescentTolerance = 1e-9;

/// Upper bound on triangles crossed in one update (bounds the worst-case update time; a stroke at
/// 1 m/s on a 3840×2160 frame over 0.1 m crosses about 80 per 1 ms update).
inline constexpr int kMaxProxySteps = 4096;

namespace detail {

/// Appends to \a out the triangles (≤ 6) that have vertex (vc, vr). \return how many.
inline int trianglesAroundVertex(int w, int h, int vc, int vr, TriangleId *out) noexcept
{
    const TriangleId all[6] = {{vc, vr, 0},         {vc, vr, 1},     {vc - 1, vr, 0},
                               {vc - 1, vr - 1, 0}, {vc - 1, vr - 1, 1}, {vc, vr - 1, 1}};
    int n = 0;
    for (const TriangleId &t : all)
        if (t.c >= 0 && t.c <= w - 2 && t.r >= 0 && t.r <= h - 2)
            out[n++] = t;
    return n;
}

inline bool triangleHasVertex(const TriangleId &tri, int vc, int vr) noexcept
{
    for (int k = 0; k < 3; ++k) {
        int c = 0;
        int r = 0;
        triangleVertex(tri, k, c, r);
        if (c == vc && r == vr)
            return true;
    }
    return false;
}

template <class Surface>
glm::dvec3 closestOn(const Surface &surf, const TriangleId &tri, const glm::dvec3 &p,
                     TriangleRegion &region) noexcept
{
    glm::dvec3 v[3];
    triangleVertices(surf, tri, v);
    return closestPointOnTriangle(p, v[0], v[1], v[2], region);
}

} // namespace detail

/// \brief Slides the proxy from triangle \a start to the nearest surface point to \a hip.
/// \param start triangle where the proxy met the surface (from firstCrossing()).
/// \param hip haptic interaction point, m (scene-box frame).
template <class Surface>
ProxySolution solveProxy(const Surface &surf, const TriangleId &start, const glm::dvec3 &hip) noexcept
{
    const int w = surf.columns();
    const int h = surf.rows();
    ProxySolution sol;
    sol.triangle = start;
    TriangleRegion region{};
    sol.point = detail::closestOn(surf, start, hip, region);
    glm::dvec3 diff = sol.point - hip;
    double best = glm::dot(diff, diff);
    // A neighbour must be nearer by more than rounding: relative 1e-12 plus (1e-9·s)².
    const double tol = kDescentTolerance * surf.spacing();
    for (; sol.steps < kMaxProxySteps; ++sol.steps) {
        if (region == TriangleRegion::Face)
            break;
        // The grid vertices that define the feature the closest point lies on.
        int ka = 0;
        int kb = -1;
        switch (region) {
        case TriangleRegion::EdgeAB: ka = 0; kb = 1; break;
        case TriangleRegion::EdgeBC: ka = 1; kb = 2; break;
        case TriangleRegion::EdgeCA: ka = 2; kb = 0; break;
        case TriangleRegion::VertexA: ka = 0; break;
        case TriangleRegion::VertexB: ka = 1; break;
        case TriangleRegion::VertexC: ka = 2; break;
        case TriangleRegion::Face: break;
        }
        int ac = 0;
        int ar = 0;
        int bc = 0;
        int br = 0;
        triangleVertex(sol.triangle, ka, ac, ar);
        if (kb >= 0)
            triangleVertex(sol.triangle, kb, bc, br);
        TriangleId around[6];
        const int n = detail::trianglesAroundVertex(w, h, ac, ar, around);
        TriangleId bestTri = sol.triangle;
        glm::dvec3 bestPoint = sol.point;
        TriangleRegion bestRegion = region;
        double bestD = best;
        const double need = best * (1.0 - 1e-12) - tol * tol;
        for (int i = 0; i < n; ++i) {
            if (around[i] == sol.triangle)
                continue;
            if (kb >= 0 && !detail::triangleHasVertex(around[i], bc, br))
                continue;
            TriangleRegion rg{};
            const glm::dvec3 q = detail::closestOn(surf, around[i], hip, rg);
            const glm::dvec3 dq = q - hip;
            const double d = glm::dot(dq, dq);
            if (d < need && d < bestD) {
                bestD = d;
                bestTri = around[i];
                bestPoint = q;
                bestRegion = rg;
            }
        }
        if (bestTri == sol.triangle)
            break;
        sol.triangle = bestTri;
        sol.point = bestPoint;
        region = bestRegion;
        best = bestD;
    }
    switch (region) {
    case TriangleRegion::Face: sol.constraints = 1; break;
    case TriangleRegion::EdgeAB:
    case TriangleRegion::EdgeBC:
    case TriangleRegion::EdgeCA: sol.constraints = 2; break;
    default: sol.constraints = 3; break;
    }
    return sol;
}

/// \brief A coarser view of a grid surface: every \a stride-th vertex in each direction, the same
/// triangulation rule (DESIGN.md §3) one level up. A view only: no copy, no allocation; vertex (c, r)
/// is the fine vertex (c·stride, r·stride), so coarse vertices lie on the fine surface.
/// Thread-safety: as the fine surface (const use is reentrant).
template <class Surface>
class StridedSurface {
public:
    /// \param fine the surface to view, \param stride ≥ 1 fine cells per coarse cell.
    StridedSurface(const Surface &fine, int stride) noexcept
        : fine_(fine), stride_(stride), w_((fine.columns() - 1) / stride + 1),
          h_((fine.rows() - 1) / stride + 1)
    {
    }
    [[nodiscard]] int columns() const noexcept { return w_; }
    [[nodiscard]] int rows() const noexcept { return h_; }
    [[nodiscard]] double spacing() const noexcept { return fine_.spacing() * stride_; }
    [[nodiscard]] glm::dvec3 vertex(int c, int r) const noexcept
    {
        return fine_.vertex(c * stride_, r * stride_);
    }
    /// \return the coarse triangle under scene point (x, y) (clamped to the coarse grid).
    [[nodiscard]] TriangleId triangleAt(double x, double y) const noexcept
    {
        const double u = fine_.xToColumn(x) / stride_;
        const double v = fine_.yToRow(y) / stride_;
        const int c = std::clamp(static_cast<int>(std::floor(u)), 0, w_ - 2);
        const int r = std::clamp(static_cast<int>(std::floor(v)), 0, h_ - 2);
        return TriangleId{c, r, (u - c) >= (v - r) ? 0 : 1};
    }

private:
    const Surface &fine_;
    int stride_;
    int w_;
    int h_;
};

/// \brief solveProxy() in two passes when the proxy has far to go: first on the surface seen every
/// \a stride-th vertex, then on the full grid from where the coarse pass ended. The number of
/// triangles crossed per update then no longer grows with the depth resolution (a 1 mm stroke per
/// update is 38 cells of a 3840-wide frame over 0.1 m, but 7 cells at stride 5). The fine pass ends
/// at the same kind of point as solveProxy() (a local optimum of the god-object on the full surface,
/// on the surface, never below it); only features narrower than \a stride cells between the old and
/// the new proxy can be passed over.
/// \param stride coarse cells per fine cell; ≤ 1, or a grid too small for it, runs solveProxy() alone.
/// \param minCells the coarse pass runs only when the HIP is more than this many fine cells (in x–y)
/// from the start triangle.
template <class Surface>
ProxySolution solveProxyCoarseToFine(const Surface &surf, const TriangleId &start,
                                     const glm::dvec3 &hip, int stride, double minCells) noexcept
{
    if (stride < 2 || surf.columns() < 2 * stride + 1 || surf.rows() < 2 * stride + 1)
        return solveProxy(surf, start, hip);
    const double du = surf.xToColumn(hip.x) - (start.c + 0.5);
    const double dv = surf.yToRow(hip.y) - (start.r + 0.5);
    if (du * du + dv * dv <= minCells * minCells)
        return solveProxy(surf, start, hip);
    const StridedSurface<Surface> coarse(surf, stride);
    const double sx = surf.columnToX(start.c + 0.5);
    const double sy = surf.rowToY(start.r + 0.5);
    const ProxySolution rough = solveProxy(coarse, coarse.triangleAt(sx, sy), hip);
    ProxySolution fine = solveProxy(surf, surf.triangleAt(rough.point.x, rough.point.y), hip);
    fine.steps += rough.steps;
    return fine;
}

} // namespace depthtouch::haptics
