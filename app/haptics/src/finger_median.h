#pragma once
/// \file
/// \brief The median of nine heights, shared by the fingertip renderer's plane fit
/// (finger_plane.cpp) and its update (finger_renderer.cpp). Private to dt_haptics.
/// Thread-safety: a pure function.

#include <algorithm>

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

} // namespace depthtouch::haptics
