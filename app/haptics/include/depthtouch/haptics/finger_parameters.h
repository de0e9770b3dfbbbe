#pragma once
/// \file
/// \brief The fingertip renderer's parameter table (finger_renderer.h): every length and force
/// threshold of the model, derived once from the physical parameters it is given.
/// Thread-safety: plain values; fingerParameters() is reentrant.

#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics {

/// How long the renderer goes on believing what the depth showed, s: three frames at 30 fps (a
/// sensor's dropout or noise shows in a frame or two). A pressed finger whose spot turned to a
/// hole is held on the surface it pressed for this long (finger_hole.cpp); the offset filter
/// passes the offset through only where the surface has fitted clean this long
/// (FingerOutput::smoothOffset()).
inline constexpr double kFingerDepthMemory = 0.1;

/// \brief The fingertip model's parameter table: the physical parameters it is given and every
/// length and force threshold of the renderer, derived from them once, at construction
/// (fingerParameters()). A run-time stiffness change (HapticRenderer::setStiffness(), a viewer's
/// remote) changes the forces, not these: when a finger is in contact, behind the surface or
/// pushed is a matter of geometry.
///
/// Units: m, N, N/m; per update means per servo tick (the renderer does not know the servo rate:
/// the rates below are per update, as the force stage's step limit is).
struct FingerParameters {
    /// \name The physical parameters (RendererConfig)
    ///@{
    double radius = 0.0;       ///< r: the fingertip's radius, the stencil's half-width, m.
    double stiffness = 0.0;    ///< k at construction, N/m.
    double maxForceStep = 0.0; ///< ΔF: the most the force may change in an update, N.
    double boxDepth = 0.0;     ///< D: the scene box's depth, m.
    ///@}
    /// \name Depths, from the force step: ΔF/k is how deep a surface must move under a finger to
    /// step its force by ΔF
    ///@{
    /// The deepest a free finger found under the surface is taken into contact: max(ΔF/k, D/10).
    /// Deeper, it came from the side under an object (or the surface jumped onto it) and is behind
    /// it; within a tenth of the box, a surface's own relief is climbed.
    double captureDepth = 0.0;
    /// A step of the surface under the finger that is ramped in rather than taken at once, and
    /// a switch between solutions that counts as one: ΔF/(4k), a quarter of a force step.
    double stepDepth = 0.0;
    /// The bounded push: how much deeper the HIP may get under the proxy in an update beyond its
    /// own motion into the surface (a surface sweeping under a resting finger): ΔF/(16k), 0.16 mm
    /// (16 cm/s at 1 kHz) at the defaults.
    double pushDepth = 0.0;
    /// The most the offset filter moves the force's offset in an update, and the most it turns
    /// it back against its last change (FingerOutput::smoothOffset()): 3·pushDepth, 3ΔF/(16k),
    /// 0.375 N of force at the defaults. Three bounded pushes: a switch of the solution turns the
    /// force over a few updates, and a surface that sweeps under a resting finger at the bounded
    /// push's rate is followed with room to spare.
    double filterStep = 0.0;
    /// The most a force unloads by in an update where the surface fell away or is unseen (the
    /// offset filter, a hold over a hole): ΔF/(8k), an eighth of a force step; unloadForce in N.
    double unloadDepth = 0.0;
    /// ΔF/8, N: the release's first step (a contact ending at a rim, a cut covering the finger).
    double unloadForce = 0.0;
    ///@}
    /// \name Reaches, from the fingertip's radius
    ///@{
    /// How far the proxy may glide beyond the HIP's own motion in an update: r/4 (a jump of the
    /// optimum over a silhouette's edge is followed in four updates, not in one step).
    double glideReach = 0.0;
    /// A contact goes on while some surface within r/2 of the HIP is above it (withinReach()):
    /// the half of the fingertip nearest its centre.
    double holdReach = 0.0;
    /// A contact that ends with a surface above the HIP within 3r/4 rolls off a rim: its force
    /// unloads (releaseCovered()).
    double rimReach = 0.0;
    ///@}
    /// \name Speeds of FingerContact::Adaptive, from the radius and the depth memory
    ///@{
    /// The HIP rests below this x–y speed: r/kFingerDepthMemory, the finger moves less than its
    /// radius over the frames the renderer believes (the patch under it is the one they
    /// measured), 1.5 cm/s at the defaults. m/s.
    double restSpeed = 0.0;
    /// A resting HIP slides above twice restSpeed: a hand's jitter about the rest speed does not
    /// switch the contact back and forth. m/s.
    double slideSpeed = 0.0;
    /// The x–y speed is smoothed over the time a finger at restSpeed takes to move a glide reach
    /// (glideReach/restSpeed, a quarter of kFingerDepthMemory): shorter, the HIP's own jitter
    /// would read as motion. s.
    double speedTime = 0.0;
    ///@}
    /// The resolution a proxy is searched to: a wall's crossing (finger_wall.cpp: as many
    /// bisections as halve the searched length under it) and the ball's proxy solve (a step
    /// under it has converged; ball_renderer.h): pushDepth/64, ΔF/(1024k), a force error under
    /// ΔF/1024 (2 mN at the defaults). m.
    double searchResolution = 0.0;
};

/// \return the parameter table of \a config (RendererConfig::fingerRadiusInBox(), stiffness,
/// maxForceStep, box depth).
FingerParameters fingerParameters(const RendererConfig &config) noexcept;

} // namespace depthtouch::haptics
