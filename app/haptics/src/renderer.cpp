#include "depthtouch/haptics/renderer.h"

#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "depthtouch/haptics/material_field.h"
#include "depthtouch/haptics/proxy_solver.h"

namespace depthtouch::haptics {

glm::dvec3 limitForce(const glm::dvec3 &force, double limit) noexcept
{
    const double length = glm::length(force);
    if (!(length <= limit)) // also catches NaN
        return std::isfinite(length) ? force * (limit / length) : glm::dvec3(0.0);
    return force;
}

glm::dvec3 slewForce(const glm::dvec3 &previous, const glm::dvec3 &target, double maxStep,
                     double maxForce) noexcept
{
    const glm::dvec3 to = limitForce(target, std::numeric_limits<double>::max());
    return limitForce(previous + limitForce(to - previous, maxStep), maxForce);
}

Result<FingerContact> parseFingerContact(std::string_view text) noexcept
{
    if (text == "god-object")
        return FingerContact::GodObject;
    if (text == "penalty")
        return FingerContact::Penalty;
    if (text == "adaptive")
        return FingerContact::Adaptive;
    return unexpected(Errc::InvalidArgument,
                      "finger contact must be god-object, penalty or adaptive");
}

Result<void> RendererConfig::validate() const noexcept
{
    auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
    if (!positive(box.width) || !positive(box.depth))
        return unexpected(Errc::InvalidArgument, "box width and depth must be positive");
    static_assert(options::kStiffness.min == 100.0 && options::kStiffness.max == 3000.0,
                  "the message below says the range");
    if (!scene::stiffnessInRange(stiffness))
        return unexpected(Errc::InvalidArgument, "stiffness must be in [100, 3000] N/m");
    if (!std::isfinite(damping) || damping < 0.0)
        return unexpected(Errc::InvalidArgument, "damping must be zero or positive");
    if (!positive(maxForce))
        return unexpected(Errc::InvalidArgument, "max force must be positive");
    if (!positive(maxForceStep))
        return unexpected(Errc::InvalidArgument, "max force step must be positive");
    if (!positive(rampTime))
        return unexpected(Errc::InvalidArgument, "ramp time must be positive");
    if (!std::isnan(cutThreshold) && !(cutThreshold > 0.0))
        return unexpected(Errc::InvalidArgument, "cut threshold must be positive");
    if (!std::isnan(coarseSpacing) && !(std::isfinite(coarseSpacing) && coarseSpacing >= 0.0))
        return unexpected(Errc::InvalidArgument, "coarse spacing must be zero or positive");
    if (!std::isnan(fingerRadius) && !(std::isfinite(fingerRadius) && fingerRadius > 0.0))
        return unexpected(Errc::InvalidArgument, "finger radius must be positive");
    auto friction = [](double mu) { return mu >= 0.0 && mu <= kMaxFriction; }; // false for NaN
    if (!friction(staticFriction) || !friction(dynamicFriction))
        return unexpected(Errc::InvalidArgument, "friction coefficients must be within 0..2");
    return ok();
}

// ---------------------------------------------------------------------------------------------

void ForceStage::reset() noexcept
{
    havePrev_ = false;
    rebase_ = false;
    prevRaw_ = prevCommand_ = prevHip_ = glm::dvec3(0.0);
    prevT_ = 0.0;
    ramping_ = false;
}

void ForceStage::setStiffness(double newtonsPerMetre) noexcept
{
    if (!scene::stiffnessInRange(newtonsPerMetre))
        return;
    prevRaw_ *= newtonsPerMetre / config_.stiffness;
    config_.stiffness = newtonsPerMetre;
}

glm::dvec3 ForceStage::spring(const glm::dvec3 &hip, const glm::dvec3 &proxy, bool contact,
                              double t, double stiffnessScale) noexcept
{
    glm::dvec3 raw = (config_.stiffness * stiffnessScale) * (proxy - hip);
    if (contact && config_.damping > 0.0 && havePrev_ && !rebase_ && t > prevT_)
        raw -= config_.damping * (hip - prevHip_) / (t - prevT_);
    prevHip_ = hip;
    return raw;
}

glm::dvec3 ForceStage::shape(glm::dvec3 raw, double t, bool contact, bool trip) noexcept
{
    raw = limitForce(raw, std::numeric_limits<double>::max()); // non-finite → zero
    if (rebase_) {
        // The clock restarted: a ramp in progress keeps its progress on the new clock.
        rampStartT_ = t - (prevT_ - rampStartT_);
        rebase_ = false;
    }
    glm::dvec3 command;
    if (!config_.safety) {
        command = limitForce(raw, config_.maxForce);
    } else {
        if (trip) {
            ramping_ = true;
            rampStartT_ = t;
            rampStart_ = prevCommand_;
        }
        // A ramp re-engages a contact; once the finger is free there is nothing to ramp to (a
        // ramp kept then would push on a finger that has left the surface: phantom force).
        if (!contact)
            ramping_ = false;
        glm::dvec3 target = limitForce(raw, config_.maxForce);
        if (ramping_) {
            // Linear blend from the force at the trip to the (clamped) force of the new contact.
            const double a = (t - rampStartT_) / config_.rampTime;
            if (a >= 1.0)
                ramping_ = false;
            else
                target = rampStart_ + (target - rampStart_) * std::max(a, 0.0);
        }
        // Final guard: the commanded force never moves by more than the threshold in one update
        // (a release from a large force unloads over a few updates instead of in one step).
        command = slewForce(prevCommand_, target, config_.maxForceStep, config_.maxForce);
    }
    prevRaw_ = raw;
    prevCommand_ = command;
    prevT_ = t;
    havePrev_ = true;
    return command;
}

glm::dvec3 ForceStage::apply(const glm::dvec3 &hip, glm::dvec3 &proxy, bool &contact, double t,
                             double surfaceAboveHip, bool &released, double stiffnessScale) noexcept
{
    const double k = config_.stiffness * stiffnessScale;
    glm::dvec3 raw = spring(hip, proxy, contact, t, stiffnessScale);
    released = false;
    // Paper IV.C: watch the force; a change above the threshold in one update is a scene cut or
    // the edge of a fast object, not something the viewer did.
    if (config_.safety && havePrev_ && glm::length(raw - prevRaw_) > config_.maxForceStep) {
        released = true;
        if (config_.reengage == Reengage::Release || std::isnan(surfaceAboveHip) ||
            !(surfaceAboveHip > hip.z)) {
            proxy = hip;
            contact = false;
        } else {
            proxy = glm::dvec3(hip.x, hip.y, surfaceAboveHip);
            contact = true;
        }
        raw = k * (proxy - hip);
    }
    // Release leaves no contact after a trip, so only Ramp ramps.
    return shape(raw, t, contact, released);
}

// ---------------------------------------------------------------------------------------------

ProxyGraphRenderer::ProxyGraphRenderer(const RendererConfig &config) noexcept
    : config_(config), field_(config.box), force_(config),
      friction_(config.staticFriction, config.dynamicFriction)
{
    field_.setCutThreshold(config.cutThreshold);
}

Result<void> ProxyGraphRenderer::setFrames(const DepthFrameView &current,
                                           const DepthFrameView *next) noexcept
{
    DT_TRY(field_.setFrames(current, next));
    const double coarse =
        std::isnan(config_.coarseSpacing) ? config_.box.width / 719.0 : config_.coarseSpacing;
    coarse_ = CoarseGrid::of(field_.columns(), field_.rows(),
                             static_cast<int>(std::floor(coarse / field_.spacing())));
    return ok();
}

void ProxyGraphRenderer::reset(const glm::dvec3 &hip) noexcept
{
    proxy_ = hip;
    lastHip_ = hip;
    haveProxy_ = true;
    surfaceUnderProxy_ = std::nan("");
    force_.reset();
    friction_.release();
}

HapticOutput ProxyGraphRenderer::update(const glm::dvec3 &hip, double t) noexcept
{
    HapticOutput out;
    out.hip = hip;
    field_.setTime(t, config_.interpolation);
    glm::dvec3 start = haveProxy_ ? proxy_ : hip;
    // Fix (a), paper IV.A / Fig. 7: move the previous proxy up by how far the surface under it rose
    // since the last update, so a rising surface cannot pass through it.
    if (config_.correction && haveProxy_ && !std::isnan(surfaceUnderProxy_) &&
        field_.contains(start.x, start.y)) {
        const double rise = field_.heightAt(start.x, start.y) - surfaceUnderProxy_;
        if (rise > 0.0)
            start.z += rise;
    }
    glm::dvec3 proxy = hip;
    bool contact = false;
    const double above =
        field_.contains(hip.x, hip.y) ? field_.heightAt(hip.x, hip.y) : std::nan("");
    const Crossing hit = firstCrossing(field_, start, hip);
    out.cellsVisited = hit.cellsVisited;
    out.cellsTested = hit.cellsTested;
    if (hit.hit) {
        // A HIP that moved more than a stride since the last update drags the proxy far: the
        // coarse pass runs without a tangent-plane guess (whose rows it would read for nothing).
        const double stride = static_cast<double>(coarse_.stride);
        double minCells = stride;
        if (coarse_.stride >= 2) {
            const glm::dvec2 step(hip - lastHip_);
            const double reach = stride * field_.spacing();
            if (glm::dot(step, step) > reach * reach)
                minCells = 0.0;
        }
        const ProxySolution sol =
            solveProxyCoarseToFine(field_, hit.triangle, hip, coarse_, minCells);
        out.proxySteps = sol.steps;
        // The proxy may have slid to where nothing separates it from the HIP any more (it went
        // round a ridge): then it is free. The segment starts on the surface; when the HIP is
        // under the surface by more than the tolerance it ends below it, so firstCrossing() would
        // find a crossing (at the HIP at the latest): the walk is needed only otherwise.
        const double tol = kSurfaceTolerance * field_.spacing();
        bool held = hip.z < above - 2.0 * tol; // false when the HIP is off the grid (NaN)
        if (!held) {
            const Crossing again = firstCrossing(field_, sol.point, hip);
            out.cellsVisited += again.cellsVisited;
            out.cellsTested += again.cellsTested;
            held = again.hit;
        }
        if (held) {
            proxy = sol.point;
            contact = true;
            out.constraints = sol.constraints;
        }
    }
    // Friction (friction.h): the force comes from the proxy the cone holds; the frictionless
    // god-object stays the start of the next collision walk (the held proxy lies on the tangent
    // plane, which may be under a curved surface).
    // A material track gives the stiffness scale and μs, μd under the goal (material_field.h).
    glm::dvec3 goal = proxy;
    const bool material = field_.current().material.present();
    const double stiffnessScale = applyMaterial(field_, goal, contact, friction_);
    if (friction_.enabled() || material) {
        if (contact)
            proxy = friction_.apply(goal, hip, t);
        else
            friction_.release();
    }
    out.force = force_.apply(hip, proxy, contact, t, above, out.released, stiffnessScale);
    if (out.released) {
        out.constraints = contact ? 1 : 0;
        goal = proxy; // released to the HIP or re-seated above it
        friction_.release();
    }
    out.proxy = proxy;
    out.contact = contact;
    lastHip_ = hip;
    proxy = goal;
    proxy_ = proxy;
    haveProxy_ = true;
    // h(proxy.xy) without refetching: over the HIP (free, released or re-seated) it is `above`; a
    // proxy held by the solver lies on the surface, so it is the proxy's own z (up to rounding).
    if (proxy.x == hip.x && proxy.y == hip.y)
        surfaceUnderProxy_ = above;
    else
        surfaceUnderProxy_ = field_.contains(proxy.x, proxy.y) ? proxy.z : std::nan("");
    return out;
}

} // namespace depthtouch::haptics
