#pragma once
/// \file
/// \brief Collision detection of the proxy graph (paper III, Fig. 4c; Walker & Salisbury): the
/// segment from the previous proxy to the HIP is projected onto the grid, the cells it crosses are
/// walked in order (2-D DDA), a cell is skipped when all its vertex heights are below the segment's
/// lowest z inside it, and only the remaining cells' two triangles are tested exactly.
///
/// Works on any *grid surface* type S with: `int columns()`, `int rows()`, `double spacing()`,
/// `double xToColumn(double)`, `double yToRow(double)`, `double columnToX(double)`,
/// `double rowToY(double)`, `double vertexZ(int c, int r)` and `glm::dvec3 vertex(int c, int r)`
/// (HeightField is one). Thread-safety: reentrant; no allocation.

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/vec3.hpp>

#include "depthtouch/haptics/geometry.h"
#include "depthtouch/haptics/height_field.h"

namespace depthtouch::haptics {

/// Relative tolerance of every surface test: a point is "on" the surface when it is within
/// kSurfaceTolerance·s of it (s = pixel spacing, m). 1e-9 of a 0.14 mm triangle is 1.4e-13 m,
/// far above double rounding on a 0.1 m box (~1e-17 m) and far below anything a user can feel.
inline constexpr double kSurfaceTolerance = 1e-9;

/// \brief The first place where a segment passes from above the surface to below it.
struct Crossing {
    bool hit = false;       ///< A crossing was found.
    double t = 0.0;         ///< Segment parameter of the crossing, [0, 1].
    glm::dvec3 point{};     ///< Crossing point on the surface, m (scene-box frame).
    TriangleId triangle{};  ///< Triangle crossed.
    int cellsVisited = 0;   ///< Cells the DDA walked.
    int cellsTested = 0;    ///< Cells not skipped by the height test (triangles tested exactly).
};

/// \brief One exact test of the brute-force reference and of the mesh-bvh baseline: when the
/// segment \a p0 → \a p1 crosses triangle \a tri of \a surf downward
/// (segmentCrossesTriangleDownward() with barycentric tolerance \a baryTol and parameter tolerance
/// 1e-12) at a parameter below \a best, records it as the nearest so far: \a best, and hit, t
/// (clamped to ≥ 0) and triangle of \a out. Reentrant; allocation-free.
template <class Surface>
void keepNearerCrossing(const Surface &surf, const TriangleId &tri, const glm::dvec3 &p0,
                        const glm::dvec3 &p1, double baryTol, double &best, Crossing &out) noexcept
{
    glm::dvec3 v[3];
    triangleVertices(surf, tri, v);
    double t = 0.0;
    if (segmentCrossesTriangleDownward(p0, p1, v[0], v[1], v[2], baryTol, 1e-12, t) && t < best) {
        best = t;
        out.hit = true;
        out.t = std::max(t, 0.0);
        out.triangle = tri;
    }
}

/// \brief Where the walk of firstCrossing() is: not yet known, above the surface, below it.
enum class CrossingState { Unknown, Above, Below };

/// \brief The segment of firstCrossing() in grid units: u = u0 + t·du (columns), v = v0 + t·dv
/// (rows), z = p0.z + t·dz (m).
struct GridSegment {
    double u0, v0, du, dv, dz;
};

/// \brief Heights of the corners (c, r), (c + 1, r), (c, r + 1), (c + 1, r + 1) of a cell, m.
struct CellCorners {
    double h00, h10, h01, h11;
};

/// \brief The exact test of firstCrossing() in cell (\a c, \a r), corner heights \a corners, over
/// segment parameters [\a tA, \a tB]: each piece of the segment over one of the cell's two
/// triangles is tested on that triangle's plane, in order, updating \a state.
/// \return true at the first downward crossing, with \a out's hit, t, triangle and point set.
[[gnu::always_inline]] inline bool crossCell(const glm::dvec3 &p0, const glm::dvec3 &p1,
                                             const GridSegment &seg, int c, int r,
                                             const CellCorners &corners, double tA, double tB,
                                             double tol, CrossingState &state,
                                             Crossing &out) noexcept
{
    using State = CrossingState;
    const double u0 = seg.u0;
    const double v0 = seg.v0;
    const double du = seg.du;
    const double dv = seg.dv;
    const double dz = seg.dz;
    const double h00 = corners.h00;
    const double h10 = corners.h10;
    const double h01 = corners.h01;
    const double h11 = corners.h11;
    // Split at the diagonal (u − c) = (v − r): d(t) = (u0 − c − v0 + r) + t·(du − dv).
    const double d0 = u0 - c - v0 + r;
    const double dd = du - dv;
    double pieces[3] = {tA, tB, tB};
    int nPieces = 1;
    if (dd != 0.0) {
        const double tD = -d0 / dd;
        if (tD > tA && tD < tB) {
            pieces[1] = tD;
            nPieces = 2;
        }
    }
    for (int k = 0; k < nPieces; ++k) {
        const double pa = pieces[k];
        const double pb = pieces[k + 1];
        const double tm = 0.5 * (pa + pb);
        const int upper = (d0 + tm * dd) >= 0.0 ? 0 : 1;
        auto g = [&](double t) {
            const double fu = u0 + t * du - c;
            const double fv = v0 + t * dv - r;
            const double hs = upper == 0 ? h00 + fu * (h10 - h00) + fv * (h11 - h10)
                                         : h00 + fv * (h01 - h00) + fu * (h11 - h01);
            return p0.z + t * dz - hs;
        };
        const double ga = g(pa);
        const double gb = g(pb);
        if (state == State::Unknown)
            state = ga >= -tol ? State::Above : State::Below;
        if (state == State::Above) {
            if (gb < -tol) {
                const double tc = ga <= 0.0 ? pa : pa + (pb - pa) * (ga / (ga - gb));
                out.hit = true;
                out.t = tc;
                out.triangle = TriangleId{c, r, upper};
                out.point = p0 + tc * (p1 - p0);
                // Put the point exactly on the crossed plane (removes rounding along z).
                const double fu = u0 + tc * du - c;
                const double fv = v0 + tc * dv - r;
                out.point.z = upper == 0 ? h00 + fu * (h10 - h00) + fv * (h11 - h10)
                                         : h00 + fv * (h01 - h00) + fu * (h11 - h01);
                return true;
            }
        } else if (gb >= -tol) {
            state = State::Above; // came back out of the surface
        }
    }
    return false;
}

/// \brief First downward crossing of segment \a p0 → \a p1 with the height field (2-D DDA walk).
///
/// "Below" means z < h(x, y) − tol with tol = kSurfaceTolerance·s. A segment that starts below the
/// surface is not in collision until it has come back above it (the proxy-graph failure of paper
/// IV.A, Fig. 5). The part of the segment outside the grid's x–y extent is free space.
/// \param p0, p1 segment ends, m, scene-box frame.
/// \return the crossing (hit == false when none); exact up to rounding: the surface is piecewise
/// linear along the segment and each piece is tested on its own triangle's plane.
template <class Surface>
Crossing firstCrossing(const Surface &surf, const glm::dvec3 &p0, const glm::dvec3 &p1) noexcept
{
    Crossing out;
    const int w = surf.columns();
    const int h = surf.rows();
    if (w < 2 || h < 2)
        return out;
    const double tol = kSurfaceTolerance * surf.spacing();
    const double u0 = surf.xToColumn(p0.x);
    const double v0 = surf.yToRow(p0.y);
    const double du = surf.xToColumn(p1.x) - u0;
    const double dv = surf.yToRow(p1.y) - v0;
    const double dz = p1.z - p0.z;
    const double uMax = w - 1;
    const double vMax = h - 1;
    const GridSegment seg{u0, v0, du, dv, dz};

    // Clip the parameter range to the grid rectangle (slabs in u and v).
    double tMin = 0.0;
    double tMax = 1.0;
    auto clip = [&](double start, double delta, double hi) {
        if (delta == 0.0)
            return start >= 0.0 && start <= hi;
        double ta = (0.0 - start) / delta;
        double tb = (hi - start) / delta;
        if (ta > tb)
            std::swap(ta, tb);
        tMin = std::max(tMin, ta);
        tMax = std::min(tMax, tb);
        return tMin <= tMax;
    };
    if (!clip(u0, du, uMax) || !clip(v0, dv, vMax))
        return out;

    // Start cell; on a cell border, take the cell the segment goes into.
    const double uS = std::clamp(u0 + tMin * du, 0.0, uMax);
    const double vS = std::clamp(v0 + tMin * dv, 0.0, vMax);
    int c = std::clamp(static_cast<int>(std::floor(uS)), 0, w - 2);
    int r = std::clamp(static_cast<int>(std::floor(vS)), 0, h - 2);
    if (du < 0.0 && uS == static_cast<double>(c) && c > 0)
        --c;
    if (dv < 0.0 && vS == static_cast<double>(r) && r > 0)
        --r;
    const int stepC = du > 0.0 ? 1 : -1;
    const int stepR = dv > 0.0 ? 1 : -1;
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const double tDeltaU = du != 0.0 ? std::fabs(1.0 / du) : kInf;
    const double tDeltaV = dv != 0.0 ? std::fabs(1.0 / dv) : kInf;
    double tNextU = du > 0.0 ? (c + 1 - u0) / du : (du < 0.0 ? (c - u0) / du : kInf);
    double tNextV = dv > 0.0 ? (r + 1 - v0) / dv : (dv < 0.0 ? (r - v0) / dv : kInf);

    using State = CrossingState;
    State state = State::Unknown;
    double tA = tMin;
    for (;;) {
        const double tB = std::min({tNextU, tNextV, tMax});
        ++out.cellsVisited;
        const double zA = p0.z + tA * dz;
        const double zB = p0.z + tB * dz;
        const double h00 = surf.vertexZ(c, r);
        const double h10 = surf.vertexZ(c + 1, r);
        const double h01 = surf.vertexZ(c, r + 1);
        const double h11 = surf.vertexZ(c + 1, r + 1);
        const double hMax = std::max(std::max(h00, h10), std::max(h01, h11));
        if (state != State::Below && hMax < std::min(zA, zB) - tol) {
            state = State::Above; // Walker & Salisbury: the whole cell lies below the segment
        } else {
            ++out.cellsTested;
            if (crossCell(p0, p1, seg, c, r, CellCorners{h00, h10, h01, h11}, tA, tB, tol, state,
                          out))
                return out;
        }
        if (tB >= tMax)
            break;
        if (tNextU < tNextV) {
            c += stepC;
            tA = tNextU;
            tNextU += tDeltaU;
        } else {
            r += stepR;
            tA = tNextV;
            tNextV += tDeltaV;
        }
        if (c < 0 || c > w - 2 || r < 0 || r > h - 2)
            break;
    }
    return out;
}

/// \brief Brute-force reference of firstCrossing(): tests every triangle of every cell inside the
/// segment's x–y bounding rectangle with the general segment–triangle test (no DDA, no skipping).
/// For tests only: cost grows with the rectangle's area.
template <class Surface>
Crossing firstCrossingBruteForce(const Surface &surf, const glm::dvec3 &p0,
                                 const glm::dvec3 &p1) noexcept
{
    Crossing out;
    const int w = surf.columns();
    const int h = surf.rows();
    const double uLo = std::min(surf.xToColumn(p0.x), surf.xToColumn(p1.x));
    const double uHi = std::max(surf.xToColumn(p0.x), surf.xToColumn(p1.x));
    const double vLo = std::min(surf.yToRow(p0.y), surf.yToRow(p1.y));
    const double vHi = std::max(surf.yToRow(p0.y), surf.yToRow(p1.y));
    const int c0 = std::max(0, static_cast<int>(std::floor(uLo)) - 1);
    const int c1 = std::min(w - 2, static_cast<int>(std::floor(uHi)) + 1);
    const int r0 = std::max(0, static_cast<int>(std::floor(vLo)) - 1);
    const int r1 = std::min(h - 2, static_cast<int>(std::floor(vHi)) + 1);
    double best = std::numeric_limits<double>::infinity();
    for (int r = r0; r <= r1; ++r) {
        for (int c = c0; c <= c1; ++c) {
            for (int upper = 0; upper < 2; ++upper)
                keepNearerCrossing(surf, TriangleId{c, r, upper}, p0, p1, 1e-12, best, out);
        }
    }
    if (out.hit)
        out.point = p0 + out.t * (p1 - p0);
    return out;
}

} // namespace depthtouch::haptics
