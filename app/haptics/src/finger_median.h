#pragma once
/// \file
/// \brief The median of nine heights, and of the heights one pixel around a point, shared by the
/// fingertip renderer's plane fit (finger_plane.cpp) and its update (finger_renderer.cpp,
/// finger_descent.cpp). Private to dt_haptics. Thread-safety: pure functions (of the height field
/// they read).

#include <algorithm>

#include "depthtouch/haptics/height_field.h"

namespace depthtouch::haptics {

/// \return the median of nine values: the 19 compare-exchanges of Paeth's median-of-9 network
/// (Graphics Gems, "Median finding on a 3×3 grid"; as in N. Devillard's opt_med9), branch-free.
inline double median9(const double (&in)[9]) noexcept
{
    double p[9];
    std::copy(in, in + 9, p);
    auto sort2 = [&p](int a, int b) {
        const double lo = std::min(p[a], p[b]);
        p[b] = std::max(p[a], p[b]);
        p[a] = lo;
    };
    sort2(1, 2);
    sort2(4, 5);
    sort2(7, 8);
    sort2(0, 1);
    sort2(3, 4);
    sort2(6, 7);
    sort2(1, 2);
    sort2(4, 5);
    sort2(7, 8);
    sort2(0, 3);
    sort2(5, 8);
    sort2(4, 7);
    sort2(3, 6);
    sort2(1, 4);
    sort2(2, 5);
    sort2(4, 7);
    sort2(4, 2);
    sort2(6, 4);
    sort2(4, 2);
    return p[4];
}

/// \return the median of the heights of \a field at (\a x0, \a y0) and one pixel (the grid
/// spacing) around it, m; a point off the grid reads as the centre. One pixel read far back or
/// far forward (a flying pixel, a dropout) is left out; a feature a few pixels wide is not.
/// \pre (x0, y0) is over the grid.
inline double pixelMedian(const HeightField &field, double x0, double y0) noexcept
{
    const double centre = field.heightAt(x0, y0);
    const double s = field.spacing();
    double z[9];
    int k = 0;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const double x = x0 + s * dx;
            const double y = y0 + s * dy;
            z[k++] = field.contains(x, y) ? field.heightAt(x, y) : centre;
        }
    return median9(z);
}

} // namespace depthtouch::haptics
