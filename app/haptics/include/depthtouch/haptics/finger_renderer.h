#pragma once
/// \file
/// \brief The fingertip proxy: the modified proxy graph (paper IV) on a surface seen at the scale
/// of a finger, so that sensor noise, depth quantisation and silhouettes feel as they would to a
/// finger rather than as the solver's local optima. The player's and `touch`'s default renderer.
///
/// Why: on real depth video the per-triangle god-object descent (proxy_solver.h) stops in local
/// optima that noise makes (an 8-bit depth step over a 0.1 m box is as tall as a pixel is wide: the
/// surface is a staircase of 45° facets), then jumps by millimetres, which the force-jump safety of
/// paper IV.C reads as a scene cut. A finger touches a patch, not a facet.
///
/// Method, per update (haptic time t, HIP h; docs/architecture.md §3 frame, m):
/// 1. **Finger-scale surface.** At a point q the surface is the least-squares plane through the
///    heights (fix (b): interpolated between frames i and i+1, paper Eq. 1) at the 3×3 points
///    q + (i·r, j·r), i, j ∈ {−1, 0, 1}, r = RendererConfig::fingerRadius (a Prewitt stencil): mean
///    height S(q), kept within r/4 of the nine heights' median, and slope ∇S(q). Noise at pixel
///    scale is averaged; slopes, and so the force's direction, are taken over 2r.
/// 2. **God-object on that surface** (Zilles & Salisbury 1995): the proxy is the HIP projected on
/// the
///    plane at q; q moves to the projection's x–y and the plane is refitted, up to
///    kFingerIterations times, each move at most r (the stencil's reach). In contact q starts at
///    the last proxy, so the proxy slides continuously and holds against a silhouette wall like a
///    god-object; the proxy's height is taken on the current surface, so a rising surface lifts it
///    (fix (a)). The proxy's x–y moves at most as far as the HIP's plus r/4 per update (glide()),
///    so a jump of the optimum (over a silhouette's edge) is a glide, not a step of the force. Held
///    against a wall (the proxy more than r to the side of the HIP), the proxy moves to the surface
///    at the HIP's own x–y when that is nearer: a silhouette's far side is what the camera did not
///    see, not a wall to be pulled back through (a finger that went under a forearm); and a HIP
///    that slipped off a steep side's plane while inside the sensor surface (an object's edge swept
///    over the finger) is held by the surface at its own x–y.
/// 3. **Contact.** Free space is what the camera sees in front of the surface: the HIP is free when
///    it is above the sensor surface at its own x–y (the unseen side of an object is not a wall to
///    be pulled back through) or on the outer side of the proxy's plane. A free HIP comes into
///    contact when it goes under both; if it is then deeper than a tenth of the box depth (4 mm
///    in the default box; at least maxForceStep/k) it came from the side under an object's
///    silhouette, or the surface jumped onto it: it is *behind* the surface (the camera did not
///    see there) and stays free until it is out (paper IV.C's release "may stay inside"). An
///    edge met less deep than that is climbed.
/// 4. **Cuts from the depth itself** (fix (c)): the surface under the proxy, fitted at the same
/// x–y,
///    moved by more than the cut threshold (HeightField::cutThreshold(), a quarter of the box
///    depth) since the last update. HeightField holds the vertices that move more than that in one
///    frame, so only a cut steps; smooth motion is interpolated and moves a thirtieth of it per
///    update. Release: the proxy goes to the HIP; Ramp: the proxy stays on the new surface and the
///    force ramps in (ForceStage::shape()). A smaller step (over maxForceStep/(4k): a loop or seek
///    onto content that moved a little) is no cut: the proxy stays and the change of force is
///    ramped in.
/// 5. **Friction** (RendererConfig::staticFriction, dynamicFriction; friction.h): the proxy of
///    steps 2–4 is the frictionless goal; in contact the friction cone holds the proxy where it
///    was while the tangential force is within μs·Fn and lets it slide at μd·Fn otherwise. The
///    goal, not the held proxy, is what the next update slides on from. A cut or a lost contact
///    lets go. Frames with a material track (DepthFrameView::material) give μs, μd and a
///    stiffness scale per pixel instead, read under the goal each update (material_field.h:
///    bilinear, and Eq. 1 in time).
/// 6. **Force** k·(proxy − HIP) − b·v, shaped by ForceStage::shape() (non-finite → zero, clamp to
/// the
///    device maximum, ramp, slew ≤ maxForceStep per update).
///
/// Cost: 9 height lookups per plane fit, at most 1 + kFingerIterations fits and one raw lookup an
/// update; nothing per frame. Thread-safety: thread-bound (the haptic thread); no allocation.

#include <glm/vec3.hpp>

#include "depthtouch/haptics/friction.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics {

/// Plane refits per update after the first (a converged proxy stops earlier).
inline constexpr int kFingerIterations = 2;
/// Taps farther than this many stencil half-widths from the stencil's median are left out of the
/// plane fit (an object's silhouette beside the finger, a flying pixel): slopes up to about 2
/// (63°) keep every tap.
inline constexpr double kFingerOutlier = 3.0;

/// \brief The least-squares plane through the 3×3 stencil at a point: z = height + slope·(p − at).
struct FingerPlane {
    double x = 0.0;      ///< Stencil centre, m.
    double y = 0.0;
    /// S: mean of the nine heights, kept within r/4 of their median (across a silhouette the
    /// mean of a step is half-way: the finger must neither be inside the object with no force
    /// nor pushed above the backdrop at its foot; the median ignores a lone flying pixel), m.
    double height = 0.0;
    double gx = 0.0;     ///< ∂S/∂x (dimensionless).
    double gy = 0.0;     ///< ∂S/∂y.
};

/// \brief Fits the plane of the 3×3 stencil of half-width \a r (m) at (x, y) on \a field.
/// Points off the grid are clamped to its border. \pre field.valid(), r > 0.
FingerPlane fitFingerPlane(const HeightField &field, double x, double y, double r) noexcept;

/// \brief The closest point of \a plane to \a p (m), and the signed distance of \a p below it
/// (positive: \a p is under the plane), m.
glm::dvec3 projectOnPlane(const FingerPlane &plane, const glm::dvec3 &p, double &below) noexcept;

/// \brief The fingertip-proxy renderer (see the file comment). Method::Finger.
class FingerRenderer final : public HapticRenderer {
public:
    /// \param config validated by the caller; its fix flags are used as given.
    explicit FingerRenderer(const RendererConfig &config) noexcept;

    [[nodiscard]] Result<void> setFrames(const DepthFrameView &current,
                                         const DepthFrameView *next) noexcept override;
    HapticOutput update(const glm::dvec3 &hip, double t) noexcept override;
    void reset(const glm::dvec3 &hip) noexcept override;
    void restartClock() noexcept override;
    [[nodiscard]] Method method() const noexcept override { return Method::Finger; }

    [[nodiscard]] const HeightField &surface() const noexcept { return field_; }
    [[nodiscard]] const RendererConfig &config() const noexcept { return config_; }
    /// \return the stencil half-width in effect, m.
    [[nodiscard]] double radius() const noexcept { return radius_; }

private:
    /// The god-object on the finger-scale surface from q = \a start (x–y): the proxy, the last
    /// plane fitted, S at the start and how far the HIP is under the plane (m).
    glm::dvec3 solve(const glm::dvec3 &hip, double startX, double startY, FingerPlane &plane,
                     double &startHeight, double &below) const noexcept;

    /// The proxy moves (x–y) at most as far as the HIP did plus r/4 per update: where the optimum
    /// jumps (from an object's side onto its top, from a wall to the surface behind it) the proxy
    /// glides there over a few updates instead of stepping the force. \return the proxy, on the
    /// surface; \a plane is refitted where it stops short.
    glm::dvec3 glide(const glm::dvec3 &hip, const glm::dvec3 &proxy,
                     FingerPlane &plane) const noexcept;

    RendererConfig config_;
    HeightField field_;
    ForceStage force_;
    glm::dvec3 lastHip_{};     ///< HIP of the last update, m.
    double radius_ = 0.0;      ///< r, m.
    double captureDepth_ = 0.0; ///< Deepest new contact: max(maxForceStep / k, box depth / 10), m.
    double stepDepth_ =
        0.0; ///< Surface step under the proxy that is ramped in: maxForceStep / (4k), m.
    glm::dvec3 proxy_{};
    bool contact_ = false;
    bool behind_ = false;      ///< HIP under the surface without contact (see the file comment).
    bool enterAnyDepth_ = true; ///< After reset(): a HIP found inside comes into contact.
    double lastX_ = 0.0;      ///< Centre of the last plane fitted in the last update, m.
    double lastY_ = 0.0;
    double lastHeight_ = 0.0; ///< Its S, m.
    FrictionCone friction_;   ///< Friction on the proxy; proxy_ stays the frictionless goal.
};

} // namespace depthtouch::haptics
