/// \file
/// \brief The fingertip renderer's finger-scale surface (finger_renderer.h, step 1): the
/// least-squares plane of the 3×3 stencil of half-width r at a point, and the projection on it.
/// Thread-safety: pure functions of the height field they read.

#include "depthtouch/haptics/finger_renderer.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "finger_median.h"

namespace depthtouch::haptics {

namespace {

/// \return how far the mean of the nine taps lies above the least-squares quadric through them at
/// the centre, m, blended out where the quadric does not fit (an edge, a flying pixel). On a curved
/// surface the plane's mean is off by (2/3)(d + e), d and e the quadric's curvature terms in tap
/// units (the 3×3 Savitzky-Golay intercept of order 2 is the mean minus that: weights −1 at the
/// corners, 2 at the sides, 5 at the centre, over 9). Where the quadric's RMS residual exceeds
/// r/50 (30 µm at r = 1.5 mm), the correction fades out linearly to none at r/25: on an edge, a
/// step or 8-bit noise the quadric's intercept weighs single taps up to 5/9 and would step the
/// force as a tap crosses the edge (on the bench's synthetic forearm, r/10 tripled the worst
/// stroke's spikes).
double curvatureCorrection(const double (&t)[9], double r, double &weight) noexcept
{
    double s = 0.0, si = 0.0, sj = 0.0, sx = 0.0, sy = 0.0, sxy = 0.0;
    for (int k = 0; k < 9; ++k) {
        const int i = k % 3 - 1;
        const int j = k / 3 - 1;
        s += t[k];
        si += i != 0 ? t[k] : 0.0;
        sj += j != 0 ? t[k] : 0.0;
        sx += i * t[k];
        sy += j * t[k];
        sxy += i * j * t[k];
    }
    // Normal equations of z = a + b·i + c·j + d·i² + e·j² + f·i·j on the grid (i, j ∈ {−1, 0, 1}).
    const double u = 0.5 * (si + sj - 4.0 / 3.0 * s); // d + e
    const double v = 0.5 * (si - sj);                 // d − e
    const double d = 0.5 * (u + v);
    const double e = 0.5 * (u - v);
    const double a = (s - 6.0 * u) / 9.0;
    const double b = sx / 6.0;
    const double c = sy / 6.0;
    const double f = sxy / 4.0;
    double rss = 0.0;
    for (int k = 0; k < 9; ++k) {
        const double i = k % 3 - 1;
        const double j = k / 3 - 1;
        const double res = t[k] - (a + b * i + c * j + d * i * i + e * j * j + f * i * j);
        rss += res * res;
    }
    const double rms = std::sqrt(rss / 9.0);
    weight = std::clamp(2.0 - rms / (0.02 * r), 0.0, 1.0);
    return weight * (2.0 / 3.0) * u;
}

/// Where the nine taps fit a quadric (weight \a w of curvatureCorrection()), the slope from the
/// centre row and column alone, blended in by \a w: the plane's slope averages the three rows'
/// (columns') differences, and on a curved patch the outer rows' slopes differ from the centre's
/// by the cross curvature (f_xyy·r²/2 each). On the bench's moving wave at r = 1.5 mm that
/// averaging left the slope 2–3 % short and the force 0.04 N off at 6 N (clean-wave force RMS
/// error with the HIP still 0.057 → 0.042 N). On an edge or noisy depth (w = 0) the plane's
/// slope over all nine taps is kept: two taps alone have √3 times its noise. \a t are the taps
/// (m, row-major as FingerPlane::taps), \a rx and \a ry their spacing (m); \a p's slope is
/// dimensionless.
void refineSlope(const double (&t)[9], double rx, double ry, double w, FingerPlane &p) noexcept
{
    const double gx = (t[5] - t[3]) / (2.0 * rx);
    const double gy = (t[7] - t[1]) / (2.0 * ry);
    p.gx += w * (gx - p.gx);
    p.gy += w * (gy - p.gy);
}

/// The normal equations of z = a + bx·i + by·j over the taps a predicate keeps (tap (i, j) of the
/// 3×3 stencil, i, j ∈ {−1, 0, 1}), solved by Cramer's rule.
struct PlaneSums {
    double n = 0, si = 0, sj = 0, sii = 0, sjj = 0, sij = 0, sh = 0, sih = 0, sjh = 0;

    [[nodiscard]] double det() const noexcept
    {
        return n * (sii * sjj - sij * sij) - si * (si * sjj - sij * sj) +
               sj * (si * sij - sii * sj);
    }
    void solve(double &a, double &bx, double &by) const noexcept
    {
        const double d = det();
        a = (sh * (sii * sjj - sij * sij) - si * (sih * sjj - sij * sjh) +
             sj * (sih * sij - sii * sjh)) /
            d;
        bx = (n * (sih * sjj - sij * sjh) - sh * (si * sjj - sij * sj) +
              sj * (si * sjh - sih * sj)) /
             d;
        by = (n * (sii * sjh - sih * sij) - si * (si * sjh - sih * sj) +
              sh * (si * sij - sii * sj)) /
             d;
    }
};

template <class Keep> PlaneSums planeSums(const double (&taps)[9], Keep keep) noexcept
{
    PlaneSums s;
    for (int k = 0; k < 9; ++k) {
        if (!keep(taps[k]))
            continue;
        const double i = k % 3 - 1;
        const double j = k / 3 - 1;
        s.n += 1;
        s.si += i;
        s.sj += j;
        s.sii += i * i;
        s.sjj += j * j;
        s.sij += i * j;
        s.sh += taps[k];
        s.sih += i * taps[k];
        s.sjh += j * taps[k];
    }
    return s;
}

} // namespace

FingerPlane fitFingerPlane(const HeightField &field, double x, double y, double r) noexcept
{
    // Keep the stencil on the grid: its centre is clamped so that every tap lies inside.
    const double halfX = 0.5 * (field.columns() - 1) * field.spacing();
    const double halfY = 0.5 * (field.rows() - 1) * field.spacing();
    const double reachX = std::min(r, halfX);
    const double reachY = std::min(r, halfY);
    const double cx = std::clamp(x, -halfX + reachX, halfX - reachX);
    const double cy = std::clamp(y, -halfY + reachY, halfY - reachY);
    FingerPlane p;
    double(&taps)[9] = p.taps;
    for (int k = 0; k < 9; ++k)
        taps[k] = field.heightAt(cx + (k % 3 - 1) * reachX, cy + (k / 3 - 1) * reachY);
    // The median of the nine: on the side of a silhouette where most of the stencil is, and
    // blind to a lone outlier (a flying pixel or speckle) that the centre sample may be.
    const double median = median9(taps);
    // Least squares z = a + bx·i + by·j over the taps within kFingerOutlier·r of the median: a
    // tap across a silhouette or on a flying pixel would tilt the plane of the side the finger
    // is on. Where too few are kept to span a plane (a side steeper than the rule allows, a hole
    // beside it), the plane is flat at the median and not spanned (FingerPlane::spanned).
    const double keep = kFingerOutlier * r;
    const PlaneSums sums =
        planeSums(taps, [&](double tap) { return std::fabs(tap - median) <= keep; });
    double a = median;
    double bx = 0.0;
    double by = 0.0;
    const double n = sums.n;
    p.spanned = sums.det() > 0.5; // 1 for the fewest taps that span a plane; 324 for all nine
    if (p.spanned)
        sums.solve(a, bx, by);
    double smooth = 0.0;
    if (n == 9.0)
        a -= curvatureCorrection(taps, r, smooth);
    p.smooth = smooth;
    p.x = cx;
    p.y = cy;
    p.gx = reachX > 0.0 ? bx / reachX : 0.0; // tap (i, j) is at (x + i·reach, y + j·reach)
    p.gy = reachY > 0.0 ? by / reachY : 0.0;
    if (smooth > 0.0 && reachX > 0.0 && reachY > 0.0)
        refineSlope(taps, reachX, reachY, smooth, p);
    // The fitted height, but within r/4 of the median: across a silhouette the fit of a step
    // would be half-way, and a finger there would be inside the object with no force
    // (pop-through) on the near side, or pushed above the backdrop (phantom force) at its foot.
    const double margin = 0.25 * r;
    p.height = std::clamp(a, median - margin, median + margin);
    // Nor more than r/4 under what was measured at the centre: its tap, and the median of its
    // pixel and the eight around it (a lone flying pixel is no surface), where that stands less
    // than a cut over the median (more is another surface over this one: an object over the
    // finger). A top narrower than the stencil (a board on edge, a cable) is a minority of the
    // taps; the median is the surface beside it, and a finger centred on it was inside it with
    // no force (`bench feel`'s synthetic-ridges: 182 ms of pop-through tracing a board's top).
    const double floor = taps[4] - margin;
    if (floor > p.height) {
        const double centre = std::min(taps[4], pixelMedian(field, cx, cy)) - margin;
        if (centre > p.height && centre + margin - median <= field.cutThreshold())
            p.height = centre;
    }
    return p;
}

glm::dvec3 projectOnPlane(const FingerPlane &plane, const glm::dvec3 &p, double &below) noexcept
{
    // Plane: z − height − gx·(x − x0) − gy·(y − y0) = 0, normal n = (−gx, −gy, 1) / |n|.
    const glm::dvec3 n(-plane.gx, -plane.gy, 1.0);
    const double nn = glm::dot(n, n);
    const double f = plane.height + plane.gx * (p.x - plane.x) + plane.gy * (p.y - plane.y) - p.z;
    // f > 0: p is under the plane by f vertically, by f / |n| along the normal.
    below = f / std::sqrt(nn);
    return p + (f / nn) * n;
}

} // namespace depthtouch::haptics
