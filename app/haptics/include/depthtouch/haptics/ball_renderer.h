#pragma once
/// \file
/// \brief The ball fingertip: the fingertip as a ball of radius r on the depth video, rendered
/// by one proxy solve on the ball-swept surface. Method::Ball (`--method ball`).
///
/// The model, in four parts, one idea each:
/// 1. **Surface** (BallSurface, ball_surface.h): the swept height S(x, y), the lowest the
///    fingertip's lowest point may be at an x–y, with its normal; stateless, holes unknown,
///    paper Eq. 1 in time. What a finger cannot enter (a gap narrower than it, a pixel read
///    low under it) it does not feel; a step taller than r is a wall r in front of the step.
/// 2. **Proxy** (solve()): the god-object (Zilles & Salisbury 1995) on that surface. The proxy p
///    minimises |p − h| (h the HIP) subject to p.z ≥ S(p.x, p.y): for a given x–y the best p.z is
///    max(S, h.z), so the solve is over x–y alone, of
///
///        f(x, y) = |(x, y) − h.xy|² + max(0, S(x, y) − h.z)²,
///
///    from the last proxy by steps each taken only where it lowers f: the Gauss–Newton step (the
///    HIP's projection on the tangent plane of S), and where the plane's prediction fails (a face,
///    a rim) or the HIP is free at its own x–y also the straight step toward h.xy, the lower f
///    taken; halved once, else the solve has converged; at most kBallIterations steps (Nocedal &
///    Wright, "Numerical Optimization", ch. 4, the trust-region test). The whole solve moves the
///    proxy's x–y at most the HIP's own motion plus r/4 (FingerParameters::glideReach): the
///    variable proxy step of Rydén & Chizeck (2013), so a jump of the optimum is a glide. A HIP
///    free at its own x–y whose way from the proxy is clear (clearPath()) is reached at once: the
///    bound is for moves along the surface. A descent that only goes down from where it was
///    cannot take turns between two solutions. Walls, gliding and the rim a finger rolls off come
///    out of this one formulation, with no rule of their own.
/// 3. **State** (FingerState, three of its values): one enum, one guard per transition:
///
///        ┌──────┐ h under S, depth ≤ captureDepth (inCapture) ┌──────────┐
///        │ Free │ ─────────────────────────────────────────→ │ Touching │
///        └──────┘ ←───────────────────────────────────────── └──────────┘
///          ↑  │    the solve reached h (reachedHip)             │    ↑
///  out of S│  │ h under S deeper (!inCapture)   cut, or the     │    │ depth ≤ captureDepth
///  (!under)│  ↓                                 device maximum  │    │ (inCapture)
///        ┌────────┐ ←──────────────────────── held (letGo) ─────┘    │
///        │ Behind │ ─────────────────────────────────────────────────┘
///        └────────┘
///
///    Behind is a finger under the surface without contact: it came from the side under an
///    object's silhouette, the surface jumped onto it, or it was let go (a cut under
///    Reengage::Release; the device maximum held for kFingerSaturationTime). It is free until
///    out, or caught again where it is within the capture depth.
/// 4. **Output** (FingerOutput, finger_output.h, shared with the finger renderer): the bounded
///    push (below), then the offset filter, spring, ramp, slew, clamp and the watch of the device
///    maximum, in one place before the HAL's clamp.
///
/// The bounded push: in contact, the HIP's depth under the proxy grows by at most the HIP's own
/// motion into the surface plus FingerParameters::pushDepth an update, so a surface sweeping
/// under a resting finger (a typing hand, a turning head) pushes it out at a bounded rate.
///
/// Every threshold is a row of FingerParameters (fingerParameters(): capture, step, push and
/// unload depths from the force step and k at construction; the glide reach from r). A stiffness
/// change changes forces, not when contact exists.
///
/// Fixes: (a) the proxy starts each update from the last on the surface now, so a rising surface
/// lifts it; (b) HeightField's Eq. 1; (c) a cut under the finger (the median of the taps' steps
/// since the last update over HeightField::cutThreshold()) trips RendererConfig::reengage's
/// re-engagement. Friction and material tracks as the finger renderer (FingerOutput::material()
/// and filter(): friction.h, material_field.h).
///
/// Cost: at most 3 + 4·kBallIterations swept-surface queries (BallSurface::at(), kBallTaps height
/// lookups each); on a smooth surface, 4 to 6.
/// Units: m, N, s; positions in the scene-box frame (docs/architecture.md §3).
/// Thread-safety: thread-bound (the haptic thread); update() never allocates, locks or throws.
/// Source: docs/benchmarks.md, "The ball fingertip", for what it measures against the finger.

#include <array>
#include <cmath>

#include <glm/vec3.hpp>

#include "depthtouch/haptics/ball_surface.h"
#include "depthtouch/haptics/finger_output.h"
#include "depthtouch/haptics/finger_parameters.h"
#include "depthtouch/haptics/finger_renderer.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics {

/// Gauss–Newton steps of the proxy solve per update: the solve starts from the last proxy, which
/// is within a glide of the optimum, and each step on a smooth surface takes most of the way.
inline constexpr int kBallIterations = 4;

/// \brief The ball fingertip renderer (the file comment). Method::Ball.
class BallRenderer final : public HapticRenderer {
public:
    /// \param config validated by the caller; its fix flags are used as given.
    explicit BallRenderer(const RendererConfig &config) noexcept;

    [[nodiscard]] Result<void> setFrames(const DepthFrameView &current,
                                         const DepthFrameView *next) noexcept override;
    HapticOutput update(const glm::dvec3 &hip, double t) noexcept override;
    void reset(const glm::dvec3 &hip) noexcept override;
    void restartClock() noexcept override { output_.restartClock(); }
    /// The forces only: the parameter table keeps the stiffness of construction.
    void setStiffness(double newtonsPerMetre) noexcept override;
    void setOutputGain(double gain) noexcept override { output_.setOutputGain(gain); }
    [[nodiscard]] Method method() const noexcept override { return Method::Ball; }

    /// \return the contact state after the last update: Free, Behind or Touching.
    [[nodiscard]] FingerState state() const noexcept { return state_; }
    [[nodiscard]] const char *contactStateName() const noexcept override
    {
        return fingerStateName(state_);
    }
    [[nodiscard]] const FingerParameters &parameters() const noexcept { return p_; }
    [[nodiscard]] const HeightField &surface() const noexcept { return field_; }
    [[nodiscard]] const HeightField *heightField() const noexcept override { return &field_; }
    /// \return the ball's radius r, m.
    [[nodiscard]] double fingertipRadius() const noexcept override { return p_.radius; }

private:
    /// The solve's result: the proxy (m) and the surface point it ended on.
    struct Solution {
        glm::dvec3 proxy{};
        BallPoint at{};
    };
    /// Part 2: the proxy from \a fromX, \a fromY (m; the last proxy's x–y, or the HIP's), whose
    /// swept surface is \a start, for the HIP \a hip; the x–y moves at most \a reach, m.
    /// \a atHip: S at the HIP's own x–y (null off the grid), reused where a step lands there.
    /// \a hipFree: the HIP is not under S at its own x–y (its way may be clear).
    [[nodiscard]] Solution solve(const glm::dvec3 &hip, double fromX, double fromY,
                                 const BallPoint &start, const BallPoint *atHip, double reach,
                                 bool hipFree) const noexcept;
    /// \return whether the ball's lowest point goes from \a from to \a to (m) above S: sampled at a
    /// third and two thirds of the way (the HIP \a to is known free).
    [[nodiscard]] bool clearPath(const glm::dvec3 &from, const glm::dvec3 &to) const noexcept;
    /// \return the median over the taps of |now − then|, m (0 for a tap that is or was a hole):
    /// how far the patch under the proxy moved since the last update. A cut moves all of it; an
    /// object's silhouette crossing the ball moves some taps only.
    [[nodiscard]] double patchStep(const BallPoint &now) const noexcept;
    /// What the next update starts from (part 3's state and the solve's end): the HIP \a hip, the
    /// update's \a contact, the HIP \a under S at its own x–y, the solve \a s and the pushed \a
    /// goal.
    void remember(const glm::dvec3 &hip, bool contact, bool under, const Solution &s,
                  const glm::dvec3 &goal) noexcept;
    /// The bounded push on \a goal (m), in contact: its depth under the proxy grows by at most the
    /// HIP's motion into the surface plus pushDepth since the last update.
    void boundPush(const glm::dvec3 &hip, glm::dvec3 &goal) const noexcept;

    RendererConfig config_;
    HeightField field_;
    FingerParameters p_;
    BallSurface ball_;
    FingerOutput output_;
    /// \name Carried between updates
    ///@{
    FingerState state_ = FingerState::Free;
    glm::dvec3 lastHip_{};      ///< m.
    glm::dvec3 surfaceProxy_{}; ///< The last solve's proxy, before the bounded push, m.
    double lastDepth_ = 0.0;    ///< |proxy − HIP| of the last update in contact, else 0, m.
    std::array<double, kBallTaps> lastTaps_{}; ///< The taps under surfaceProxy_ then, m.
    bool enterAnyDepth_ = true; ///< After reset(): a HIP found inside comes into contact.
    ///@}
};

} // namespace depthtouch::haptics
