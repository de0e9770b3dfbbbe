/// \file
/// \brief The fingertip renderer's force output stage (finger_output.h): the filter on the
/// force's offset from the HIP (finger_renderer.h, step 5 "Depth noise" and "Steps"), the unload of
/// a contact that ended, the spring, ForceStage's shaping and the watch of the device maximum.

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/finger_output.h"

#include "depthtouch/haptics/feel.h"
#include "depthtouch/haptics/material_field.h"

namespace depthtouch::haptics {

void FingerOutput::smoothOffset(const glm::dvec3 &hip, const FingerGoal &c, double t,
                                glm::dvec3 &held) noexcept
{
    // The proxy's offset from the HIP through an alpha-beta filter (the steady-state Kalman filter
    // of a constant-velocity track; Brookner, "Tracking and Kalman Filtering Made Easy", ch. 1): on
    // noisy depth each update's plane tilts and shifts anew as the taps cross pixels, and at 50
    // cm/s the force turned back and forth by 0.05-0.2 N every update (alternating runs of 11 on
    // the synthetic head's cheek and the time-of-flight occluder's flying pixels). The trend term
    // follows an offset that changes steadily (a slope under a moving finger, a press) without
    // lag. The filtered offset moves no farther in an update than the unfiltered one did (or than
    // the catch-up below), and never more than p_.filterStep: the proxy's bounds (r/4 an update,
    // the bounded push) hold for the force's proxy too, the trend's overshoot where a glide stops
    // is cut short, and a switch of the solution turns the force over a few updates. Where it lags
    // (the unfiltered offset jumped once, then held still), it catches up by a share alpha of the
    // gap an update: with p_.pushDepth/4 alone it crawled, and a tap lifting off the living room's
    // table edge kept 3.4 N for a contact 0.1 mm deep until the contact ended, then dropped it
    // in two 2 N steps. It unloads by at most 2·p_.pushDepth an update. A new contact, a trip or a
    // ramped step starts it afresh at the offset, whether or not the offset moved; a hold over a
    // hole (nothing measured: its own unload rate is the force's) takes the hold's offset, but
    // from where the filter is, no faster than that bound. It never puts the proxy under the HIP
    // where the unfiltered proxy is not (pushUp()).
    //
    // What it filters is noise, and a clean surface has none to filter: where the nine taps under
    // the goal have fitted a quadric (FingerPlane::smooth) for kFingerDepthMemory, alpha rises
    // to 1 and the offset passes through. The filter's lag was the force's error on clean
    // geometry (the moving wave at 1 m/s: 0.092 N RMS against the paper's method's 0.024 N, the
    // force turning at 25 Hz as the finger crossed the wave's crests). The trust falls at once
    // with the fit, so a surface whose taps are noisy now and then (8-bit plateaus between
    // steps, a sensor's speckle in some frames) stays filtered: trusting each fit on its own
    // left alternating runs of 5-7 updates on the synthetic head and forearm.
    //
    // What it filters is the surface's part of the offset, not the hand's: the HIP's own move along
    // the offset compresses or relaxes the spring, and that passes at once, as a spring answers
    // (the mean of the last two such moves: a hand climbing over noisy depth moves in a 500 Hz
    // staircase, which would alternate the force). Filtered with the rest, a hand lifting off or
    // climbing 2 mm an update had its force follow at most 0.375 N an update behind it, and the
    // zero-order hold charged the hand with the force from before: most of the energy `bench feel`
    // measured over the ideal penalty's (docs/benchmarks.md, "The offset filter lags the hand's
    // own motion"). An offset that turns back against its last change turns by at most the step
    // bound in that update: a hand reversing against a side at 50 cm/s turned the force 0.62 N.
    const glm::dvec3 offset = c.proxy - hip;
    if (!config_.smoothOffset) {
        held = c.proxy;
        return;
    }
    const double dt = t - lastT_; // NaN before the first update: no growth
    lastT_ = t;
    // The catch-up toward the unfiltered offset where the filter lags it: a share
    // kFingerOffsetAlpha of the gap (not the trusted alpha: a lag is taken over a few updates, not
    // at once past the bounded push's rate), at least p_.pushDepth/4 and at most 2·p_.pushDepth an
    // update (0.25 N at the default stiffness, the rate a hold over a hole unloads at).
    const double gap = glm::length(offset - offset_);
    const double catchUp =
        std::max(0.25 * p_.pushDepth, std::min(kFingerOffsetAlpha * gap, p_.unloadDepth));
    // Unloading at most 2·p_.pushDepth an update (from an offset \a from long): a surface that
    // falls away under the finger (not a cut) takes its force over a few updates, not in one step
    // of up to 2 N. The bound is the surface's: a HIP lifting off unloads by its own move out too
    // (\a out over a hole; elsewhere the hand's part has passed before the bound), as a spring
    // does.
    const double was = glm::length(offset_);
    const glm::dvec3 u = was > 0.0 ? offset_ / was : glm::dvec3{0.0};
    const double moved = glm::dot(c.hipMove, u); // the HIP's move along the offset, m
    const auto unloadBounded = [this](const glm::dvec3 &next, double from, double out) {
        const double now = glm::length(next);
        const double least = from - p_.unloadDepth - out;
        return now > 0.0 && now < least ? next * (least / now) : next;
    };
    const glm::dvec3 before = offset_;
    const bool restart = !c.contact || !c.touching || c.trip || c.stepped;
    if (restart) {
        offset_ = offset;
        offsetTrend_ = {};
        // A contact that begins while an ended one's force is still unloading (releaseCovered():
        // a let-go at the device maximum, caught again a moment later) starts from that force, so
        // the filter unloads it at its bounded rate instead of the force stage's 2 N steps.
        const double k = config_.stiffness * scale_;
        if (c.contact && !c.trip && k > 0.0 && glm::length(release_) > k * glm::length(offset))
            offset_ = release_ / k;
    } else if (c.unseen) {
        // Held over a hole: the hold's own offset, whose unload is the force's (finger_hole.cpp),
        // but from a filter still unloading, no faster than its bound: on the synthetic occluder a
        // hole opened while the filter took 6.9 N off a push the surface had ended, and the
        // hold's 1.1 mm came through at once (three 2 N steps, the force's own step limit).
        offset_ = unloadBounded(offset, was, std::max(0.0, moved));
        offsetTrend_ = {};
    } else if (lastOffset_ == offset) {
        // Nothing moved (a paused picture under a still finger): straight to the offset, at most
        // the catch-up, so that the force stands still once it is there.
        offset_ += gap > catchUp ? (offset - offset_) * (catchUp / gap) : offset - offset_;
        offsetTrend_ = {};
    } else {
        // The trust is the surface's, read in contact only: a finger that bounces off a clean
        // surface and back (a stiff spring in the loop with a light hand) meets the same surface.
        trust_ =
            std::min(c.smooth, trust_ + (dt > 0.0 ? std::min(dt / kFingerDepthMemory, 1.0) : 0.0));
        const double alpha = kFingerOffsetAlpha + trust_ * (1.0 - kFingerOffsetAlpha);
        const double beta = alpha * alpha / (2.0 - alpha);
        // The hand's part passes (the mean of its last two moves along the offset, at most the
        // offset's length); the filter and its bounds take the surface's part. A move out along
        // the offset relaxes the spring only as far as the offset did shrink: where the goal
        // moved with the hand (a bounded push's depth grows whichever way the hand goes; a new
        // contact's first offset leans as far as the plane it was found on, and the hand's slide
        // along that plane is no move out of it), there is nothing to pass, and a force that
        // began at the bounded push's first step fell back to nearly nothing with each such move
        // (the keys' and the crowd's swipes in `bench feel`: alternating runs of 4-6 updates).
        const double hand = std::min(0.5 * (moved + lastAlong_), was);
        const double along =
            hand > 0.0 ? std::min(hand, std::max(0.0, was - glm::length(offset))) : hand;
        const glm::dvec3 prior = offset_ - along * u;
        const glm::dvec3 predicted = prior + offsetTrend_;
        // The measurement is the mean of this offset and the last (less the hand's part, as the
        // prior is) where the surface has not fitted clean: an offset that alternates at the servo
        // rate (the stencil's taps on a keyboard's keys and in the gaps between them in turn) is
        // not passed at all, where the filter alone passes 0.23 of it (its gain at the Nyquist
        // frequency), alternating runs of 4-7 updates in `bench feel`. The cost is half an update
        // of lag on noisy depth; a clean surface's offset passes as it is (trust_ 1).
        const glm::dvec3 measured =
            offset + (1.0 - trust_) * 0.5 * (lastOffset_ - along * u - offset);
        const glm::dvec3 residual = measured - predicted;
        const glm::dvec3 step = predicted + alpha * residual - prior;
        offsetTrend_ += beta * residual;
        // At most p_.filterStep (0.375 N) however far the unfiltered offset jumped: a switch of
        // the solution (a press at rest by the kitchen's cabinet edge: the top 5.5 mm above, then
        // a point 2.2 mm to the side) turned the force by 1 N in an update.
        const double limit = std::min(
            std::max(glm::length(offset - lastOffset_ + along * u), catchUp), p_.filterStep);
        const double length = glm::length(step);
        const double scale = length > limit ? limit / length : 1.0;
        glm::dvec3 next = unloadBounded(prior + step * scale, glm::length(prior), 0.0);
        // Turning back against its last change: at most the step bound in that update.
        const glm::dvec3 change = next - offset_;
        if (glm::dot(change, lastChange_) < 0.0 && glm::length(change) > p_.filterStep)
            next = offset_ + change * (p_.filterStep / glm::length(change));
        offset_ = next;
        offsetTrend_ *= scale;
    }
    lastChange_ = restart ? glm::dvec3{0.0} : offset_ - before;
    lastAlong_ = restart ? 0.0 : moved;
    lastOffset_ = offset;
    held = hip + glm::dvec3{offset_.x, offset_.y, std::max(offset_.z, std::min(offset.z, 0.0))};
}

bool FingerOutput::handOverRamp(const glm::dvec3 &hip, const glm::dvec3 &hipMove,
                                glm::dvec3 &held) noexcept
{
    // A ramp blends from the force before a trip or a step to the new contact's over the ramp
    // time (0.25 s). Where the surface falls away under the finger during it (a tap's pushed
    // proxy snapping back to the table beside an object, a finger lifting), the ramp held the
    // force it started from with the proxy 0.1 mm from the HIP (2.7 N for 0.1 N on the living
    // room's table edge), and dropped it in 2 N steps (the step limit) when the contact ended.
    // Where the finger is left less than a ramped step's depth deep, the filter takes that force as
    // its offset and unloads it at 2·p_.pushDepth an update. So does a finger lifting off (the
    // HIP's own move out along the offset): a ramp from 4 N held that force while the finger rose
    // out at 40 cm/s and dropped it in 2 N steps when the contact ended (the demo's head). Deeper
    // and not lifting, the ramp goes on: a pressed finger's force turning under it (a hold at the
    // kitchen's cabinet edge) is the ramp's to blend.
    //
    // The hand-over is continuous: \a held is the proxy the spring would use (after friction),
    // and the stiffness is the spring's last (scale_, which boundScale() then moves within
    // unloadForce of force). Handed over before friction, the friction cone's anchor took the
    // proxy back to its own direction (1.0-1.5 N in an update: the demo's head as the finger
    // lifted off a ramp, the typing hand's desk edge under friction); at the material's target
    // scale, a boundary under the finger stepped it by Δscale/scale of the command.
    if (!config_.smoothOffset || !force_.ramping())
        return false;
    const double k = config_.stiffness * scale_;
    const glm::dvec3 command = force_.lastCommand();
    const glm::dvec3 offset = held - hip;
    const double depth = glm::length(offset);
    const bool lifting = glm::dot(hipMove, offset) > 0.0;
    if (!(k > 0.0) || !((depth < p_.stepDepth || lifting) && k * depth < glm::length(command)))
        return false;
    force_.endRamp();
    offset_ = command / k;
    offsetTrend_ = {};
    held = hip + offset_;
    return true;
}

void FingerOutput::releaseCovered(const glm::dvec3 &hip, double raw, const HeightField &field,
                                  const FingerGoal &c, bool wasInContact,
                                  glm::dvec3 &force) noexcept
{
    // A cut that covers a pressed finger (a hand over a held press, an occluder's edge over the
    // whole fingertip patch) trips and lets it go behind the new surface. Its force went in the
    // force's step limit, 2 N an update: a press 6 mm into the active-stereo lab's floor, a
    // person's edge over it, gave 4.9 -> 2.9 -> 0.9 -> 0 N, three knocks. With the HIP under the
    // new surface there is no free space for that force to push the finger into: it unloads at
    // maxForceStep/8 an update, as a surface that falls away does, while the HIP stays covered.
    // A contact that ends (\a wasInContact: also where a hold over a hole ended it, measured
    // again lower) with a surface above the HIP within 3r/4 (a finger sliding off a rim: free at
    // r/2, withinReach()) unloads from maxForceStep/8, the step doubling to maxForceStep/4 (0.25,
    // 0.5, 0.5 N ...; at most kFingerOffsetAlpha of the force left), while the rim stays within
    // 3r/4: a ball rolling off an edge is pushed less and less, slowly at first (its depth falls
    // as r − √(x² + h²) with its distance x past the edge). It went to 0 in one update: a swipe at
    // 50 cm/s 2 mm into the kitchen's ragged cabinet edge (3 mm teeth, 3 mm gaps) rose to 0.8 N on
    // each tooth and dropped it at each gap, 33 sign reversals a second. At a constant
    // maxForceStep/8, or out to the whole radius, it outlasted the rim by an update at 50 cm/s
    // where the measured edge lies a pixel beyond the true one (1-12 ms of phantom force over the
    // clips); doubling up to maxForceStep, its last step was a spike (0.7 N beside the living
    // room's moving object). Out of 3r/4 the force is 0, as the release of a contact was. A contact
    // that ended with the HIP covered (below) unloads as a covering trip does.
    if (c.contact || !config_.smoothOffset) {
        release_ = {};
        return;
    }
    const bool covered = raw > hip.z; // false for NaN
    // Any contact that ended under the surface now measured, however it ended, unloads as a
    // covering cut's trip does: a hold over a hole that ended under what came over it (a person
    // walking over a finger held 3 mm into bonn-crowd's floor) was left free with no force, and its
    // 6 N fell in the step limit's 2 N steps (0.8-0.9 N at once from a 1 mm hold); now 0.25 N an
    // update, with the same pop-through, phantom force, regain and energy on every stroke of `bench
    // feel`.
    const bool started = c.trip ? covered : wasInContact;
    if (!started && release_ == glm::dvec3{})
        return; // nothing to unload (a free finger: no lookups)
    const auto reachAbove = [&field](const glm::dvec3 &at, double radius) {
        return reachHeight(
            [&field](double x, double y) {
                return field.contains(x, y) ? field.heightAt(x, y) : std::nan("");
            },
            at.x, at.y, radius);
    };
    if (!covered && !(reachAbove(hip, p_.rimReach) > hip.z)) {
        release_ = {};
        return;
    }
    if (started) {
        release_ = force_.lastCommand();
        releaseStep_ = 0.0;
    }
    const double least = p_.unloadForce;
    releaseStep_ = covered ? least : std::clamp(2.0 * releaseStep_, least, 2.0 * least);
    // The hand's own lift out along the force unloads it as the spring it came from would (k·s
    // per metre of the rise's part along the force), within the same maxForceStep/4 an update, as
    // the offset filter passes a lifting finger's unload (smoothOffset()): the schedule above is
    // for a ball rolling off a rim sideways, and a hand that lifts off at the bench's climb rate
    // (2 mm an update) was pushed 2 mm at 1.33 N after it was out (synthetic-head/8's 50 cm/s
    // swipe, +E 17.65 -> 13.63 mJ). Only the rise: a slide along a tilted force is the roll-off
    // itself (counted too, the forearm's swipes reversed the force 1.9 times a second).
    const double length = glm::length(release_);
    const double out =
        length > 0.0 ? std::max(0.0, c.hipMove.z) * std::max(0.0, release_.z) / length : 0.0;
    const double lift = force_.stiffness() * scale_ * out;
    // Off a rim, never more than the offset filter's share of what is left, as the filter takes a
    // surface that falls away: a contact of 0.1 N (a fingertip on a keyboard's keys, the sensor
    // seeing the gaps between them) went in one step at each gap and began again at the next key.
    const double roll =
        covered ? releaseStep_ : std::min(releaseStep_, kFingerOffsetAlpha * length);
    const double step = roll + std::min(lift, std::max(0.0, 2.0 * least - releaseStep_));
    release_ = length > step ? release_ * ((length - step) / length) : glm::dvec3{};
    force = release_;
}

glm::dvec3 FingerOutput::filter(const glm::dvec3 &hip, const FingerGoal &c, double t) noexcept
{
    glm::dvec3 held = c.proxy;
    smoothOffset(hip, c, t, held);
    if (friction_.enabled() || material_) {
        if (c.contact && !c.trip)
            held = friction_.apply(held, hip, t);
        else
            friction_.release();
    }
    if (c.contact && !c.trip && !c.stepped && handOverRamp(hip, c.hipMove, held))
        friction_.moveTo(held);
    return held;
}

double FingerOutput::material(const HeightField &field, const FingerGoal &c) noexcept
{
    material_ = field.current().material.present();
    return applyMaterial(field, c.proxy, c.contact, friction_);
}

glm::dvec3 FingerOutput::force(const glm::dvec3 &hip, const glm::dvec3 &held, const FingerGoal &c,
                               double t, double stiffnessScale, double raw,
                               const HeightField &field, bool wasInContact) noexcept
{
    glm::dvec3 rawForce =
        force_.spring(hip, held, c.contact, t, boundScale(stiffnessScale, hip, held, c));
    releaseCovered(hip, raw, field, c, wasInContact, rawForce);
    const glm::dvec3 command = force_.shape(rawForce, t, c.contact, c.trip || c.stepped);
    watchSaturation(command, t, c.contact);
    return command;
}

double FingerOutput::boundScale(double target, const glm::dvec3 &hip, const glm::dvec3 &held,
                                const FingerGoal &c) noexcept
{
    // The material's stiffness scale is bilinear over a pixel (material_field.h): a proxy crossing
    // a boundary under a deep press steps the force by Δscale·k·depth (the demo's head beside the
    // curtain, 675 → 525 N/m at 6.8 mm: 1.04 N in an update). In a continuing contact it moves at
    // most by what changes the force by p_.unloadForce an update, the output stage's rate for a
    // surface that changes under a pressed finger; a new contact, a trip or a step takes it at
    // once (the ramp blends that force in).
    const double depth = glm::length(held - hip);
    const double k = force_.stiffness();
    if (!c.contact || !c.touching || c.trip || c.stepped || !(depth > 0.0) || !(k > 0.0)) {
        scale_ = target;
        return scale_;
    }
    const double most = p_.unloadForce / (k * depth);
    scale_ += std::clamp(target - scale_, -most, most);
    return scale_;
}

void FingerOutput::reset() noexcept
{
    scale_ = 1.0;
    offset_ = {};
    offsetTrend_ = {};
    lastOffset_ = {};
    trust_ = 0.0;
    lastT_ = std::nan("");
    release_ = {};
    releaseStep_ = 0.0;
    lastChange_ = {};
    lastAlong_ = 0.0;
    saturatedSince_ = std::nan("");
    letGoNext_ = false;
    force_.reset();
    friction_.release();
}

void FingerOutput::setOutputGain(double gain) noexcept
{
    if (!std::isnan(gain))
        outputGain_ = std::clamp(gain, 0.0, 1.0);
}

void FingerOutput::watchSaturation(const glm::dvec3 &force, double t, bool contact) noexcept
{
    // The command at the device maximum: the finger is deeper than the device can push it out of
    // (an object pressed onto it that the hand does not yield to, or a press past what the device
    // renders). Held there for kFingerSaturationTime, the next update lets it go.
    const double sent = outputGain_ * glm::length(force);
    if (!contact || !config_.safety || !(sent >= config_.maxForce * (1.0 - kFingerAtMaximum))) {
        saturatedSince_ = std::nan("");
        return;
    }
    if (std::isnan(saturatedSince_))
        saturatedSince_ = t;
    if (t - saturatedSince_ >= kFingerSaturationTime) {
        letGoNext_ = true;
        saturatedSince_ = std::nan("");
    }
}

} // namespace depthtouch::haptics
