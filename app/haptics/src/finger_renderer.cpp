#include "depthtouch/haptics/finger_renderer.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/material_field.h"

namespace depthtouch::haptics {

namespace {

/// \return the median of nine values: the 19 compare-exchanges of Paeth's median-of-9 network
/// (Graphics Gems, "Median finding on a 3×3 grid"; as in N. Devillard's opt_med9), branch-free.
double median9(const double (&in)[9]) noexcept
{
    double p[9];
    std::copy(in, in + 9, p);
    auto sort2 = [&p](int a, int b) {
        const double lo = std::min(p[a], p[b]);
        p[b] = std::max(p[a], p[b]);
        p[a] = lo;
    };
    sort2(1, 2); sort2(4, 5); sort2(7, 8); sort2(0, 1); sort2(3, 4); sort2(6, 7);
    sort2(1, 2); sort2(4, 5); sort2(7, 8); sort2(0, 3); sort2(5, 8); sort2(4, 7);
    sort2(3, 6); sort2(1, 4); sort2(2, 5); sort2(4, 7); sort2(4, 2); sort2(6, 4);
    sort2(4, 2);
    return p[4];
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
    double taps[9];
    for (int k = 0; k < 9; ++k)
        taps[k] = field.heightAt(cx + (k % 3 - 1) * reachX, cy + (k / 3 - 1) * reachY);
    // The median of the nine: on the side of a silhouette where most of the stencil is, and
    // blind to a lone outlier (a flying pixel or speckle) that the centre sample may be.
    const double median = median9(taps);
    // Least squares z = a + bx·i + by·j over the taps within kFingerOutlier·r of the median: a
    // tap across a silhouette or on a flying pixel would tilt the plane of the side the finger
    // is on (the normal equations of the kept taps, solved by Cramer's rule).
    const double keep = kFingerOutlier * r;
    double n = 0, si = 0, sj = 0, sii = 0, sjj = 0, sij = 0, sh = 0, sih = 0, sjh = 0;
    for (int k = 0; k < 9; ++k) {
        if (!(std::fabs(taps[k] - median) <= keep))
            continue;
        const double i = k % 3 - 1;
        const double j = k / 3 - 1;
        n += 1;
        si += i;
        sj += j;
        sii += i * i;
        sjj += j * j;
        sij += i * j;
        sh += taps[k];
        sih += i * taps[k];
        sjh += j * taps[k];
    }
    const double det =
        n * (sii * sjj - sij * sij) - si * (si * sjj - sij * sj) + sj * (si * sij - sii * sj);
    double a = median;
    double bx = 0.0;
    double by = 0.0;
    if (det > 0.5) { // 1 for the fewest taps that span a plane; 324 for all nine
        a = (sh * (sii * sjj - sij * sij) - si * (sih * sjj - sij * sjh) +
             sj * (sih * sij - sii * sjh)) /
            det;
        bx = (n * (sih * sjj - sij * sjh) - sh * (si * sjj - sij * sj) +
              sj * (si * sjh - sih * sj)) /
             det;
        by = (n * (sii * sjh - sih * sij) - si * (si * sjh - sih * sj) +
              sh * (si * sij - sii * sj)) /
             det;
    }
    FingerPlane p;
    p.x = cx;
    p.y = cy;
    p.gx = reachX > 0.0 ? bx / reachX : 0.0; // tap (i, j) is at (x + i·reach, y + j·reach)
    p.gy = reachY > 0.0 ? by / reachY : 0.0;
    // The fitted height, but within r/4 of the median: across a silhouette the fit of a step
    // would be half-way, and a finger there would be inside the object with no force
    // (pop-through) on the near side, or pushed above the backdrop (phantom force) at its foot.
    const double margin = 0.25 * r;
    p.height = std::clamp(a, median - margin, median + margin);
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

FingerRenderer::FingerRenderer(const RendererConfig &config) noexcept
    : config_(config), field_(config.box), force_(config),
      friction_(config.staticFriction, config.dynamicFriction)
{
    field_.setCutThreshold(config.cutThreshold);
    radius_ = std::isnan(config.fingerRadius) ? 0.015 * config.box.width : config.fingerRadius;
    const double tripDepth = config.maxForceStep / config.stiffness; // the force step as a depth
    captureDepth_ = std::max(tripDepth, 0.1 * config.box.depth);
    stepDepth_ = 0.25 * tripDepth;
}

Result<void> FingerRenderer::setFrames(const DepthFrameView &current,
                                       const DepthFrameView *next) noexcept
{
    return field_.setFrames(current, next);
}

void FingerRenderer::reset(const glm::dvec3 &hip) noexcept
{
    proxy_ = hip;
    lastHip_ = hip;
    contact_ = false;
    behind_ = false;
    enterAnyDepth_ = true;
    force_.reset();
    friction_.release();
}

void FingerRenderer::restartClock() noexcept { force_.restartClock(); }

glm::dvec3 FingerRenderer::solve(const glm::dvec3 &hip, double startX, double startY,
                                 FingerPlane &plane, double &startHeight,
                                 double &below) const noexcept
{
    plane = fitFingerPlane(field_, startX, startY, radius_);
    startHeight = plane.height;
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
        if (d > radius_) {
            dx *= radius_ / d;
            dy *= radius_ / d;
        }
        FingerPlane next = fitFingerPlane(field_, plane.x + dx, plane.y + dy, radius_);
        if (!(distance(next) <= best)) {
            // Overshot (a surface curved tighter than the HIP is deep, e.g. a forearm's side):
            // half the step, so that the proxy does not hop between two sides of the optimum.
            next = fitFingerPlane(field_, plane.x + 0.5 * dx, plane.y + 0.5 * dy, radius_);
            if (!(distance(next) <= best))
                break;
        }
        plane = next;
        best = distance(plane);
        p = projectOnPlane(plane, hip, below);
    }
    return p;
}

glm::dvec3 FingerRenderer::glide(const glm::dvec3 &hip, const glm::dvec3 &proxy,
                                 FingerPlane &plane) const noexcept
{
    const double hx = hip.x - lastHip_.x;
    const double hy = hip.y - lastHip_.y;
    const double allowed = std::sqrt(hx * hx + hy * hy) + 0.25 * radius_;
    const double dx = proxy.x - proxy_.x;
    const double dy = proxy.y - proxy_.y;
    const double d = std::sqrt(dx * dx + dy * dy);
    if (!(d > allowed))
        return proxy;
    // Toward the new optimum by what is allowed, on the surface there.
    plane = fitFingerPlane(field_, proxy_.x + dx * (allowed / d), proxy_.y + dy * (allowed / d),
                           radius_);
    return {plane.x, plane.y, plane.height};
}

HapticOutput FingerRenderer::update(const glm::dvec3 &hip, double t) noexcept
{
    HapticOutput out;
    out.hip = hip;
    field_.setTime(t, config_.interpolation);
    const bool over = field_.contains(hip.x, hip.y); // false before the first frames
    // The sensor surface at the HIP's own x–y: above it is free space (what the camera saw).
    const double raw = over ? field_.heightAt(hip.x, hip.y) : std::nan("");
    const bool inside = raw > hip.z; // false for NaN
    glm::dvec3 proxy = hip;
    bool contact = false;
    bool trip = false;
    bool stepped = false; // the surface under the proxy stepped by less than a cut
    FingerPlane plane{};
    double below = 0.0;
    double startHeight = 0.0;
    if (!inside) {
        behind_ = false;
    } else if (contact_ && config_.correction) {
        // Slide on from the last proxy, on the current surface (fix (a): it lifts with it).
        // The first fit is where the last update's ended: fix (c) from the depth compares the
        // surface there with what it was then (a step since the last update is a cut).
        proxy = solve(hip, lastX_, lastY_, plane, startHeight, below);
        const double step = std::fabs(startHeight - lastHeight_);
        if (config_.safety && step > field_.cutThreshold())
            trip = true;
        else if (step > stepDepth_)
            stepped = true;
        contact = below > 0.0;
        // Two cases go to the surface at the HIP's own x–y. Held against a wall (the proxy more
        // than r to the side), the wall is an object's silhouette and behind it is what the
        // camera did not see: where that surface is nearer than the wall's proxy, the finger went
        // round or under the object and touches it instead of being pulled back through. And a
        // HIP that slipped off a steep side's plane while still inside the sensor surface (an
        // object's edge swept over the finger) is held by that surface.
        const double sideX = proxy.x - hip.x;
        const double sideY = proxy.y - hip.y;
        if (!contact || sideX * sideX + sideY * sideY > radius_ * radius_) {
            FingerPlane localPlane{};
            double localStart = 0.0;
            double localBelow = 0.0;
            const glm::dvec3 local = solve(hip, hip.x, hip.y, localPlane, localStart, localBelow);
            if (localBelow > 0.0 && (!contact || localBelow < glm::length(proxy - hip))) {
                proxy = local;
                plane = localPlane;
                below = localBelow;
                contact = true;
            }
        }
        if (contact)
            proxy = glide(hip, proxy, plane);
    } else if (contact_ || !behind_) {
        // From the HIP (a new contact, or the proxy-graph baseline without fix (a)).
        proxy = solve(hip, hip.x, hip.y, plane, startHeight, below);
        contact = below > 0.0 && (contact_ || enterAnyDepth_ || below <= captureDepth_ ||
                                  !config_.safety);
        if (below > 0.0 && !contact)
            behind_ = true; // came under the surface from the side, or the surface jumped onto it
    }
    if (trip && config_.reengage == Reengage::Release) {
        contact = false;
        behind_ = true;
    }
    if (!contact)
        proxy = hip;
    enterAnyDepth_ = false;
    out.released = trip;
    // The material under the goal (the track's per-pixel stiffness and friction), else the
    // renderer's own friction at stiffness scale 1.
    const bool material = field_.current().material.present();
    const double stiffnessScale = applyMaterial(field_, proxy, contact, friction_);
    // Friction acts on the force and the reported proxy; proxy_ keeps the frictionless goal (the
    // glide and the next update's search start from it).
    glm::dvec3 held = proxy;
    if (friction_.enabled() || material) {
        if (contact && !trip)
            held = friction_.apply(proxy, hip, t);
        else
            friction_.release();
    }
    const glm::dvec3 rawForce = force_.spring(hip, held, contact, t, stiffnessScale);
    out.force = force_.shape(rawForce, t, contact, trip || stepped);
    out.proxy = held;
    out.contact = contact;
    out.constraints = contact ? 1 : 0;
    contact_ = contact;
    proxy_ = proxy;
    lastHip_ = hip;
    lastX_ = plane.x;
    lastY_ = plane.y;
    lastHeight_ = plane.height;
    return out;
}

} // namespace depthtouch::haptics
