/// \file
/// \brief The fingertip renderer's wall contact: a finger that moves into an object's silhouette
/// from the side meets the object's side as a wall (renderer.h, finger_renderer.h step 3).
///
/// A height field is solid under its surface, so an object seen by a depth camera stands on the
/// surface behind it as a column: its silhouette is a wall as tall as the depth step. A free HIP
/// that crosses that wall sideways (a swipe from the backdrop onto a person, a circle across an
/// arm's edge) comes under the object's top far deeper than a new contact may be caught (the
/// capture depth): taken as *behind* the surface, it would be free and fall into the object for
/// as long as it took to rise above its top (20-60 ms a crossing on `bench feel`'s swipes at
/// 20-50 cm/s: pop-through).
///
/// Method (the god-object of Zilles & Salisbury 1995, on the wall): the proxy is the last point of
/// the HIP's path from the last update that is free (bisection on the segment), and the wall is
/// the vertical plane through it whose outward normal n is the horizontal direction of steepest
/// descent of the surface there (heights ±r apart: a step's gradient points into the object).
/// It is a wall only where a fingertip fits in front of it (roomBefore()): a gap between a
/// keyboard's keys is free space to a point, not to a finger, and a swipe across the keys met
/// each key's side in turn (on a wall, free in the next gap: a force alternating at the servo
/// rate).
/// n is kept for the contact: read again each update at the proxy on a ragged silhouette (a
/// person's edge at 8 bits), it turned the search line, which moved the proxy, which turned n, and
/// the proxy hopped 0.5 mm between an edge's pixels at the servo rate. Each update the wall is
/// found again along n from the HIP: the proxy is HIP + s·n, s the smallest depth along n that is
/// free (bisection), so a moving object's side moves the proxy with it; s may change by the HIP's
/// own motion plus p_.pushDepth an update (the bounded push of limitPush(): a wall that sweeps onto
/// the finger faster than that pushes it out at a bounded rate, and the saturation let-go trips a
/// hand that does not yield; nor does the proxy hop back between an edge's pixels). The force k·s·n
/// is horizontal. Where the top comes as near as the side (the object's upper edge) the proxy turns
/// from the side to the top straight above the HIP over a band of r, a corner rounded at the
/// finger's scale (a 90° step of the force there would be a spike), and the finger leaves the
/// wall for the ordinary contact once the top is nearer by r, the god-object's nearest point. It
/// is free once it is above the surface at its own x–y.
/// Cost: on a wall, one bisection (up to log2(length/searchResolution) + 1 height lookups) and one
/// plane fit an update; when a free HIP comes under the surface, one bisection along its path, 5
/// lookups for the normal, up to 36 for the room in front of the side and one plane fit.
/// Thread-safety: thread-bound (the haptic thread); no allocation.

#include "depthtouch/haptics/finger_renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "finger_median.h"

namespace depthtouch::haptics {

namespace {
/// \return the bisection steps that halve \a length under \a resolution (both m): 0 for a length
/// already under it or NaN, at most a double's mantissa (further halvings change nothing).
int bisections(double length, double resolution) noexcept
{
    if (!(length > resolution))
        return 0;
    const double steps = std::ceil(std::log2(length / resolution));
    return static_cast<int>(std::min(steps, double{std::numeric_limits<double>::digits}));
}
} // namespace

bool FingerRenderer::freeAt(const glm::dvec3 &p) const noexcept
{
    return !field_.contains(p.x, p.y) || field_.heightAt(p.x, p.y) < p.z;
}

bool FingerRenderer::wallNormal(const glm::dvec3 &at, glm::dvec2 &n) const noexcept
{
    const double r = p_.radius;
    auto height = [this](double x, double y, double fallback) {
        return field_.contains(x, y) ? field_.heightAt(x, y) : fallback;
    };
    const double h = height(at.x, at.y, at.z);
    const double taps[4] = {height(at.x + r, at.y, h), height(at.x - r, at.y, h),
                            height(at.x, at.y + r, h), height(at.x, at.y - r, h)};
    const double gx = taps[0] - taps[1];
    const double gy = taps[2] - taps[3];
    const double g = std::sqrt(gx * gx + gy * gy);
    if (!(g > kFingerWallSlope * 2.0 * r))
        return false;
    // Which way the side faces is read from what was measured. A hole's vertices lie holeDrop()
    // under the box (HeightField), and their cliff says a wall is there but not which way it
    // faces: where the hole is a band along an object's side (the backdrop a stereo camera's
    // second view cannot see beside a silhouette) it turned n along the band, and a finger
    // crossing the band into the object read its path as one through the top. A tap on or beside
    // a hole reads as the lowest measured tap, the surface the object stands on.
    double foot = std::numeric_limits<double>::infinity();
    for (const double z : taps)
        if (!field_.besideHole(z))
            foot = std::min(foot, z);
    if (std::isfinite(foot)) {
        const auto measured = [&](int i) { return field_.besideHole(taps[i]) ? foot : taps[i]; };
        const double mx = measured(0) - measured(1);
        const double my = measured(2) - measured(3);
        const double m = std::sqrt(mx * mx + my * my);
        if (m > 0.0) {
            n = glm::dvec2(-mx / m, -my / m);
            return true;
        }
    }
    n = glm::dvec2(-gx / g, -gy / g);
    return true;
}

bool FingerRenderer::roomBefore(const glm::dvec3 &out, const glm::dvec2 &n) const noexcept
{
    // A finger cannot have come through a gap narrower than itself: where the surface in front of
    // the side rises again to the crossing's height within r (between a keyboard's keys, across
    // a dropout a pixel wide), the side is no wall. The surface there is the median of the pixel
    // and the eight around it: a lone flying pixel in front of an object's side is no surface.
    for (int i = 1; i <= 4; ++i) {
        const double d = 0.25 * p_.radius * i;
        const double x = out.x + d * n.x;
        const double y = out.y + d * n.y;
        if (!field_.contains(x, y))
            return true;
        const double z = pixelMedian(field_, x, y);
        if (z >= out.z && !field_.besideHole(z))
            return false;
    }
    return true;
}

bool FingerRenderer::enterWall(const glm::dvec3 &hip, Candidate &c) noexcept
{
    // The last HIP, free at this time, and this one inside: where the path crossed the surface.
    if (!freeAt(lastHip_) || freeAt(hip))
        return false;
    glm::dvec3 out = lastHip_;
    glm::dvec3 in = hip;
    const int steps = bisections(glm::length(in - out), p_.searchResolution);
    for (int i = 0; i < steps; ++i) {
        const glm::dvec3 mid = 0.5 * (out + in);
        (freeAt(mid) ? out : in) = mid;
    }
    glm::dvec2 n{};
    const glm::dvec2 path(hip.x - lastHip_.x, hip.y - lastHip_.y);
    // A path through the top (no horizontal part into the wall) is the ordinary contact.
    if (!wallNormal(out, n) || !(glm::dot(n, path) < 0.0))
        return false;
    const double s = (out.x - hip.x) * n.x + (out.y - hip.y) * n.y;
    if (!(s >= 0.0))
        return false;
    if (!roomBefore(out, n)) {
        c.throughGap = true;
        return false;
    }
    wall_.normal = n;
    wall_.depth = s;
    c.proxy = hip + s * glm::dvec3(n, 0.0);
    c.below = s;
    c.contact = true;
    c.plane = fitFingerPlane(field_, c.proxy.x, c.proxy.y, p_.radius);
    c.wall = true;
    return true;
}

void FingerRenderer::wallContact(const glm::dvec3 &hip, double raw, Candidate &c) noexcept
{
    const glm::dvec3 n(wall_.normal, 0.0);
    // The side: the smallest free depth along n, searched as far as the bounded push reaches (the
    // side's depth grows by the HIP's motion into it and p_.pushDepth an update, as a pushed
    // limitPush()'s: sliding along a ragged side, a jut is pushed in at that rate, not stepped
    // onto by the slide's own motion).
    const double reach = wall_.depth +
                         std::max(0.0, glm::dot(glm::dvec2(lastHip_ - hip), wall_.normal)) +
                         p_.pushDepth;
    double s = reach;
    if (freeAt(hip + s * n)) {
        double in = 0.0;
        const int steps = bisections(s, p_.searchResolution);
        for (int i = 0; i < steps; ++i) {
            const double mid = 0.5 * (in + s);
            (freeAt(hip + mid * n) ? s : in) = mid;
        }
    }
    // A side read on a ragged silhouette (flying pixels, 8-bit steps) moves no faster than the
    // HIP and the bounded push either: the proxy does not hop between the edge's pixels.
    s = std::max(s, wall_.depth - pushReach(hip));
    wall_.depth = s;
    // The corner, rounded over a band of r: the proxy turns from the side (depth s along n) to the
    // top straight above the HIP (depth raw − z) as the top becomes the nearer of the two, and the
    // finger leaves the wall once the top is nearer by r (the god-object's nearest point, without
    // a 90° step of the force at the corner).
    const double top = raw - hip.z;
    const double toTop = std::clamp(0.5 + (s - top) / (2.0 * p_.radius), 0.0, 1.0);
    if (toTop >= 1.0) {
        c.wall = false;
        FingerPlane start{};
        c.proxy = solve(hip, hip.x, hip.y, c.plane, start, c.below);
        if (!(c.below > 0.0)) // the stencil's median is beside the object: straight up
            straightUp(hip, raw, c);
        c.contact = true;
        pushUp(hip, raw, c);
        limitPush(hip, c);
        return;
    }
    c.proxy = hip + (1.0 - toTop) * s * n + glm::dvec3(0.0, 0.0, toTop * top);
    c.contact = true;
    c.below = glm::length(c.proxy - hip);
    c.plane = fitFingerPlane(field_, c.proxy.x, c.proxy.y, p_.radius);
}

} // namespace depthtouch::haptics
