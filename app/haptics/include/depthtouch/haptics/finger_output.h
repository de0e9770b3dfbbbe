#pragma once
/// \file
/// \brief The fingertip renderer's force output stage (finger_renderer.h, steps 5 and 7): from the
/// proxy the contact decided to the command, in one place. In order: the material under the goal
/// (its stiffness scale and friction coefficients), the alpha-beta filter on the
/// proxy's offset from the HIP (the surface's noise at speed; a bounded move, turn and unload; the
/// HIP's own move along the offset passing through, as a spring's), the hand-over of a ramp that
/// holds more than the surface gives or that a lifting finger leaves, friction on the filtered
/// proxy (friction.h), the spring s·k·(proxy − HIP) − b·v with the material's scale s moving at a
/// bounded rate, the unload of a contact that ended at a rim or under a cut, ForceStage's ramp,
/// slew and clamp (renderer.h), and the watch of the device maximum. What comes after it is the
/// device's own: the haptic task's gain and force-rate limit (ServoLoop::shapeForce()) and the
/// HAL's clamp.
///
/// Units: m, N, s; positions in the scene-box frame (docs/architecture.md §3).
/// Thread-safety: thread-bound (the haptic thread); no allocation, no lock.

#include <cmath>

#include <glm/vec3.hpp>

#include "depthtouch/haptics/finger_parameters.h"
#include "depthtouch/haptics/friction.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics {

/// Longest time the command may stay at the device maximum before the finger is let go (on the
/// next update), s: at most 5 updates at the maximum at 1 kHz, whatever the clock's jitter.
inline constexpr double kFingerSaturationTime = 0.003;

/// A command within this share of the device maximum is at it (the force-step limiter and the
/// ramps approach it in small steps; `bench feel` counts time at the maximum the same way).
inline constexpr double kFingerAtMaximum = 1e-3;

/// The alpha-beta filter on the force's offset from the HIP (FingerOutput::smoothOffset()) over
/// noisy depth: the offset's share α of each residual; the trend's is α²/(2 − α) (Benedict and
/// Bordner's pairing for a track with steady motion), 0.1. Where the surface under the goal has
/// fitted clean for kFingerDepthMemory (FingerPlane::smooth), α rises to 1: the offset passes
/// through, and the force follows clean geometry without lag (the clean moving wave's force RMS
/// error at 1 m/s 0.092 → 0.025 N, the paper's method's 0.024). On noisy depth its measurement is
/// the mean of the last two offsets (nothing that alternates at the servo rate passes). The same
/// share bounds a rim's release (FingerOutput::releaseCovered()): a contact that ended unloads by
/// at most α of what is left an update, as the filter takes a surface that falls away.
inline constexpr double kFingerOffsetAlpha = 0.4;

/// \brief What the contact decided in an update, as the output stage needs it.
struct FingerGoal {
    glm::dvec3 proxy{};   ///< The frictionless goal, m (the HIP where there is no contact).
    bool contact = false; ///< The finger is in contact after the update.
    bool trip = false;    ///< Safety tripped (a cut, an occluder, the device maximum).
    bool stepped = false; ///< A step or a re-caught contact: the force ramps in.
    /// Held over a hole (FingerState::OverHole): nothing measured, no noise to filter; its own
    /// unload rate is the force's.
    bool unseen = false;
    /// In contact at the search's start (FingerRenderer::touching(), after a hold over a hole
    /// that ended before the search).
    bool touching = false;
    /// FingerPlane::smooth of the plane under the goal: how clean the surface measured there is
    /// (0..1); the offset filter passes a clean surface's offset through (smoothOffset()).
    double smooth = 0.0;
    /// The HIP's move since the last update, m (box frame): the device's measurement. Its part
    /// along the force's offset compresses the spring at once, past the filter and its bounds
    /// (smoothOffset()), and relaxes it as far as the offset shrank; where it takes the HIP out
    /// (a hand lifting off), the force also follows it out of a ramp (handOverRamp()) and, as far
    /// as it rises, out of a rim's release (releaseCovered()).
    glm::dvec3 hipMove{};
};

/// \brief The force output stage (see the file comment).
class FingerOutput {
public:
    /// \param config the renderer's (validated); \param p its parameter table.
    FingerOutput(const RendererConfig &config, const FingerParameters &p) noexcept
        : config_(config), p_(p), force_(config),
          friction_(config.staticFriction, config.dynamicFriction)
    {
    }

    /// \brief The material step (applyMaterial(), material_field.h) on the friction cone of
    /// filter(): in contact on frames with a material track, its coefficients become the
    /// material's under \a c's goal. \return the stiffness scale there (1 without a track or
    /// contact).
    double material(const HeightField &field, const FingerGoal &c) noexcept;
    /// \brief The proxy the force and the report use, m: \a c's goal through the offset filter
    /// (smoothOffset()), then friction (friction.h) on the filtered proxy where the renderer has
    /// friction or the frames a material track (material()): the cone's in a contact without a
    /// trip, else released; then, in a continuing contact, the hand-over of a ramp
    /// (handOverRamp()), whose proxy the cone holds from then on.
    /// \a t: haptic time, s (the filter's trust in a clean surface grows with it; friction's
    /// static phase).
    glm::dvec3 filter(const glm::dvec3 &hip, const FingerGoal &c, double t) noexcept;
    /// \brief The command of time \a t (s), N: the spring of \a held (m, after friction), the
    /// unload of a contact that ended (releaseCovered(): \a raw the sensor surface at the HIP's
    /// x–y, m, NaN off the grid; \a field for the rim within the fingertip's reach; \a wasInContact
    /// at the update's start), then ForceStage::shape() and the watch of the device maximum.
    /// \return finite, |F| ≤ maxForce.
    glm::dvec3 force(const glm::dvec3 &hip, const glm::dvec3 &held, const FingerGoal &c, double t,
                     double stiffnessScale, double raw, const HeightField &field,
                     bool wasInContact) noexcept;
    /// \return whether the command stayed at the device maximum for kFingerSaturationTime: the
    /// finger is let go on this update. Clears it.
    bool takeLetGo() noexcept
    {
        const bool go = letGoNext_;
        letGoNext_ = false;
        return go;
    }

    /// Forgets the filter, the release, the force history, the saturation watch and friction's
    /// anchor (not the gain).
    void reset() noexcept;
    void restartClock() noexcept { force_.restartClock(); }
    /// The forces only (HapticRenderer::setStiffness()): ignored out of range.
    void setStiffness(double newtonsPerMetre) noexcept
    {
        force_.setStiffness(newtonsPerMetre);
        config_.stiffness = force_.stiffness();
    }
    /// HapticRenderer::setOutputGain(): the caller's factor, 0..1 (NaN ignored).
    void setOutputGain(double gain) noexcept;
    [[nodiscard]] double stiffness() const noexcept { return config_.stiffness; }

private:
    /// Sets \a held (the proxy the force and the report use; m, box frame) to the HIP plus the
    /// filtered offset of \a c's proxy (kFingerOffsetAlpha, raised to 1 by the trust in a clean
    /// surface, trust_) at haptic time \a t (s).
    void smoothOffset(const glm::dvec3 &hip, const FingerGoal &c, double t,
                      glm::dvec3 &held) noexcept;
    /// A ramp in progress (a trip's, a ramped step's) whose command is above the spring force
    /// of \a held (m, after friction) at the spring's last stiffness scale (scale_): the ramp
    /// ends and the filter takes its command as the offset (\a held moves to it, so the force
    /// is continuous), to unload at its bounded rate. \return whether it handed over.
    bool handOverRamp(const glm::dvec3 &hip, const glm::dvec3 &hipMove, glm::dvec3 &held) noexcept;
    /// A trip with the HIP under the surface now measured at its x–y (\a raw, m; a cut that
    /// covered the finger), or a contact (\a wasInContact: at the update's start) that ended
    /// with the HIP so covered (a hold over a hole that ended under what came over it) or with a
    /// surface above the HIP within rimReach (a rim it slid off, also out of a hold over a
    /// hole): \a force (N) becomes the last command, unloaded by unloadForce an update while
    /// the HIP stays covered, from unloadForce doubling to twice it while only the rim is within
    /// rimReach; the HIP's own rise (FingerGoal::hipMove, its part along the force) unloads it as
    /// the spring would besides, within twice unloadForce an update.
    void releaseCovered(const glm::dvec3 &hip, double raw, const HeightField &field,
                        const FingerGoal &c, bool wasInContact, glm::dvec3 &force) noexcept;
    /// \return the stiffness scale the spring uses: \a target (the material's under the goal)
    /// taken at most p_.unloadForce of force an update away in a continuing contact, \a held
    /// − \a hip deep (m).
    double boundScale(double target, const glm::dvec3 &hip, const glm::dvec3 &held,
                      const FingerGoal &c) noexcept;
    /// After kFingerSaturationTime with the command sent, outputGain_ × \a force (N), at the
    /// device maximum in contact, the next update lets the finger go.
    void watchSaturation(const glm::dvec3 &force, double t, bool contact) noexcept;

    RendererConfig config_;
    FingerParameters p_;
    ForceStage force_;
    FrictionCone friction_;    ///< On the filtered proxy; the renderer's goal stays frictionless.
    bool material_ = false;    ///< The frames have a material track (material()).
    glm::dvec3 offset_{};      ///< Filtered offset of the force's proxy from the HIP, m.
    glm::dvec3 offsetTrend_{}; ///< Its change an update (smoothOffset()'s trend), m.
    glm::dvec3 lastOffset_{};  ///< The last update's unfiltered offset, m.
    /// The filter's trust in the surface, 0..1: FingerGoal::smooth's least over the last
    /// kFingerDepthMemory (it falls at once and grows back over that time).
    double trust_ = 0.0;
    double lastT_ = std::nan(""); ///< Haptic time of the last filtered update, s.
    double scale_ = 1.0;          ///< The stiffness scale the spring used last (boundScale()).
    glm::dvec3 release_{};        ///< A force unloading after its contact ended, N.
    double releaseStep_ = 0.0;    ///< release_'s last step, N.
    glm::dvec3 lastChange_{};     ///< The filtered offset's last change, m (smoothOffset()).
    double lastAlong_ = 0.0;      ///< The HIP's last move along the offset, m (smoothOffset()).
    double outputGain_ = 1.0;     ///< setOutputGain(): the caller's factor on the force, 0..1.
    double saturatedSince_ = std::nan(""); ///< Haptic time the command reached the maximum, s.
    bool letGoNext_ = false; ///< The command stayed at the maximum: let go on the next update.
};

} // namespace depthtouch::haptics
