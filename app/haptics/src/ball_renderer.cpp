/// \file
/// \brief The ball fingertip renderer (ball_renderer.h): one proxy solve on the ball-swept
/// surface, three states, the shared output stage.

#include "depthtouch/haptics/ball_renderer.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/material_field.h"

namespace depthtouch::haptics {

namespace {

/// A proxy this near the HIP is on it: the solve's last step to the HIP's x–y lands there up to
/// rounding, m.
constexpr double kOnHip = 1e-9;

/// The least |n.z| the solve's slope −n.xy/n.z is taken at: a normal nearer horizontal (the ball
/// against a wall's edge at its equator) is a face to slide along, whose slope is this steep.
constexpr double kSteepestNz = 1e-3;

} // namespace

BallRenderer::BallRenderer(const RendererConfig &config) noexcept
    : config_(config), field_(config.box), p_(fingerParameters(config)), ball_(p_.radius),
      output_(config, p_), friction_(config.staticFriction, config.dynamicFriction)
{
    field_.setCutThreshold(config.cutThreshold);
}

Result<void> BallRenderer::setFrames(const DepthFrameView &current,
                                     const DepthFrameView *next) noexcept
{
    return field_.setFrames(current, next);
}

void BallRenderer::setStiffness(double newtonsPerMetre) noexcept
{
    output_.setStiffness(newtonsPerMetre);
    config_.stiffness = output_.stiffness();
}

void BallRenderer::reset(const glm::dvec3 &hip) noexcept
{
    state_ = FingerState::Free;
    lastHip_ = hip;
    surfaceProxy_ = hip;
    lastDepth_ = 0.0;
    lastTaps_.fill(std::nan(""));
    enterAnyDepth_ = true;
    output_.reset();
    friction_.release();
}

BallRenderer::Solution BallRenderer::solve(const glm::dvec3 &hip, double fromX, double fromY,
                                           const BallPoint &start, double reach,
                                           bool hipFree) const noexcept
{
    // f(x, y) = |(x, y) − h.xy|² + max(0, S(x, y) − h.z)² (ball_renderer.h, part 2).
    auto objective = [&hip](double x, double y, double height) {
        const double dx = x - hip.x;
        const double dy = y - hip.y;
        const double e = height > hip.z ? height - hip.z : 0.0; // 0 for NaN: nothing holds
        return dx * dx + dy * dy + e * e;
    };
    Solution s;
    double x = fromX;
    double y = fromY;
    double height = start.height; // S at (x, y)
    double f = objective(x, y, height);
    // Tries the step (sx, sy), then half of it: \return whether either lowered f.
    auto tryStep = [&](double sx, double sy) {
        // A step reaches at most r (the ball's own disc); the whole solve at most \a reach.
        const double step = std::hypot(sx, sy);
        if (step > p_.radius) {
            sx *= p_.radius / step;
            sy *= p_.radius / step;
        }
        for (const double share : {1.0, 0.5}) {
            double cx = x + share * sx;
            double cy = y + share * sy;
            const double far = std::hypot(cx - fromX, cy - fromY);
            if (far > reach) {
                cx = fromX + (cx - fromX) * (reach / far);
                cy = fromY + (cy - fromY) * (reach / far);
            }
            const double hc = ball_.height(field_, cx, cy);
            const double fc = objective(cx, cy, hc);
            if (fc < f) {
                x = cx;
                y = cy;
                height = hc;
                f = fc;
                return true;
            }
        }
        return false;
    };
    // Where the HIP is in free space at its own x–y the straight step goes first: a proxy whose
    // way to the HIP is clear ends on it (a finger rolled off a rim), where the tangent plane of a
    // face would only slide it along the face. Under S, the Gauss–Newton step goes first.
    glm::dvec3 n = start.normal;
    bool normalAtXY = true;
    for (int it = 0; it < kBallIterations && f > 0.0; ++it) {
        const double ex = x - hip.x;
        const double ey = y - hip.y;
        bool taken = hipFree && tryStep(-ex, -ey);
        if (!taken && height > hip.z) {
            // Under S here: the Gauss–Newton step of f, −(I + g gᵀ)⁻¹ (Δ + e·g) with g = ∇S =
            // −n.xy / n.z: the HIP's projection on the tangent plane of S, moved along S.
            if (!normalAtXY)
                n = ball_.normal(field_, x, y, height);
            const double nz = std::max(n.z, kSteepestNz);
            const double gx = -n.x / nz;
            const double gy = -n.y / nz;
            const double e = height - hip.z;
            const double rx = ex + e * gx;
            const double ry = ey + e * gy;
            const double gr = (gx * rx + gy * ry) / (1.0 + gx * gx + gy * gy);
            const double ox = x;
            const double oy = y;
            taken = tryStep(-(rx - gx * gr), -(ry - gy * gr));
            normalAtXY = !taken || (x == ox && y == oy);
        }
        // Above S here (beside a wall, or off the surface), or where the tangent plane does not
        // hold (S is a face, a jump the plane cannot see past): straight toward the HIP's x–y.
        if (!taken && !hipFree)
            taken = tryStep(-ex, -ey);
        if (taken)
            normalAtXY = false;
        else
            break;
    }
    if (x == fromX && y == fromY) {
        s.at = start;
    } else {
        s.at.height = ball_.height(field_, x, y, s.at.taps); // the taps, for the next cut test
        s.at.normal = n;
    }
    s.proxy = {x, y, height > hip.z ? height : hip.z};
    return s;
}

double BallRenderer::patchStep(const BallPoint &now) const noexcept
{
    std::array<double, kBallTaps> moved{};
    std::size_t n = 0;
    for (std::size_t i = 0; i < kBallTaps; ++i) {
        const double d = std::fabs(now.taps[i] - lastTaps_[i]);
        if (d == d)
            moved[n++] = d;
    }
    if (n == 0)
        return 0.0;
    const auto mid = moved.begin() + static_cast<std::ptrdiff_t>(n / 2);
    std::nth_element(moved.begin(), mid, moved.begin() + static_cast<std::ptrdiff_t>(n));
    return *mid;
}

void BallRenderer::boundPush(const glm::dvec3 &hip, glm::dvec3 &goal) const noexcept
{
    const glm::dvec3 offset = goal - hip;
    const double depth = glm::length(offset);
    if (!(depth > 0.0))
        return;
    const glm::dvec3 dir = offset / depth;
    const double allowed = lastDepth_ + std::max(0.0, glm::dot(lastHip_ - hip, dir)) + p_.pushDepth;
    if (depth > allowed)
        goal = hip + dir * allowed;
}

HapticOutput BallRenderer::update(const glm::dvec3 &hip, double t) noexcept
{
    HapticOutput out;
    out.hip = hip;
    field_.setTime(t, config_.interpolation);
    const bool wasInContact = state_ == FingerState::Touching;
    FingerGoal c;
    c.proxy = hip;
    c.touching = wasInContact;
    c.hipMove = hip - lastHip_;
    const bool over = field_.contains(hip.x, hip.y);
    const double raw = over ? field_.heightAt(hip.x, hip.y) : std::nan("");
    const bool under = over && ball_.height(field_, hip.x, hip.y) > hip.z; // false for NaN
    // Where the solve starts: the last proxy in contact (fix (a): on the surface now), else the
    // last HIP (a finger that came from the side under a face meets the face).
    const glm::dvec3 &from = wasInContact && config_.correction ? surfaceProxy_ : lastHip_;
    Solution s{hip, {}};
    if (wasInContact || under) {
        const BallPoint start = ball_.at(field_, from.x, from.y);
        if (wasInContact && config_.safety && patchStep(start) > field_.cutThreshold())
            c.trip = true; // a cut: the whole patch under the finger moved (fix (c))
        const double moved = std::hypot(hip.x - lastHip_.x, hip.y - lastHip_.y);
        s = solve(hip, from.x, from.y, start, moved + (wasInContact ? p_.glideReach : p_.radius),
                  !under);
    }
    const double depth = glm::length(s.proxy - hip);
    const bool inCapture = enterAnyDepth_ || depth <= p_.captureDepth || !config_.safety;
    c.contact = depth > kOnHip && (wasInContact || inCapture);
    glm::dvec3 goal = s.proxy;
    if (c.contact)
        boundPush(hip, goal);
    // The device maximum held too long lets go (kFingerSaturationTime); a cut too under
    // Reengage::Release, while Reengage::Ramp keeps the contact and ramps the force in.
    const bool saturated = output_.takeLetGo() && c.contact;
    c.trip = c.trip || saturated;
    if (c.trip && (saturated || config_.reengage == Reengage::Release))
        c.contact = false;
    c.proxy = c.contact ? goal : hip;
    // The material under the goal, friction on the filtered proxy (as the finger renderer).
    const bool material = field_.current().material.present();
    const double scale = applyMaterial(field_, c.proxy, c.contact, friction_);
    glm::dvec3 held = output_.filter(hip, c, t, scale);
    if (friction_.enabled() || material) {
        if (c.contact && !c.trip)
            held = friction_.apply(held, hip, t);
        else
            friction_.release();
    }
    out.force = output_.force(hip, held, c, t, scale, raw, field_, wasInContact);
    out.proxy = held;
    out.contact = c.contact;
    out.released = c.trip;
    out.constraints = c.contact ? 1 : 0;
    // What the next update starts from.
    state_ = c.contact ? FingerState::Touching : under ? FingerState::Behind : FingerState::Free;
    lastHip_ = hip;
    surfaceProxy_ = c.contact ? s.proxy : hip;
    lastDepth_ = c.contact ? glm::length(goal - hip) : 0.0;
    lastTaps_ = s.at.taps;
    if (!c.contact)
        lastTaps_.fill(std::nan(""));
    enterAnyDepth_ = false;
    return out;
}

} // namespace depthtouch::haptics
