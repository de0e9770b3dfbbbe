#pragma once
/// \file
/// \brief Cell arithmetic shared by the adaptive mesh's files, private to dt_render: the integer
/// log2 of a block size, the walk over a block's cells at a step, the value of a cell's
/// two-triangle surface, and the error a sample counts beside a hole.
/// Thread-safety: pure functions.

#include <algorithm>

namespace depthtouch::render::mesh {

/// \return floor(log2(\a v)) for \a v >= 1.
inline int log2i(int v) noexcept
{
    int l = 0;
    while ((1 << (l + 1)) <= v)
        ++l;
    return l;
}

/// Value at (c, r) of the linear triangle surface of the cell (ca..cb, ra..rb) split by its
/// top-left → bottom-right diagonal (docs/architecture.md §3).
inline double cellValue(double z00, double z10, double z11, double z01, double u, double v) noexcept
{
    if (u >= v)
        return z00 + u * (z10 - z00) + v * (z11 - z10);
    return z00 + v * (z01 - z00) + u * (z11 - z01);
}

/// Visits the cells of step \a s of the block of samples (c0..c1, r0..r1), row-major, the last row
/// and column cut at the block's edge: \a cell(a, b, c, d) with the vertex numbers \a vertex(c, r)
/// gives its corners, a top-left, b top-right, c bottom-right, d bottom-left. Its two triangles
/// split top-left → bottom-right are (a, b, c) and (a, c, d) (docs/architecture.md §3).
template <class Vertex, class Cell>
inline void forEachCell(int c0, int r0, int c1, int r1, int s, const Vertex &vertex, Cell &&cell)
{
    for (int ra = r0; ra < r1; ra += s) {
        const int rb = std::min(ra + s, r1);
        for (int ca = c0; ca < c1; ca += s) {
            const int cb = std::min(ca + s, c1);
            cell(vertex(ca, ra), vertex(cb, ra), vertex(cb, rb), vertex(ca, rb));
        }
    }
}

/// Holes (docs/architecture.md §3): the error of a sample where a block's coverage is wrong, a hole
/// under a drawn block or a measured sample under a block that is not drawn (it has a hole
/// corner). Above any cap, so such a block is split like one across a depth edge, down to single
/// cells (whose samples are their corners, never wrong); it is not added to error sums: the code
/// of a hole is not a depth, and its jump to a measured neighbour is no geometric error.
constexpr float kCoverageError = 1e6f;

/// \return the error a sample of geometric error \a geometric counts in a block: \a geometric where
/// it is measured (\a hole false) under a drawn block, 0 where it is a hole under a block not
/// drawn, \a mismatch (kCoverageError, or 0 for a single cell) where the coverage is wrong.
inline float sampleError(float geometric, bool hole, bool drawn, float mismatch) noexcept
{
    return drawn ? (hole ? mismatch : geometric) : (hole ? 0.0f : mismatch);
}

} // namespace depthtouch::render::mesh
