#pragma once
/// \file
/// \brief Cell arithmetic shared by the adaptive mesh's files, private to dt_render: the integer
/// log2 of a block size and the value of a cell's two-triangle surface.
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

} // namespace depthtouch::render::mesh
