/// \file
/// \brief The ball fingertip renderer (ball_renderer.h): one proxy solve on the ball-swept
/// surface, three states, the shared output stage.

#include "depthtouch/haptics/ball_renderer.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace depthtouch::haptics {

namespace {

/// A proxy this near the HIP is on it: the solve's last step to the HIP's x–y lands there up to
/// rounding, m.
constexpr double kOnHip = 1e-9;

/// The least |n.z| the solve's slope −n.xy/n.z is taken at: a normal nearer horizontal (the ball
/// against a wall's edge at its equator) is a face to slide along, whose slope is this steep.
constexpr double kSteepestNz = 1e-3;

/// \return f(x, y) = |(x, y) − h.xy|² + max(0, S − h.z)² for \a height S there (ball_renderer.h,
/// part 2), m²; a NaN S (nothing measured) holds nothing.
double objective(const glm::dvec3 &hip, double x, double y, double height) noexcept
{
    const double dx = x - hip.x;
    const double dy = y - hip.y;
    const double e = height > hip.z ? height - hip.z : 0.0;
    return dx * dx + dy * dy + e * e;
}

/// \return the Gauss–Newton step of f at (\a x, \a y) (m, x–y), where S is \a at and above the
/// HIP: −(I + g gᵀ)⁻¹ (Δ + e·g), g = ∇S = −n.xy / n.z, the HIP's projection on the tangent plane
/// moved along it; \a predicted is f after it on that plane, m².
glm::dvec2 newtonStep(const glm::dvec3 &hip, double x, double y, const BallPoint &at,
                      double &predicted) noexcept
{
    const glm::dvec3 &n = at.normal;
    const double nz = std::max(n.z, kSteepestNz);
    const double gx = -n.x / nz;
    const double gy = -n.y / nz;
    const double ex = x - hip.x;
    const double ey = y - hip.y;
    const double e = at.height - hip.z;
    const double rx = ex + e * gx;
    const double ry = ey + e * gy;
    const double gr = (gx * rx + gy * ry) / (1.0 + gx * gx + gy * gy);
    const glm::dvec2 step(-(rx - gx * gr), -(ry - gy * gr));
    const double lx = ex + step.x;
    const double ly = ey + step.y;
    const double le = std::max(0.0, e + gx * step.x + gy * step.y);
    predicted = lx * lx + ly * ly + le * le;
    return step;
}

} // namespace

BallRenderer::BallRenderer(const RendererConfig &config) noexcept
    : config_(config), field_(config.box), p_(fingerParameters(config)), ball_(p_.radius),
      output_(config, p_)
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
}

BallRenderer::Solution BallRenderer::solve(const glm::dvec3 &hip, double fromX, double fromY,
                                           const BallPoint &start, const BallPoint *atHip,
                                           double reach, bool hipFree) const noexcept
{
    Solution s;
    double x = fromX;
    double y = fromY;
    s.at = start;
    double f = objective(hip, x, y, s.at.height);
    if (hipFree && clearPath(glm::dvec3(x, y, std::max(s.at.height, hip.z)), hip)) {
        // The god-object's own rule: a proxy whose way to the HIP is clear goes to it, however far
        // (the reach bounds a move along the surface, not a release into free space).
        s.proxy = hip;
        return s;
    }
    // One trial point: the step (sx, sy) by \a share from (x, y), within r (the ball's own disc)
    // and the whole solve within \a reach of where it started.
    struct Trial {
        double x, y, f;
        BallPoint at;
    };
    auto trial = [&](double sx, double sy, double share) {
        const double step = std::hypot(sx, sy);
        const double scale = share * (step > p_.radius ? p_.radius / step : 1.0);
        double cx = x + scale * sx;
        double cy = y + scale * sy;
        const double far = std::hypot(cx - fromX, cy - fromY);
        if (far > reach) {
            cx = fromX + (cx - fromX) * (reach / far);
            cy = fromY + (cy - fromY) * (reach / far);
        }
        // The straight step's full share lands on the HIP's x–y, already queried by update().
        const bool onHip = atHip != nullptr && cx == hip.x && cy == hip.y;
        Trial t{cx, cy, 0.0, onHip ? *atHip : ball_.at(field_, cx, cy)};
        t.f = objective(hip, cx, cy, t.at.height);
        return t;
    };
    // Two steps: the Gauss–Newton step on the tangent plane of S (where the proxy is under S) and
    // the straight step toward the HIP's x–y (the descent of |Δ|², f's other term). The
    // Gauss–Newton step goes first and is taken where f falls by at least a quarter of what the
    // tangent plane predicts (the trust-region test; Nocedal & Wright, "Numerical Optimization",
    // ch. 4). Where it does not (S is a face, or curves away within the step) or the HIP is free
    // at its own x–y (its way may be clear), the straight step is tried too and the lower f taken:
    // the proxy rolls off a rim, or onto a top that has come nearer than a face. Neither lowering
    // f, their halves; neither again, or a step under the search resolution (ΔF/(1024k): a force
    // error under ΔF/1024), the solve has converged. (A fifth of a pixel, 0.06 mm in the default
    // box at 320 pixels, left a frictionless tilted plane's force 1.8° off its normal.)
    const double settle = p_.searchResolution;
    for (int it = 0; it < kBallIterations && f > 0.0; ++it) {
        const double ex = x - hip.x;
        const double ey = y - hip.y;
        double predicted = f; // f after the Gauss–Newton step, on the tangent plane
        const bool under = s.at.height > hip.z;
        const glm::dvec2 gn = under ? newtonStep(hip, x, y, s.at, predicted) : glm::dvec2{};
        const double gnx = gn.x;
        const double gny = gn.y;
        const bool newtonMoves = under && std::hypot(gnx, gny) > settle;
        const bool straightMoves = std::hypot(ex, ey) > settle;
        if (!straightMoves && !newtonMoves)
            break;
        Trial best{x, y, f, {}};
        bool found = false;
        for (const double share : {1.0, 0.5}) {
            bool trusted = false;
            if (newtonMoves) {
                Trial newton = trial(gnx, gny, share);
                trusted = f - newton.f >= 0.25 * share * (f - predicted);
                if (newton.f < best.f) {
                    best = newton;
                    found = true;
                }
            }
            if (straightMoves && (!trusted || hipFree || !under)) {
                Trial straight = trial(-ex, -ey, share);
                if (straight.f < best.f) {
                    best = straight;
                    found = true;
                }
            }
            if (found)
                break;
        }
        if (!found)
            break;
        x = best.x;
        y = best.y;
        f = best.f;
        s.at = best.at;
    }
    s.proxy = {x, y, s.at.height > hip.z ? s.at.height : hip.z};
    return s;
}

bool BallRenderer::clearPath(const glm::dvec3 &from, const glm::dvec3 &to) const noexcept
{
    // The segment from the proxy to the HIP (the HIP itself is known free) at a third and two
    // thirds: the ball's lowest point there above S. A ridge narrower than a third of the path
    // and the ball together can be missed: at 1 m/s the path is 1 mm an update.
    for (const double share : {1.0 / 3.0, 2.0 / 3.0}) {
        const glm::dvec3 p = from + share * (to - from);
        if (ball_.at(field_, p.x, p.y).height > p.z)
            return false;
    }
    return true;
}

double BallRenderer::patchStep(const BallPoint &now) const noexcept
{
    // A tap that is or was a hole, or on a hole's cliff (HeightField::besideHole()), moved 0: a
    // hole opening or closing is no cut (as the finger's stencilStep()); on time-of-flight depth
    // most of the disc may be holes, and the few taps left were the moving hand's.
    std::array<double, kBallTaps> moved{};
    for (std::size_t i = 0; i < kBallTaps; ++i) {
        const double a = now.taps[i];
        const double b = lastTaps_[i];
        const bool both = a == a && b == b && !field_.besideHole(a) && !field_.besideHole(b);
        moved[i] = both ? std::fabs(a - b) : 0.0;
    }
    const auto mid = moved.begin() + kBallTaps / 2;
    std::nth_element(moved.begin(), mid, moved.end());
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
    const BallPoint atHip = over ? ball_.at(field_, hip.x, hip.y) : BallPoint{};
    const bool under = over && atHip.height > hip.z; // false for NaN
    // Where the solve starts: the last proxy in contact (fix (a): on the surface now), else the
    // last HIP (a finger that came from the side under a face meets the face).
    const glm::dvec3 &from = wasInContact && config_.correction ? surfaceProxy_ : lastHip_;
    Solution s{hip, {}};
    if (wasInContact || under) {
        const BallPoint start = ball_.at(field_, from.x, from.y);
        if (wasInContact && config_.safety && patchStep(start) > field_.cutThreshold())
            c.trip = true; // a cut: the whole patch under the finger moved (fix (c))
        const double moved = std::hypot(hip.x - lastHip_.x, hip.y - lastHip_.y);
        s = solve(hip, from.x, from.y, start, over ? &atHip : nullptr,
                  moved + (wasInContact ? p_.glideReach : p_.radius), !under);
    }
    // Part 3's guards (ball_renderer.h's diagram), by their names there.
    const double depth = glm::length(s.proxy - hip);
    const bool inCapture = enterAnyDepth_ || depth <= p_.captureDepth || !config_.safety;
    const bool reachedHip = !(depth > kOnHip);
    c.contact = !reachedHip && (wasInContact || inCapture);
    glm::dvec3 goal = s.proxy;
    if (c.contact)
        boundPush(hip, goal);
    // letGo: the device maximum held too long (kFingerSaturationTime), or a cut under
    // Reengage::Release; Reengage::Ramp keeps the contact through a cut and ramps the force in.
    const bool saturated = output_.takeLetGo() && c.contact;
    c.trip = c.trip || saturated;
    const bool letGo = c.trip && (saturated || config_.reengage == Reengage::Release);
    if (letGo)
        c.contact = false;
    c.proxy = c.contact ? goal : hip;
    // The material under the goal, friction on the filtered proxy (FingerOutput).
    const double scale = output_.material(field_, c);
    const glm::dvec3 held = output_.filter(hip, c, t);
    out.force = output_.force(hip, held, c, t, scale, raw, field_, wasInContact);
    out.proxy = held;
    out.contact = c.contact;
    out.released = c.trip;
    out.constraints = c.contact ? 1 : 0;
    remember(hip, c.contact, under, s, goal);
    return out;
}

void BallRenderer::remember(const glm::dvec3 &hip, bool contact, bool under, const Solution &s,
                            const glm::dvec3 &goal) noexcept
{
    state_ = contact ? FingerState::Touching : under ? FingerState::Behind : FingerState::Free;
    lastHip_ = hip;
    surfaceProxy_ = contact ? s.proxy : hip;
    lastDepth_ = contact ? glm::length(goal - hip) : 0.0;
    lastTaps_ = s.at.taps;
    if (!contact)
        lastTaps_.fill(std::nan(""));
    enterAnyDepth_ = false;
}

} // namespace depthtouch::haptics
