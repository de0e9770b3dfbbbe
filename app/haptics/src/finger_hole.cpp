/// \file
/// \brief The fingertip renderer's hold over a hole that opens under a pressed finger
/// (finger_renderer.h, step 5 "Holes").
///
/// A hole is where the sensor measured nothing (DepthFrameView::holeBelow): free space to a finger
/// that meets it. Under a finger already pressing the surface it is the surface unseen, as under
/// an occluder: a structured-light sensor casts a shadow band beside an object's edge that sweeps
/// over the surface with the object, and a time-of-flight or stereo sensor drops pixels for a frame
/// or two. Before, the force went to zero the update the spot turned to a hole and came back when
/// it was measured again: a press beside a passing occluder gave a 1.1 N step off and a 2 N step
/// on one frame later, and one 6 mm deep unloaded 4.5 N in three updates (`bench feel`, the
/// synthetic occluder's press at its edge).
///
/// Now the proxy keeps its height and its x–y offset from the HIP (the force stays as it was: it
/// shrinks as the finger lifts, and neither grows nor turns as it presses deeper, for there is
/// nothing measured to press into) for kFingerDepthMemory while the HIP stays within r of where the
/// hole opened (a finger that slides on past the rim finds the hole free, as a fingertip of radius
/// r rolls off an edge) and under the held proxy's height. When the hold ends, the force unloads by
/// maxForceStep/8 an update (0.25 N) along its last direction instead of at once: a finger lifting
/// off a rim beside the hole, its force mostly sideways, stepped 0.7-0.8 N off when it passed the
/// proxy's height. A measured spot again ends the hold: the finger slides on from the held proxy,
/// or, where what is measured now is a cut from what it was held on (an occluder came over the
/// unseen spot), it is free and caught by what is there, as it was without the hold; a force it
/// had unloads at the bounded rate while what came over it covers the HIP
/// (FingerOutput::releaseCovered()), not in the step limit's 2 N steps.
/// Cost: no height lookup while held (the plane is the last update's); one plane fit (9 lookups) on
/// the update the spot is measured again. Thread-safety: thread-bound.

#include "depthtouch/haptics/finger_renderer.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace depthtouch::haptics {

bool FingerRenderer::holdOverHole(const glm::dvec3 &hip, double raw, double t,
                                  Candidate &c) noexcept
{
    // NaN (off the grid) is not measured, but neither is it a hole: the finger left the grid.
    const bool hole = !field_.measured(raw) && !std::isnan(raw);
    if (!hole || !touching() || state_ == FingerState::OnWall) {
        const double cut = field_.cutThreshold();
        if (state_ == FingerState::OverHole && config_.safety &&
            (std::fabs(raw - proxy_.z) > cut ||
             stencilStep(fitFingerPlane(field_, lastPlane_.x, lastPlane_.y, p_.radius)) > cut)) {
            // Measured again, but not the surface the finger was held on (an occluder came over
            // it while it was unseen): free, as the hole left it before the hold, to be caught
            // by what is there now (capture()) instead of tripping on the step.
            state_ = FingerState::Free;
            c.behind = false;
            heldDepth_ = 0.0;
        }
        return false;
    }
    const glm::dvec3 goal(hip.x + proxy_.x - lastHip_.x, hip.y + proxy_.y - lastHip_.y, proxy_.z);
    const glm::dvec3 offset = goal - hip;
    const double reach = glm::length(offset);
    if (state_ != FingerState::OverHole) {
        hole_.since = t;
        hole_.at = {hip.x, hip.y};
        hole_.depth = lastDepth_;
        const glm::dvec3 last = proxy_ - lastHip_;
        hole_.dir = glm::length(last) > 0.0 ? last / glm::length(last) : glm::dvec3(0.0, 0.0, 1.0);
    }
    // Held, the force does not grow past the one the finger had when the hole opened (nothing is
    // measured to press into). Past the hold, or with the HIP risen to the held proxy's height
    // (lifting off a rim beside the hole, the force mostly sideways), the depth shrinks by half a
    // ramped step an update along the last direction: the force unloads, never steps off.
    const bool held = t - hole_.since <= kFingerDepthMemory &&
                      glm::length(glm::dvec2(hip.x, hip.y) - hole_.at) <= p_.radius &&
                      goal.z > hip.z;
    // Pressed deeper than the hold's depth, the force keeps its direction as well as its size:
    // turned toward the deeper HIP, it swung by 0.06 N an update before the hold ended (a swipe
    // down into the stereo occluder's shadow band, then let go over the backdrop beyond it: a
    // force that turns and then drops is a sign reversal).
    if (held && reach <= hole_.depth)
        hole_.dir = offset / reach;
    const double depth =
        held ? std::min(reach, hole_.depth) : std::min(hole_.depth, lastDepth_ - p_.unloadDepth);
    if (!(depth > 0.0))
        return false;
    c.contact = true;
    c.proxy = hip + hole_.dir * depth;
    c.below = c.proxy.z - hip.z;
    c.plane.x = lastPlane_.x + c.proxy.x - proxy_.x; // the last plane, carried with the proxy
    c.plane.y = lastPlane_.y + c.proxy.y - proxy_.y;
    c.plane.height = lastPlane_.height;
    std::copy(std::begin(lastPlane_.taps), std::end(lastPlane_.taps), std::begin(c.plane.taps));
    return true;
}

} // namespace depthtouch::haptics
