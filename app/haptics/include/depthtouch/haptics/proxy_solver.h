#pragma once
/// \file
/// \brief The god-object proxy update on an implicit grid surface (paper III; Zilles & Salisbury,
/// Ruspini): from the triangle where the proxy met the surface, the proxy slides to the surface
/// point closest to the HIP, across faces, edges and vertices, within one update.
///
/// Method: local descent over triangles. The closest point of the current triangle to the HIP is
/// computed exactly; if it lies on an edge or a vertex, the triangles sharing that edge or vertex
/// are tried, and the proxy moves to the one whose closest point is nearer. It stops when no
/// neighbour is nearer: on a face (1 active constraint plane), on a convex or concave edge (2) or
/// at a vertex or a concave corner (3 or more). The result satisfies the god-object's optimality
/// conditions; every intermediate point is on the surface, so the proxy never ends below it. Works
/// on the same grid-surface types as collision.h. Thread-safety: reentrant; no allocation.

#include <algorithm>
#include <cmath>
#include <cstdint>

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

/// \brief The triangle across edge \a region (EdgeAB, EdgeBC or EdgeCA) of \a tri on a W×H grid.
/// \return false when that edge is on the grid's border (no triangle across it).
inline bool triangleAcrossEdge(int w, int h, const TriangleId &tri, TriangleRegion region,
                               TriangleId &out) noexcept
{
    // upper 0 = (c,r) (c+1,r) (c+1,r+1): AB is the top edge, BC the right edge, CA the diagonal;
    // upper 1 = (c,r) (c+1,r+1) (c,r+1): AB is the diagonal, BC the bottom edge, CA the left edge.
    const int c = tri.c;
    const int r = tri.r;
    if (tri.upper == 0) {
        out = region == TriangleRegion::EdgeAB   ? TriangleId{c, r - 1, 1}
              : region == TriangleRegion::EdgeBC ? TriangleId{c + 1, r, 1}
                                                 : TriangleId{c, r, 1};
    } else {
        out = region == TriangleRegion::EdgeAB   ? TriangleId{c, r, 0}
              : region == TriangleRegion::EdgeBC ? TriangleId{c, r + 1, 0}
                                                 : TriangleId{c - 1, r, 0};
    }
    return out.c >= 0 && out.c <= w - 2 && out.r >= 0 && out.r <= h - 2;
}

/// \brief closestPointOnTriangle() for triangle VXY seen from its corner V, with the quantities
/// the vertex step has already: edges `ex = X − V`, `ey = Y − V`, `gx = (P − V)·ex`,
/// `gy = (P − V)·ey`. Same Voronoi-region tests (Ericson §5.1.5) with A = V, so
/// the same point up to rounding; the dot products with P − X and P − Y follow from these by
/// subtraction. \a pos gives the positions of V, X, Y in the triangle's own vertex order, for
/// \a region. \pre gx > 0 or gy > 0 (V is not the answer). Forced inline: the vertex step calls it
/// for up to five triangles, and inlined it costs about half as many instructions.
[[gnu::always_inline]] inline glm::dvec3
closestPointOnCorner(const glm::dvec3 &v, const glm::dvec3 &x, const glm::dvec3 &y,
                     const glm::dvec3 &ex, const glm::dvec3 &ey, double gx, double gy,
                     const int (&pos)[3], TriangleRegion &region) noexcept
{
    auto vertexRegion = [](int k) {
        return k == 0 ? TriangleRegion::VertexA
                      : (k == 1 ? TriangleRegion::VertexB : TriangleRegion::VertexC);
    };
    auto edgeRegion = [](int p, int q) {
        const int sum = p + q; // {0,1} → 1, {0,2} → 2, {1,2} → 3
        return sum == 1 ? TriangleRegion::EdgeAB
                        : (sum == 3 ? TriangleRegion::EdgeBC : TriangleRegion::EdgeCA);
    };
    const double xx = glm::dot(ex, ex);
    const double yy = glm::dot(ey, ey);
    const double xy = glm::dot(ex, ey);
    const double d1 = gx;
    const double d2 = gy;
    const double d3 = gx - xx; // ex·(P − X)
    const double d4 = gy - xy; // ey·(P − X)
    if (d3 >= 0.0 && d4 <= d3) {
        region = vertexRegion(pos[1]);
        return x;
    }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        region = edgeRegion(pos[0], pos[1]);
        return v + (d1 / (d1 - d3)) * ex;
    }
    const double d5 = gx - xy; // ex·(P − Y)
    const double d6 = gy - yy; // ey·(P − Y)
    if (d6 >= 0.0 && d5 <= d6) {
        region = vertexRegion(pos[2]);
        return y;
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        region = edgeRegion(pos[0], pos[2]);
        return v + (d2 / (d2 - d6)) * ey;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        region = edgeRegion(pos[1], pos[2]);
        return x + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (y - x);
    }
    region = TriangleRegion::Face;
    const double denom = 1.0 / (va + vb + vc);
    return v + ex * (vb * denom) + ey * (vc * denom);
}

/// \brief The six triangles around a grid vertex V and the ring of its six neighbours.
///
/// Ring j is V + (kRingDc[j], kRingDr[j]): E, SE, S, W, NW, N (rows grow downward); ring index 6
/// stands for V. Triangle i is (V.c + kTriDc[i], V.r + kTriDr[i], kTriUpper[i]) and kTriVerts[i]
/// gives its vertices in triangleVertex() order as ring indices.
struct VertexStar {
    static constexpr int kRingDc[6] = {1, 1, 0, -1, -1, 0};
    static constexpr int kRingDr[6] = {0, 1, 1, 0, -1, -1};
    static constexpr int kTriDc[6] = {0, 0, -1, -1, -1, 0};
    static constexpr int kTriDr[6] = {0, 0, 0, -1, -1, -1};
    static constexpr int kTriUpper[6] = {0, 1, 0, 0, 1, 1};
    static constexpr int kTriVerts[6][3] = {{6, 0, 1}, {6, 1, 2}, {3, 6, 2},
                                            {4, 5, 6}, {4, 6, 3}, {5, 0, 6}};
    /// The two ring vertices of triangle i besides V, X then Y.
    static constexpr int kTriRing[6][2] = {{0, 1}, {1, 2}, {3, 2}, {4, 5}, {4, 3}, {5, 0}};
    /// Positions (0..2, triangleVertex() order) of V, X and Y in triangle i.
    static constexpr int kTriPos[6][3] = {{0, 1, 2}, {0, 1, 2}, {1, 0, 2},
                                          {2, 0, 1}, {1, 0, 2}, {2, 0, 1}};
    /// Star index of the triangle (V.c + dc, V.r + dr, upper) as [dc + 1][dr + 1][upper]
    /// (−1: that triangle does not have V).
    static constexpr int kStarIndex[2][2][2] = {{{3, 4}, {2, -1}}, {{-1, 5}, {0, 1}}};
};

/// \brief The nearest triangle one descent step has found so far: where the proxy goes next.
struct DescentCandidate {
    TriangleId tri;        ///< Triangle (the current one until a nearer is found).
    glm::dvec3 point;      ///< Its closest point to the HIP, m.
    glm::dvec3 v[3];       ///< Its vertices, triangleVertex() order (set with a nearer triangle).
    TriangleRegion region; ///< The feature \a point lies on.
    double d;              ///< Squared distance from \a point to the HIP, m².
};

/// \brief Takes triangle \a tri (vertices \a a, \a b, \a c, closest point \a q on feature \a rg,
/// at squared distance \a d from the HIP) as \a best when it is nearer by more than \a need asks.
[[gnu::always_inline]] inline void offerTriangle(DescentCandidate &best, double need,
                                                 const TriangleId &tri, const glm::dvec3 &q,
                                                 TriangleRegion rg, double d, const glm::dvec3 &a,
                                                 const glm::dvec3 &b, const glm::dvec3 &c) noexcept
{
    if (d < need && d < best.d) {
        best.d = d;
        best.tri = tri;
        best.point = q;
        best.region = rg;
        best.v[0] = a;
        best.v[1] = b;
        best.v[2] = c;
    }
}

/// \brief The triangle across edge \a region of \a tri (vertices \a cur) and its vertices \a v; the
/// two on the edge are taken from \a cur, not refetched.
/// \return false when that edge is on the grid's border (\a v is then not set).
template <class Surface>
[[gnu::always_inline]] inline bool
triangleAcrossEdge(const Surface &surf, int w, int h, const TriangleId &tri, TriangleRegion region,
                   const glm::dvec3 (&cur)[3], TriangleId &across, glm::dvec3 (&v)[3]) noexcept
{
    if (!triangleAcrossEdge(w, h, tri, region, across))
        return false;
    int cc[3];
    int cr[3];
    for (int k = 0; k < 3; ++k)
        triangleVertex(tri, k, cc[k], cr[k]);
    for (int k = 0; k < 3; ++k) {
        int c = 0;
        int r = 0;
        triangleVertex(across, k, c, r);
        const int same = c == cc[0] && r == cr[0]   ? 0
                         : c == cc[1] && r == cr[1] ? 1
                         : c == cc[2] && r == cr[2] ? 2
                                                    : -1;
        v[k] = same >= 0 ? cur[same] : surf.vertex(c, r);
    }
    return true;
}

/// \brief The descent step from grid vertex V of \a tri (vertex \a region, at \a at bit for bit;
/// vertices \a cur): tries the other triangles around V whose closest point can be nearer than V.
template <class Surface>
[[gnu::always_inline]] inline void
tryAroundVertex(const Surface &surf, int w, int h, const TriangleId &tri, const glm::dvec3 &at,
                TriangleRegion region, const glm::dvec3 (&cur)[3], const glm::dvec3 &hip,
                double need, DescentCandidate &best) noexcept
{
    using Star = VertexStar;
    const int k = region == TriangleRegion::VertexA ? 0 : region == TriangleRegion::VertexB ? 1 : 2;
    int vc = 0;
    int vr = 0;
    triangleVertex(tri, k, vc, vr);
    // The current triangle is star triangle i0; its vertices are known already.
    const int i0 = Star::kStarIndex[tri.c - vc + 1][tri.r - vr + 1][tri.upper];
    glm::dvec3 ring[7];
    bool known[7] = {false, false, false, false, false, false, true};
    ring[6] = at;
    for (int m = 0; m < 3; ++m) {
        ring[Star::kTriVerts[i0][m]] = cur[m];
        known[Star::kTriVerts[i0][m]] = true;
    }
    const bool interior = vc >= 1 && vc <= w - 2 && vr >= 1 && vr <= h - 2;
    const glm::dvec3 toHip = hip - at;
    // Edges from V and how far the HIP lies along each: g_j = (hip − V)·(X_j − V).
    glm::dvec3 edge[6]{}; // zero outside the grid (never read there)
    double along[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    // Unrolled: the star tables then become constants (the step's hottest loops).
#pragma GCC unroll 6
    for (int j = 0; j < 6; ++j) {
        const int c = vc + Star::kRingDc[j];
        const int r = vr + Star::kRingDr[j];
        if (!interior && (c < 0 || c >= w || r < 0 || r >= h))
            continue;
        if (!known[j])
            ring[j] = surf.vertex(c, r);
        edge[j] = ring[j] - at;
        along[j] = glm::dot(edge[j], toHip);
    }
#pragma GCC unroll 6
    for (int i = 0; i < 6; ++i) {
        if (i == i0)
            continue;
        const TriangleId t{vc + Star::kTriDc[i], vr + Star::kTriDr[i], Star::kTriUpper[i]};
        if (!interior && (t.c < 0 || t.c > w - 2 || t.r < 0 || t.r > h - 2))
            continue;
        const int a = Star::kTriRing[i][0];
        const int b = Star::kTriRing[i][1];
        // The HIP behind V along both edges: V is this triangle's closest point.
        if (!(along[a] > 0.0) && !(along[b] > 0.0))
            continue;
        TriangleRegion rg{};
        const glm::dvec3 q = closestPointOnCorner(at, ring[a], ring[b], edge[a], edge[b], along[a],
                                                  along[b], Star::kTriPos[i], rg);
        const glm::dvec3 dq = q - hip;
        const double d = glm::dot(dq, dq);
        const int *tv = Star::kTriVerts[i];
        offerTriangle(best, need, t, q, rg, d, ring[tv[0]], ring[tv[1]], ring[tv[2]]);
    }
}

/// \return the active constraint planes where the proxy rests on feature \a region: 1 on a face,
/// 2 on an edge, 3 at a vertex.
inline int activeConstraints(TriangleRegion region) noexcept
{
    switch (region) {
    case TriangleRegion::Face:
        return 1;
    case TriangleRegion::EdgeAB:
    case TriangleRegion::EdgeBC:
    case TriangleRegion::EdgeCA:
        return 2;
    default:
        return 3;
    }
}

} // namespace detail

/// \brief Slides the proxy from triangle \a start to the nearest surface point to \a hip.
/// \param start triangle where the proxy met the surface (from firstCrossing()).
/// \param hip haptic interaction point, m (scene-box frame).
///
/// Cost: across an edge only the one triangle beyond it is tried; around a vertex V the six
/// neighbours are computed once for the (up to five) triangles tried, and a triangle VXY is tried
/// only when the HIP lies ahead of V along VX or VY (`(hip − V)·(X − V) > 0`): otherwise V itself
/// is that triangle's closest point, which is not nearer than the proxy already at V. Vertices of
/// the current triangle are reused, never refetched. The triangles moved across and the result are
/// those of trying every triangle around the feature, bit for bit.
template <class Surface>
ProxySolution solveProxy(const Surface &surf, const TriangleId &start,
                         const glm::dvec3 &hip) noexcept
{
    const int w = surf.columns();
    const int h = surf.rows();
    ProxySolution sol;
    sol.triangle = start;
    glm::dvec3 cur[3]; // vertices of sol.triangle, triangleVertex() order
    triangleVertices(surf, start, cur);
    TriangleRegion region{};
    sol.point = closestPointOnTriangle(hip, cur[0], cur[1], cur[2], region);
    glm::dvec3 diff = sol.point - hip;
    double best = glm::dot(diff, diff);
    // A neighbour must be nearer by more than rounding: relative 1e-12 plus (1e-9·s)².
    const double tol = kDescentTolerance * surf.spacing();
    for (; sol.steps < kMaxProxySteps; ++sol.steps) {
        if (region == TriangleRegion::Face)
            break;
        detail::DescentCandidate next;
        next.tri = sol.triangle;
        next.point = sol.point;
        next.region = region;
        next.d = best;
        const double need = best * (1.0 - 1e-12) - tol * tol;
        auto tryTriangle = [&](const TriangleId &tri, const glm::dvec3 &a, const glm::dvec3 &b,
                               const glm::dvec3 &c) {
            TriangleRegion rg{};
            const glm::dvec3 q = closestPointOnTriangle(hip, a, b, c, rg);
            const glm::dvec3 dq = q - hip;
            detail::offerTriangle(next, need, tri, q, rg, glm::dot(dq, dq), a, b, c);
        };
        if (region == TriangleRegion::EdgeAB || region == TriangleRegion::EdgeBC ||
            region == TriangleRegion::EdgeCA) {
            // One candidate: the triangle across the edge.
            TriangleId across{};
            glm::dvec3 v[3];
            if (detail::triangleAcrossEdge(surf, w, h, sol.triangle, region, cur, across, v))
                tryTriangle(across, v[0], v[1], v[2]);
        } else { // the proxy is at a grid vertex (sol.point, bit for bit)
            detail::tryAroundVertex(surf, w, h, sol.triangle, sol.point, region, cur, hip, need,
                                    next);
        }
        if (next.tri == sol.triangle)
            break;
        sol.triangle = next.tri;
        sol.point = next.point;
        region = next.region;
        best = next.d;
        cur[0] = next.v[0];
        cur[1] = next.v[1];
        cur[2] = next.v[2];
    }
    sol.constraints = detail::activeConstraints(region);
    return sol;
}

/// \brief Size of the grid seen every \a stride-th vertex of a W×H grid (StridedSurface), computed
/// once per frame size so that an update does no integer division.
struct CoarseGrid {
    int stride = 0;  ///< Fine cells per coarse cell (< 2: no coarse pass).
    int columns = 0; ///< (W − 1) / stride + 1
    int rows = 0;    ///< (H − 1) / stride + 1
    /// \return the coarse grid of a \a w × \a h grid at \a stride (columns = rows = 0 for stride <
    /// 1).
    static CoarseGrid of(int w, int h, int stride) noexcept
    {
        if (stride < 1)
            return CoarseGrid{stride, 0, 0};
        return CoarseGrid{stride, (w - 1) / stride + 1, (h - 1) / stride + 1};
    }
};

/// \brief A coarser view of a grid surface: every \a stride-th vertex in each direction, the same
/// triangulation rule (docs/architecture.md §3) one level up. A view only: no copy, no allocation;
/// vertex (c, r) is the fine vertex (c·stride, r·stride), so coarse vertices lie on the fine
/// surface. Thread-safety: as the fine surface (const use is reentrant).
template <class Surface>
class StridedSurface {
public:
    /// \param fine the surface to view, \param stride ≥ 1 fine cells per coarse cell.
    StridedSurface(const Surface &fine, int stride) noexcept
        : fine_(fine), stride_(stride), w_((fine.columns() - 1) / stride + 1),
          h_((fine.rows() - 1) / stride + 1)
    {
    }
    /// \brief The same view with its size computed beforehand (no division per construction).
    /// \pre columns == (fine.columns() − 1) / stride + 1, rows likewise (see CoarseGrid).
    StridedSurface(const Surface &fine, int stride, int columns, int rows) noexcept
        : fine_(fine), stride_(stride), w_(columns), h_(rows)
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
        // Truncation is floor() wherever it matters: for u in (−1, 0) both clamp to column 0.
        const int c = std::clamp(static_cast<int>(u), 0, w_ - 2);
        const int r = std::clamp(static_cast<int>(v), 0, h_ - 2);
        return TriangleId{c, r, (u - c) >= (v - r) ? 0 : 1};
    }

private:
    const Surface &fine_;
    int stride_;
    int w_;
    int h_;
};

/// \brief solveProxy() for grids finer than the proxy needs to walk, with a first guess of where
/// the proxy is going.
///
/// The guess is the HIP projected onto the surface's tangent plane at the start, taken from the
/// vertices \a stride cells around it (the god-object optimum of that plane). Facets a few cells
/// wide have noisy normals (a 16-bit depth step over a 3840-wide frame tilts a facet by about a
/// degree), so the plane of the start triangle alone would guess several cells wide of the mark,
/// and a descent from there stops in one of the shallow local optima that noise makes.
/// - When the guess is within \a minCells fine cells (x–y) of the start triangle, the full-grid
///   descent starts at the triangle under the guess.
/// - Else the proxy has far to go: the descent runs first on the surface seen every \a stride-th
///   vertex, then on the full grid from where that ended. The number of triangles crossed per
///   update then no longer grows with the depth resolution (a 1 mm stroke per update is 38 cells of
///   a 3840-wide frame over 0.1 m, but 7 cells at stride 5).
///
/// Either way the result is the same kind of point as solveProxy()'s (a local optimum of the
/// god-object on the full surface, on the surface, never below it); only features narrower than
/// \a stride cells between the old and the new proxy can be passed over.
/// \param grid the coarse grid (CoarseGrid::of()); its stride is fine cells per coarse cell.
///   A stride under 2, or a surface too small for it, runs solveProxy() alone.
/// \param minCells the largest first-guess move, fine cells; farther, the coarse pass runs.
///   ≤ 0: no guess, the coarse pass runs (for a move known to be long, e.g. a fast HIP).
template <class Surface>
ProxySolution solveProxyCoarseToFine(const Surface &surf, const TriangleId &start,
                                     const glm::dvec3 &hip, const CoarseGrid &grid,
                                     double minCells) noexcept
{
    const int stride = grid.stride;
    if (stride < 2 || surf.columns() < 2 * stride + 1 || surf.rows() < 2 * stride + 1)
        return solveProxy(surf, start, hip);
    // No guess asked for (minCells ≤ 0, a long move known beforehand): straight to the coarse pass,
    // without reading the stencil's rows.
    if (minCells > 0.0) {
        // Tangent plane at the start from central differences over ±stride vertices.
        const int c = std::clamp(start.c, stride, surf.columns() - 1 - stride);
        const int r = std::clamp(start.r, stride, surf.rows() - 1 - stride);
        const glm::dvec3 west = surf.vertex(c - stride, r);
        const glm::dvec3 east = surf.vertex(c + stride, r);
        const glm::dvec3 north = surf.vertex(c, r - stride);
        const glm::dvec3 south = surf.vertex(c, r + stride);
        const glm::dvec3 n = glm::cross(east - west, south - north);
        const double nn = glm::dot(n, n);
        const glm::dvec3 centre = 0.25 * (west + east + north + south);
        const glm::dvec3 guess = nn > 0.0 ? hip - (glm::dot(hip - centre, n) / nn) * n : hip;
        const double du = surf.xToColumn(guess.x) - (start.c + 0.5);
        const double dv = surf.yToRow(guess.y) - (start.r + 0.5);
        if (du * du + dv * dv <= minCells * minCells) // false for NaN
            return solveProxy(surf, surf.triangleAt(guess.x, guess.y), hip);
    }
    const StridedSurface<Surface> coarse(surf, stride, grid.columns, grid.rows);
    const double sx = surf.columnToX(start.c + 0.5);
    const double sy = surf.rowToY(start.r + 0.5);
    const ProxySolution rough = solveProxy(coarse, coarse.triangleAt(sx, sy), hip);
    ProxySolution fine = solveProxy(surf, surf.triangleAt(rough.point.x, rough.point.y), hip);
    fine.steps += rough.steps;
    return fine;
}

/// \brief solveProxyCoarseToFine() with the coarse grid of \a stride computed here.
template <class Surface>
ProxySolution solveProxyCoarseToFine(const Surface &surf, const TriangleId &start,
                                     const glm::dvec3 &hip, int stride, double minCells) noexcept
{
    return solveProxyCoarseToFine(surf, start, hip,
                                  CoarseGrid::of(surf.columns(), surf.rows(), stride), minCells);
}

} // namespace depthtouch::haptics
