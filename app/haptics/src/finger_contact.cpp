/// \file
/// \brief FingerContact::Penalty: the fingertip renderer's contact from the finger-scale plane
/// under the HIP's own x–y (renderer.h, finger_renderer.h).
///
/// Per update: the plane of the 3×3 stencil at the HIP's x–y (fitFingerPlane(): half-width r, the
/// quadric's height where the nine fit one, taps far from the median and holes left out). The HIP
/// is free above it, or where most of the stencil is a hole (nothing was measured under the
/// finger). Under it, the proxy is the HIP's projection on the plane: the force k·(proxy − HIP)
/// is the penalty of the HIP's depth along the plane's normal, which for a plane is the
/// god-object's own force (Zilles & Salisbury 1995), and which, unlike a god-object's search,
/// depends on the HIP and the time alone. Beside an object's moving edge the proxy cannot take
/// turns between two solutions (a limit cycle): there is one.
///
/// State is kept only where a viewer's finger needs it, shared with the god-object contact:
/// - a finger that comes under the plane deeper than the capture depth came from the side under
///   an object, or the surface jumped onto it: it is behind the surface and free until it is out,
///   or until the surface it was held on is back within its held depth (enter());
/// - in contact, the depth may grow by the HIP's motion into the surface plus maxForceStep/(16k)
///   an update (limitPush()): a surface that sweeps under a resting finger pushes it out at a
///   bounded rate;
/// - cuts from the depth itself (paper IV.C, fix (c)): most of the stencil where the last update's
///   was, refitted now, moved by more than the cut threshold (stencilStep()); a smaller step of its
///   height is ramped in;
/// - the command held at the device maximum lets the finger go (watchSaturation()).
/// Cost: two plane fits an update (18 height lookups) in contact, one out of it.
/// Thread-safety: thread-bound (the haptic thread); no allocation.

#include "depthtouch/haptics/finger_renderer.h"

#include <cmath>

#include <glm/geometric.hpp>

namespace depthtouch::haptics {

void FingerRenderer::penalty(const glm::dvec3 &hip, double raw, Candidate &c) noexcept
{
    c.plane = fitFingerPlane(field_, hip.x, hip.y, p_.radius);
    double below = 0.0;
    glm::dvec3 goal = projectOnPlane(c.plane, hip, below);
    // The sensor surface at the HIP's own x–y counts only where it was measured: a triangle with a
    // hole vertex lies under the box (a finger resting at a hole's border rests on the patch).
    const bool measured = field_.measured(raw);
    if (field_.overHole(c.plane.height) && measured && raw > hip.z) {
        // Most of the patch is a hole but the HIP's own spot was measured: it pushes straight up.
        goal = {hip.x, hip.y, raw};
        below = raw - hip.z;
    } else if (field_.overHole(c.plane.height) || !(below > 0.0) || (measured && !(raw > hip.z))) {
        // Free: above the plane, over a hole, or above the sensor surface at the HIP's own x–y
        // (what the camera saw in front of the surface is free space).
        c.behind = false;
        return;
    }
    if (!touching()) {
        enter(below, c);
        if (c.contact) {
            c.proxy = goal;
            c.below = below;
            limitPush(hip, c); // caught deep (behind an object): the force grows at a bounded rate
        }
        return;
    }
    c.contact = true;
    c.below = below;
    c.proxy = goal;
    // Fix (c) from the depth: the stencil where the last update's was, refitted now.
    const FingerPlane then = fitFingerPlane(field_, lastPlane_.x, lastPlane_.y, p_.radius);
    const double moved =
        field_.overHole(then.height) ? 0.0 : std::fabs(then.height - lastPlane_.height);
    if (config_.safety && stencilStep(then) > field_.cutThreshold()) {
        // A cut: the proxy is re-seated on the new surface at once, as the god-object's is, and
        // the force stage ramps the change in (Reengage::Ramp) or the finger is let go (Release).
        c.trip = true;
        return;
    }
    if (moved > p_.stepDepth)
        c.stepped = true;
    // The proxy moves at most as far as the HIP did plus r/4 an update (as glide() does for the
    // god-object): a patch that tilts, steps or sweeps in under a resting finger turns and grows
    // the force over a few updates, never jumping the proxy onto it. Both ends lie on the outer
    // side of the HIP (the normal points up), so the proxy held short never pulls it down.
    const double allowed = glm::length(hip - lastHip_) + p_.glideReach;
    const glm::dvec3 step = goal - proxy_;
    const double d = glm::length(step);
    if (d > allowed)
        c.proxy = proxy_ + step * (allowed / d);
    limitPush(hip, c); // a surface rising under the finger pushes it out at a bounded rate
}

} // namespace depthtouch::haptics
