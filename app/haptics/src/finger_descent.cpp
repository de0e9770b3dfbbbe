/// \file
/// \brief The fingertip renderer's god-object descent on its finger-scale surface
/// (finger_renderer.h, step 2): solve() moves the stencil toward the HIP's projection,
/// keepOnPatch() keeps the proxy on the patch its plane was fitted to, and glide() bounds how far
/// the proxy moves in an update. Private to dt_haptics; thread-bound as the renderer.

#include <cmath>

#include "depthtouch/haptics/finger_renderer.h"
#include "finger_median.h"

namespace depthtouch::haptics {

glm::dvec3 FingerRenderer::solve(const glm::dvec3 &hip, double startX, double startY,
                                 FingerPlane &plane, FingerPlane &start,
                                 double &below) const noexcept
{
    plane = fitFingerPlane(field_, startX, startY, p_.radius);
    start = plane;
    glm::dvec3 p = projectOnPlane(plane, hip, below);
    // The god-object's objective: the distance from the HIP to the surface point at q.
    auto distance = [&hip](const FingerPlane &f) {
        const glm::dvec3 d(f.x - hip.x, f.y - hip.y, f.height - hip.z);
        return glm::dot(d, d);
    };
    double best = distance(plane);
    const double settle = 0.2 * field_.spacing();
    for (int it = 0; it < kFingerIterations; ++it) {
        // Move the stencil to the projection (a Gauss-Newton step), at most its own reach.
        double dx = p.x - plane.x;
        double dy = p.y - plane.y;
        const double d = std::sqrt(dx * dx + dy * dy);
        if (!(d > settle))
            break;
        if (d > p_.radius) {
            dx *= p_.radius / d;
            dy *= p_.radius / d;
        }
        FingerPlane next = fitFingerPlane(field_, plane.x + dx, plane.y + dy, p_.radius);
        // A plane the taps do not span (flat at their median on a side too steep for the outlier
        // rule) is no surface to move onto: beside the head's contour it lay 0.1 mm over a finger
        // pressed 6 mm into the side, and the force vanished (42 ms of pop-through).
        if (!next.spanned && plane.spanned)
            break;
        if (!(distance(next) <= best)) {
            // Overshot (a surface curved tighter than the HIP is deep, e.g. a forearm's side):
            // half the step, so that the proxy does not hop between two sides of the optimum.
            next = fitFingerPlane(field_, plane.x + 0.5 * dx, plane.y + 0.5 * dy, p_.radius);
            if (!(distance(next) <= best))
                break;
        }
        plane = next;
        best = distance(plane);
        p = projectOnPlane(plane, hip, below);
    }
    return p;
}

void FingerRenderer::keepOnPatch(Candidate &c) const noexcept
{
    // The plane is the surface within the stencil's reach of its centre q only. Where the descent
    // stopped short (a step toward the HIP's projection was farther from the HIP), the projection
    // lies on the plane extrapolated beyond its taps. Where the sensor surface there stands over
    // it by more than the r/4 a plane fit may lie under its samples (and less than a cut: not an
    // object over the finger, whose surface is not this contact's), it is no surface point: the
    // extrapolation runs under a rise narrower than the stencil (an object's edge the finger is
    // pressed into), and the force there drops to nothing with the finger inside. The proxy is
    // the plane's point r from q toward it instead.
    const double ox = c.proxy.x - c.plane.x;
    const double oy = c.proxy.y - c.plane.y;
    const double out = std::sqrt(ox * ox + oy * oy);
    if (!(out > p_.radius) || !field_.contains(c.proxy.x, c.proxy.y))
        return;
    const double inside = pixelMedian(field_, c.proxy.x, c.proxy.y) - c.proxy.z;
    if (!(inside > 0.25 * p_.radius && inside <= field_.cutThreshold()))
        return;
    const double x = c.plane.x + ox * (p_.radius / out);
    const double y = c.plane.y + oy * (p_.radius / out);
    c.proxy = {x, y, c.plane.height + c.plane.gx * (x - c.plane.x) + c.plane.gy * (y - c.plane.y)};
}

glm::dvec3 FingerRenderer::glide(const glm::dvec3 &hip, const glm::dvec3 &proxy, FingerPlane &plane,
                                 double &moved, glm::dvec2 &dir) const noexcept
{
    moved = 0.0;
    dir = {};
    const double hx = hip.x - lastHip_.x;
    const double hy = hip.y - lastHip_.y;
    const double allowed = std::sqrt(hx * hx + hy * hy) + p_.glideReach;
    // From the last proxy on the surface: a pushed proxy is off it, along the push (a glide from
    // there took turns with the plane it started on, a buzz of the force's direction).
    const glm::dvec3 &from = surfaceProxy_;
    const double dx = proxy.x - from.x;
    const double dy = proxy.y - from.y;
    const double d = std::sqrt(dx * dx + dy * dy);
    if (!(d > allowed))
        return proxy;
    if (pushed_ && dx * lastGlide_.x + dy * lastGlide_.y < -0.5 * d) {
        // Back the way the last glide went: two far optima take turns (the search from either
        // side of a ridge ends on the other), and the proxy would glide to and fro at the servo
        // rate. It stays this update; the last glide's direction is kept, so it goes on, at half
        // the pace, toward the one it was heading for.
        plane = fitFingerPlane(field_, from.x, from.y, p_.radius);
        dir = lastGlide_;
        return {plane.x, plane.y, plane.height};
    }
    moved = allowed;
    dir = {dx / d, dy / d};
    // Toward the new optimum by what is allowed, on the surface there.
    plane =
        fitFingerPlane(field_, from.x + dx * (allowed / d), from.y + dy * (allowed / d), p_.radius);
    return {plane.x, plane.y, plane.height};
}

} // namespace depthtouch::haptics
