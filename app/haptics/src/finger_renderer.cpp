#include "depthtouch/haptics/finger_renderer.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/feel.h"
#include "finger_median.h"

namespace depthtouch::haptics {

FingerParameters fingerParameters(const RendererConfig &config) noexcept
{
    FingerParameters p;
    p.radius = config.fingerRadiusInBox();
    p.stiffness = config.stiffness;
    p.maxForceStep = config.maxForceStep;
    p.boxDepth = config.box.depth;
    const double stepForceDepth = p.maxForceStep / p.stiffness; // ΔF/k
    p.captureDepth = std::max(stepForceDepth, 0.1 * p.boxDepth);
    p.stepDepth = 0.25 * stepForceDepth;
    p.pushDepth = 0.0625 * stepForceDepth;
    p.filterStep = 3.0 * p.pushDepth;
    p.unloadDepth = 0.125 * stepForceDepth;
    p.unloadForce = p.maxForceStep / 8.0;
    p.glideReach = 0.25 * p.radius;
    p.holdReach = 0.5 * p.radius;
    p.rimReach = 0.75 * p.radius;
    p.restSpeed = p.radius / kFingerDepthMemory;
    p.slideSpeed = 2.0 * p.restSpeed;
    p.speedTime = p.glideReach / p.restSpeed;
    p.searchResolution = p.pushDepth / 64.0;
    return p;
}

FingerRenderer::FingerRenderer(const RendererConfig &config) noexcept
    : config_(config), field_(config.box), p_(fingerParameters(config)), output_(config, p_)
{
    field_.setCutThreshold(config.cutThreshold);
}

void FingerRenderer::setStiffness(double newtonsPerMetre) noexcept
{
    output_.setStiffness(newtonsPerMetre);
    config_.stiffness = output_.stiffness();
}

Result<void> FingerRenderer::setFrames(const DepthFrameView &current,
                                       const DepthFrameView *next) noexcept
{
    return field_.setFrames(current, next);
}

void FingerRenderer::reset(const glm::dvec3 &hip) noexcept
{
    proxy_ = hip;
    surfaceProxy_ = hip;
    lastGlide_ = {};
    lastHip_ = hip;
    state_ = FingerState::Free;
    pushed_ = false;
    enterAnyDepth_ = true;
    heldDepth_ = 0.0;
    lastDepth_ = 0.0;
    lastT_ = std::nan("");
    speed_ = 0.0;
    resting_ = false;
    output_.reset();
}

void FingerRenderer::restartClock() noexcept
{
    output_.restartClock();
}

void FingerRenderer::slide(const glm::dvec3 &hip, double raw, Candidate &c) const noexcept
{
    // Slide on from the last proxy, on the current surface (fix (a): it lifts with it). The first
    // fit is where the last update's ended: fix (c) from the depth compares the surface there with
    // what it was then (a step since the last update is a cut).
    FingerPlane start{};
    c.proxy = solve(hip, lastPlane_.x, lastPlane_.y, c.plane, start, c.below);
    keepOnPatch(c);
    const double startHeight = start.height;
    // A hole that opened under the proxy (the stencil's median turned to a hole) is no cut: the
    // surface is gone, not moved, and the finger is free there (no trip, no force).
    const double moved =
        field_.overHole(startHeight) ? 0.0 : std::fabs(startHeight - lastPlane_.height);
    // A cut moves most of the patch (stencilStep()); the plane's own step, an object's silhouette
    // passing over part of it too, is ramped.
    const double step = stencilStep(start);
    if (config_.safety && step > field_.cutThreshold())
        c.trip = true;
    else if (moved > p_.stepDepth)
        c.stepped = true;
    c.contact = c.below > 0.0;
    // Two cases go to the surface at the HIP's own x–y. Held against a wall (the proxy more than r
    // to the side), the wall is an object's silhouette and behind it is what the camera did not
    // see: where that surface is nearer than the wall's proxy, the finger went round or under the
    // object and touches it instead of being pulled back through. And a HIP that slipped off a
    // steep side's plane while still inside the sensor surface (an object's edge swept over the
    // finger) is held by that surface. So is a HIP above its wall's proxy while under the sensor
    // surface at its own x–y: the wall's object moved over it (a turning head over a finger on the
    // curtain), and the wall would pull the finger down into the backdrop.
    const double sideX = c.proxy.x - hip.x;
    const double sideY = c.proxy.y - hip.y;
    const bool overtaken = c.contact && c.proxy.z < hip.z;
    bool atHip = false;
    if (!c.contact || overtaken || sideX * sideX + sideY * sideY > p_.radius * p_.radius) {
        FingerPlane localPlane{};
        FingerPlane localStart{};
        double localBelow = 0.0;
        const glm::dvec3 local = solve(hip, hip.x, hip.y, localPlane, localStart, localBelow);
        // Nearer by a share (hysteresis): beside an edge the two solutions must not take turns.
        const double nearer = (1.0 - kFingerHysteresis) * glm::length(c.proxy - hip);
        if (localBelow > 0.0 && (!c.contact || overtaken || localBelow < nearer)) {
            c.switched = c.contact && !overtaken;
            c.proxy = local;
            c.plane = localPlane;
            c.below = localBelow;
            c.contact = true;
            atHip = true;
        }
    }
    if (!c.contact) {
        // Out from under the fingertip's plane where only its reach held it (withinReach()):
        // free.
        if (!(raw > hip.z))
            return;
        // Still under the sensor surface at its own x–y (the stencil's median is the backdrop
        // beside an object's silhouette): the contact goes on, pushing straight up from there.
        straightUp(hip, raw, c);
        c.contact = true;
        return;
    }
    double glided = 0.0;
    c.proxy = glide(hip, c.proxy, c.plane, glided, c.glide);
    // A descent never ends farther from the HIP than where it started (the surface point of the
    // last update's plane, refitted now), and a glide (a jump of the optimum, followed over a few
    // updates) only for a gain of kFingerHysteresis of its length: otherwise the proxy stays, so
    // that it cannot alternate between two points beside an object's edge update after update (the
    // surface there moves a little each update, and two far solutions take turns being nearer).
    auto distance = [&hip](const FingerPlane &f) {
        return glm::length(glm::dvec3(f.x - hip.x, f.y - hip.y, f.height - hip.z));
    };
    if (atHip || distance(c.plane) < distance(start) - kFingerHysteresis * glided)
        return;
    double below = 0.0;
    const glm::dvec3 stay = projectOnPlane(start, hip, below);
    if (below > 0.0) { // the HIP is still under the plane it stays on
        c.plane = start;
        c.proxy = stay;
        c.below = below;
    }
}

void FingerRenderer::capture(const glm::dvec3 &hip, Candidate &c) noexcept
{
    // From the HIP (a new contact, a finger behind an object, or the proxy-graph baseline without
    // fix (a)). A finger let go behind an occluder is caught again by the surface it was held on:
    // within its held depth (plus a ramped step) instead of the capture depth of a new contact.
    FingerPlane start{};
    c.proxy = solve(hip, hip.x, hip.y, c.plane, start, c.below);
    if (c.below > 0.0)
        enter(c.below, c);
    // Through an object's side: its wall, where that is nearer than a caught top (the god-object's
    // nearest point) or where the top was too deep to be caught (finger_wall.cpp).
    Candidate wall = c;
    if (config_.correction && enterWall(hip, wall)) {
        if (!c.contact || wall.below < c.below) {
            c = wall;
            c.behind = false;
        }
    } else if (wall.throughGap && c.below > 0.0) {
        // Through a gap narrower than the fingertip: it was on the surface either side of the
        // gap, not in front of a wall nor behind an object, whatever its depth (limitPush()
        // grows its force at the bounded push's rate).
        c.contact = true;
        c.behind = false;
    }
    if (c.contact && !touching())
        limitPush(hip, c); // caught deep (behind an object, under a returning surface): bounded
}

void FingerRenderer::enter(double below, Candidate &c) noexcept
{
    const double reach =
        c.behind ? std::max(p_.captureDepth, heldDepth_ + p_.stepDepth) : p_.captureDepth;
    c.contact = touching() || enterAnyDepth_ || below <= reach || !config_.safety;
    // Not caught: it came under the surface from the side, or the surface jumped onto it. Caught
    // again: the force steps at most maxForceStep an update.
    c.behind = !c.contact;
}

void FingerRenderer::pushUp(const glm::dvec3 &hip, double raw, Candidate &c) const noexcept
{
    // A glide ends on the surface part-way to the new optimum, which beyond an edge may lie under
    // the HIP: the spring would pull the finger down the side. A height field's surface pushes
    // up: the proxy is then the HIP's projection on the plane there or, with the HIP above that
    // plane (it is under the sensor surface at its own x–y: slide() runs inside), that surface
    // straight above it, as slide()'s own fallback.
    if (!(c.proxy.z < hip.z))
        return;
    double below = 0.0;
    const glm::dvec3 q = projectOnPlane(c.plane, hip, below);
    if (below > 0.0) {
        c.proxy = q;
        c.below = below;
        return;
    }
    if (!(raw > hip.z)) { // held by the fingertip's reach only (withinReach()), and out of it
        c.contact = false;
        return;
    }
    straightUp(hip, raw, c);
}

void FingerRenderer::straightUp(const glm::dvec3 &hip, double raw, Candidate &c) const noexcept
{
    c.plane = fitFingerPlane(field_, hip.x, hip.y, p_.radius);
    c.proxy = {hip.x, hip.y, raw};
    c.below = raw - hip.z;
}

double FingerRenderer::pushReach(const glm::dvec3 &hip) const noexcept
{
    return glm::length(hip - lastHip_) + p_.pushDepth;
}

double FingerRenderer::stencilStep(const FingerPlane &now) const noexcept
{
    double moved[9];
    for (int k = 0; k < 9; ++k)
        moved[k] = field_.besideHole(now.taps[k]) || field_.besideHole(lastPlane_.taps[k])
                       ? 0.0
                       : std::fabs(now.taps[k] - lastPlane_.taps[k]);
    return median9(moved);
}

void FingerRenderer::limitPush(const glm::dvec3 &hip, Candidate &c) noexcept
{
    // How deep the HIP is under the proxy may grow by the HIP's motion into the surface (along
    // the candidate's offset; once pushed, against the push) and p_.pushDepth an update: a surface
    // that sweeps under a resting finger (an object's side, a turning head) pushes it out at a
    // bounded rate, and a hand that yields rises onto it; one that does not is let go once the
    // force has reached the device maximum (watchSaturation()). The motion along the surface adds
    // nothing: a swipe at 50 cm/s onto each 3 mm tooth of the kitchen's ragged cabinet edge made
    // its contact 0.66 mm deep in one update (0.5 N, after the last tooth's force had unloaded:
    // a sign reversal each), where the depth it pressed the tooth's top by grew by none of it.
    const glm::dvec3 candidate = c.proxy - hip;
    const double depth = glm::length(candidate);
    const double reach = pushReach(hip);
    c.found = c.proxy;
    // Once pushed, the HIP's motion counts only against pushDir_: a hand that yields to the push
    // is followed at p_.pushDepth an update, not by its own motion as well (in the demo the force
    // grew the faster the hand gave way, to the device maximum).
    const glm::dvec3 into = pushed_ ? pushDir_ : (depth > 0.0 ? candidate / depth : pushDir_);
    const double deeper = std::max(0.0, glm::dot(lastHip_ - hip, into)) + p_.pushDepth;
    const double allowed = lastDepth_ + deeper;
    if (!pushed_ && c.switched && lastDepth_ > 0.0) {
        // A proxy held to the side, replaced by the surface at the HIP's own x–y (slide()): the
        // force turns from the side's direction over a few updates, as a bounded push does, for
        // beside flickering pixels the two solutions took turns.
        pushDir_ = glm::normalize(proxy_ - lastHip_);
    } else if (!pushed_) {
        if (!(depth > allowed))
            return;
        c.pushing = true;
        pushDir_ = candidate / depth;
        c.proxy = hip + pushDir_ * allowed;
        c.bounded = true;
        return;
    }
    // While pushed, the proxy's offset from the HIP turns toward the candidate's by at most reach
    // (m across) an update: under an occluder two far solutions (the top straight above the HIP,
    // a point on the object's flank) took turns being the candidate, and the proxy hopped between
    // them at the servo rate (a 500 Hz limit cycle of the force's direction); nor does the
    // force's direction step where the push ends. A surface that leaves the finger takes its
    // force at once (the depth is the candidate's, up to the bound).
    const glm::dvec3 dir = depth > 0.0 ? candidate / depth : pushDir_;
    const double angle = std::acos(std::clamp(glm::dot(dir, pushDir_), -1.0, 1.0));
    const double turn = reach / std::max(lastDepth_, p_.radius);
    if (angle > turn) {
        const glm::dvec3 across = dir - glm::dot(dir, pushDir_) * pushDir_;
        const double acrossLength = glm::length(across);
        if (acrossLength > 0.0)
            pushDir_ = std::cos(turn) * pushDir_ + std::sin(turn) * (across / acrossLength);
    } else {
        pushDir_ = dir;
    }
    c.proxy = hip + pushDir_ * std::min(depth, allowed);
    c.bounded = true;
    c.pushing = !(angle <= turn && depth <= allowed);
}

HapticOutput FingerRenderer::update(const glm::dvec3 &hip, double t) noexcept
{
    HapticOutput out;
    out.hip = hip;
    field_.setTime(t, config_.interpolation);
    const bool over = field_.contains(hip.x, hip.y); // false before the first frames
    // The sensor surface at the HIP's own x–y: above it is free space (what the camera saw).
    const double raw = over ? sensorHeight(hip) : std::nan("");
    Candidate c;
    c.proxy = hip;
    c.behind = state_ == FingerState::Behind;
    c.wall = state_ == FingerState::OnWall;
    const bool wasInContact = touching(); // holdOverHole() may end it before the search
    search(hip, raw, over, t, c);
    // The material under the goal (the track's per-pixel stiffness and friction), else the
    // renderer's own friction at stiffness scale 1.
    const double stiffnessScale = output_.material(field_, c);
    letGo(hip, c);
    out.released = c.trip;
    // The offset from the HIP is filtered, and friction acts, on the force and the reported proxy;
    // proxy_ keeps the unfiltered, frictionless goal (the glide and the next update's search start
    // from it). Friction acts on the filtered goal.
    c.touching = touching();
    c.smooth = c.plane.smooth;
    c.hipMove = hip - lastHip_;
    const glm::dvec3 held = output_.filter(hip, c, t);
    out.force = output_.force(hip, held, c, t, stiffnessScale, raw, field_, wasInContact);
    out.proxy = held;
    out.contact = c.contact;
    out.constraints = c.contact ? 1 : 0;
    remember(hip, c);
    return out;
}

void FingerRenderer::search(const glm::dvec3 &hip, double raw, bool over, double t,
                            Candidate &c) noexcept
{
    const bool inside = raw > hip.z; // false for NaN
    const bool wasResting = resting_;
    const bool resting = restingContact(hip, t);
    if (holdOverHole(hip, raw, t, c)) {
        // Held on the surface it pressed: a hole opened under the finger (finger_hole.cpp).
        c.unseen = true;
    } else if (resting) {
        c.wall = false;
        if (over)
            penalty(hip, raw, c);
        else
            c.behind = false;
        if (!c.behind && !c.contact)
            heldDepth_ = 0.0;
        if (c.contact && !wasResting && touching() && switchSteps(c))
            c.stepped = true; // from the god-object's proxy to the penalty's: ramped in
    } else if (!inside && !withinReach(hip, raw)) {
        c.behind = false;
        heldDepth_ = 0.0;
    } else if (state_ == FingerState::OnWall) {
        wallContact(hip, raw, c);
    } else if (touching() && config_.correction) {
        slide(hip, raw, c);
        if (c.contact && !c.trip)
            pushUp(hip, raw, c);
        if (c.contact && !c.trip)
            limitPush(hip, c);
        // Held by its reach alone (withinReach()), only while the HIP does not press on: a HIP
        // moving deeper there is beside an object's rim, not on it.
        if (!inside && c.contact && !c.trip && pressesOn(hip, c.proxy))
            c.contact = false;
    } else {
        capture(hip, c);
    }
    if (wasResting && !resting_ && c.contact && touching() && !c.trip && switchSteps(c))
        c.stepped = true; // from the penalty's proxy to the god-object's: ramped in
    // A step is ramped from the force before it over the ramp time (0.25 s), which is right for a
    // step up under a pressed finger only: from a force under the step's own size the ramp held
    // the force near zero for tens of updates with the HIP inside (15 ms of pop-through on the
    // feel bench's forearm); the bounded push (limitPush()) grows it instead. A step down (the
    // surface fell away: the proxy is nearer the HIP than last update) ramped down held a force
    // the surface no longer gives for as long (3.0 N for 0.85 N, 20 updates after a 3 mm fall); the
    // offset filter unloads it at its bounded rate instead (smoothOffset()).
    if (c.stepped && !c.trip &&
        (lastDepth_ < p_.stepDepth || glm::length(c.proxy - hip) < lastDepth_))
        c.stepped = false;
}

void FingerRenderer::letGo(const glm::dvec3 &hip, Candidate &c) noexcept
{
    if (output_.takeLetGo() && c.contact) {
        c.trip = true;
        c.letGo = true;
        c.saturated = true;
    }
    if (c.trip && (c.letGo || config_.reengage == Reengage::Release)) {
        // Behind the surface: free until out, or caught again by the surface it was held on.
        heldDepth_ = c.saturated ? 0.0 : lastDepth_;
        c.contact = false;
        c.behind = true;
    }
    if (!c.contact) {
        c.proxy = hip;
        c.wall = false;
    }
    enterAnyDepth_ = false;
}

void FingerRenderer::remember(const glm::dvec3 &hip, const Candidate &c) noexcept
{
    state_ = nextState(c);
    pushed_ = c.pushing && touching();
    proxy_ = c.proxy;
    surfaceProxy_ = c.bounded && c.contact ? c.found : c.proxy;
    lastGlide_ = c.contact ? c.glide : glm::dvec2{};
    lastHip_ = hip;
    lastDepth_ = c.contact ? glm::length(c.proxy - hip) : 0.0;
    lastPlane_ = c.plane;
}

bool FingerRenderer::pressesOn(const glm::dvec3 &hip, const glm::dvec3 &proxy) const noexcept
{
    // The depth's growth since last update is the HIP's own motion along the contact's normal plus
    // the surface's (the stencil plane's noise: 40 µm in a frame of time-of-flight multipath under
    // a resting finger). The HIP presses on where its own part is the larger one; growth by the
    // surface alone is the surface's to give, as the bounded push takes it (limitPush()).
    const glm::dvec3 d = proxy - hip;
    const double depth = glm::length(d);
    if (!(depth > lastDepth_))
        return false;
    const double hipInto = glm::dot(lastHip_ - hip, d / depth);
    return hipInto > (depth - lastDepth_) - hipInto;
}

bool FingerRenderer::withinReach(const glm::dvec3 &hip, double raw) const noexcept
{
    // A fingertip is not a point: pressed on a surface, it is not let go because a few pixels
    // under its centre read farther back (time-of-flight flying pixels, an active-stereo mismatch,
    // the teeth of a Kinect silhouette under a swipe) while the surface around them, within half
    // its radius, is still above the HIP. The contact goes on where the stencil's plane still has
    // the HIP under it (slide(), pushUp()) and only while the HIP leaves it (update()): a contact
    // that grew deeper there was a finger beside an object's rim, held up by the top's plane (a
    // press down the kitchen cabinet's side: 6 N with the HIP 7 mm under the top). Half the radius,
    // not all of it: at the full radius the finger was held 2 mm beside the synthetic forearm's
    // 8-bit edge, where bench feel, judging phantom force by the true surface within the radius,
    // found 4 ms of it. Over a hole (nothing measured at the HIP: off the grid too) the hole's own
    // rules hold (finger_hole.cpp).
    if (!std::isfinite(raw) || field_.overHole(raw) || !touching() ||
        state_ == FingerState::OnWall || !config_.correction)
        return false;
    return reachAbove(hip, p_.holdReach) > hip.z; // false for NaN
}

double FingerRenderer::reachAbove(const glm::dvec3 &hip, double radius) const noexcept
{
    return reachHeight(
        [this](double x, double y) {
            return field_.contains(x, y) ? field_.heightAt(x, y) : std::nan("");
        },
        hip.x, hip.y, radius);
}

double FingerRenderer::sensorHeight(const glm::dvec3 &hip) const noexcept
{
    const double raw = field_.heightAt(hip.x, hip.y);
    if (!touching() || raw > hip.z)
        return raw;
    // In contact, and free by the surface at the HIP's own x–y: one pixel read far back (an active
    // stereo mismatch, a time-of-flight dropout, a single hole) is not free space under a pressed
    // finger. The median of the surface at the HIP and one pixel around it (a pixel's vertex
    // reaches four of the nine) is; past a silhouette's edge by more than a pixel, most of them
    // lie on the far side and the finger is free as before.
    return pixelMedian(field_, hip.x, hip.y);
}

FingerState FingerRenderer::nextState(const Candidate &c) noexcept
{
    if (c.contact)
        return c.unseen ? FingerState::OverHole
               : c.wall ? FingerState::OnWall
                        : FingerState::Touching;
    return c.behind ? FingerState::Behind : FingerState::Free;
}

bool FingerRenderer::switchSteps(const Candidate &c) const noexcept
{
    // On a smooth surface the two contacts' proxies lie within a small step of each other: the
    // force changes by less than the ramp's own threshold (a surface step of p_.stepDepth), and a
    // ramp would only hold the old force while the new one moves on (a finger lifted off just
    // after it came to rest would be let go from the ramp's stale force: a spike).
    return glm::length(c.proxy - proxy_) > p_.stepDepth;
}

bool FingerRenderer::restingContact(const glm::dvec3 &hip, double t) noexcept
{
    if (config_.fingerContact != FingerContact::Adaptive) {
        resting_ = config_.fingerContact == FingerContact::Penalty;
        return resting_;
    }
    const double dt = t - lastT_;
    if (dt > 0.0) { // not on the first update, nor after a restarted clock
        const double moved = std::hypot(hip.x - lastHip_.x, hip.y - lastHip_.y);
        speed_ += (moved / dt - speed_) * std::min(1.0, dt / p_.speedTime);
    }
    lastT_ = t;
    resting_ = resting_ ? speed_ < p_.slideSpeed : speed_ < p_.restSpeed;
    return resting_;
}

} // namespace depthtouch::haptics
