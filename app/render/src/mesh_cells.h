#pragma once
/// \file
/// \brief Cell arithmetic shared by the adaptive mesh's files, private to dt_render: the integer
/// log2 of a block size, the value of a cell's two-triangle surface, and the error a sample counts
/// beside a hole.
/// Thread-safety: pure functions.

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
