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
/// Every length and force threshold below is a row of the parameter table (FingerParameters:
/// captureDepth, stepDepth, pushDepth, the offset filter's filterStep, unloadDepth and unloadForce
/// from the force step ΔF and the stiffness k at construction; glideReach r/4, holdReach r/2,
/// rimReach 3r/4 from the fingertip's radius r; the adaptive contact's rest and slide speeds and
/// smoothing time from r and kFingerDepthMemory; the search resolution ΔF/(1024k)), derived once:
/// a run-time stiffness change changes forces, not when contact exists. The named constants that
/// remain (eight: the depth memory, the offset filter's α, the saturation time and what counts as
/// at the maximum, the hysteresis between solutions, the wall's slope, the plane refits and the
/// stencil's outlier distance) each say their reason where they are declared.
///
/// The map: the model in four parts; the numbered steps below say what each does.
/// - *Surface* (fitFingerPlane() in finger_plane.cpp, sensorHeight(), reachAbove()): the height
///   field at a fingertip's scale: the 3×3 stencil's plane and how well its taps fit a quadric
///   (FingerPlane::smooth), the sensor surface at the HIP's x–y, the highest surface within
///   reach; holes are unknown, not surface (steps 1 and 5 "Holes").
/// - *Proxy* (search(): slide(), capture(), penalty(), wallContact(), holdOverHole()): one goal
///   an update, the god-object on that surface or the penalty of the plane under the HIP, its
///   moves bounded: the glide, the bounded push, a wall's side, a hold over a hole (steps 2–5).
/// - *State* (FingerState; nextState(), letGo(), remember()): one value carried between updates,
///   each transition with one named guard; each state's own data in one member (wall_, hole_).
/// - *Output* (FingerOutput, finger_output.h): the material under the goal, the offset filter (a
///   clean surface passes through; the HIP's own move is the spring's), the ramp's hand-over,
///   friction, the spring at the material's bounded stiffness, the unload of an ended contact,
///   ForceStage's ramp, slew and clamp, the watch of the device maximum (steps 5 "Depth noise",
///   6 and 7).
///
/// Method, per update (haptic time t, HIP h; docs/architecture.md §3 frame, m):
/// 1. **Finger-scale surface.** At a point q the surface is the least-squares plane through the
///    heights (fix (b): interpolated between frames i and i+1, paper Eq. 1) at the 3×3 points
///    q + (i·r, j·r), i, j ∈ {−1, 0, 1}, r = RendererConfig::fingerRadius (a Prewitt stencil): mean
///    height S(q), kept within r/4 of the nine heights' median and no more than r/4 under what
///    was measured at q (its tap and the median of its pixel and the eight around it, where that
///    stands less than a cut over the median: a top narrower than the stencil, a board on edge
///    or a cable, is a minority of the taps), and slope ∇S(q). Noise at pixel scale is
///    averaged; slopes, and so the force's direction, are taken over 2r. Where the nine fit a
///    quadric (RMS residual under r/50, fading out by r/25), S(q) is the quadric's height at q
///    (the 3×3 Savitzky-Golay intercept of order 2): a plane's mean lies under a crest; and its
///    slope is the centre row's and column's difference (the outer rows' differ by the cross
///    curvature), blended in by the same fit quality.
/// 2. **God-object on that surface** (Zilles & Salisbury 1995): the proxy is the HIP projected
///    on the plane at q; q moves to the projection's x–y and the plane is refitted, up to
///    kFingerIterations times, each move at most r (the stencil's reach); a projection left more
///    than r from q and inside the sensor surface is no surface point, and the proxy is the
///    plane's point r from q toward it (keepOnPatch()). In contact q starts at
///    the last proxy, so the proxy slides continuously and holds against a silhouette wall like a
///    god-object; the proxy's height is taken on the current surface, so a rising surface lifts it
///    (fix (a)). The proxy's x–y moves at most as far as the HIP's plus r/4 per update (glide()),
///    so a jump of the optimum (over a silhouette's edge) is a glide, not a step of the force; the
///    glide starts from the last proxy on the surface (not from a pushed proxy, which is off it),
///    and while pushed it does not go straight back the way the last update's went. Held
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
///    edge met less deep than that is climbed. A free HIP whose path since the last update went
///    through an object's side (steeper than kFingerWallSlope) with room for the fingertip in
///    front of it meets that side as a wall instead, where the wall is nearer than the top
///    (finger_wall.cpp): the proxy stays on the side, found again each update along its normal,
///    and turns onto the top over the upper edge. Through a gap narrower than r (between a
///    keyboard's keys, a notch of a ragged silhouette) it was on the surface either side, which
///    a point's free space does not know: it is caught at any depth, its force growing at the
///    bounded push's rate.
/// 4. **Cuts from the depth itself** (fix (c)): most of the patch under the proxy, refitted at the
///    same x–y, moved by more than the cut threshold (HeightField::cutThreshold(), a quarter of the
///    box depth) since the last update: the median of the nine taps' own steps (stencilStep()). An
///    object's silhouette crossing part of the patch steps its plane but is no cut. HeightField
///    holds the vertices that move more than that in one frame, so only a cut steps; smooth motion
///    is interpolated and moves a thirtieth of it per update. The force never points down
///    (pushUp()). Release: the proxy goes to the HIP; Ramp: the proxy stays on the new surface and
///    the force ramps in (ForceStage::shape()). A smaller step (over maxForceStep/(4k): a loop or
///    seek onto content that moved a little) is no cut: the proxy stays and the change of force is
///    ramped in.
/// 5. **Continuity where the finger rests beside, under or in the path of moving objects.**
///    - *No limit cycles*: a descent step (and a glide) is taken only when it brings the surface
///      point nearer the HIP than the last update's (refitted now) by kFingerHysteresis of the
///      glide's length, and the surface at the HIP's own x–y replaces a proxy held to the side
///      only when nearer by the same share: beside an object's edge, two solutions cannot take
///      turns from one update to the next (before: a 500 Hz buzz pressing beside a typing hand).
///    - *Bounded push*: the HIP's depth under the proxy grows by at most the HIP's motion into
///      the surface (along the offset; once pushed, against the push) plus maxForceStep/(16k)
///      per update (a finger swiped onto a ledge is not pressed into it by its motion along
///      it), so a surface that sweeps under a resting finger (an
///      object's side, a turning head) pushes it out at a bounded rate, and a hand that yields
///      rises onto it instead of being thrown out at full force or left behind it (a yielding
///      hand's own motion does not speed the push up). While bounded, the push's direction
///      turns toward each update's candidate by at most that rate across:
///      under an occluder two far solutions took turns and the force's direction alternated at the
///      servo rate (a 500 Hz limit cycle). So does a proxy held to the side of the HIP when the
///      surface above the HIP replaces it (step 2): beside flickering pixels the two took turns,
///      and each switch turned the force at once.
///    - *Depth noise*: the proxy's offset from the HIP that the force and the report use passes
///      an alpha-beta filter (FingerOutput, finger_output.h; the search keeps the unfiltered
///      goal), each update's move no longer than the unfiltered offset's nor than filterStep
///      (a switch of the solution turns the force over a few updates): on noisy depth at 50 cm/s
///      the taps cross pixels every update and the plane tilted and shifted anew each time, turning
///      the force back and forth by 0.05-0.2 N at the servo rate (RendererConfig::smoothOffset
///      turns it off: `bench feel`'s `finger-unfiltered`). Its measurement is the mean of the
///      last two offsets, so what alternates at the servo rate is not passed. Where it lags, it
///      catches up by a share of the gap; it unloads by at most maxForceStep/8 an update, a hold
///      over a hole too, and turns back against its last change by at most filterStep an update.
///      Those bounds are for what the surface does: the HIP's own move along the offset (the mean
///      of its last two) is the spring's, and passes at once, a move out only as far as the
///      offset shrank (a goal that moved with the hand, a bounded push, is not relaxed by it; a
///      finger lifting off is unloaded as it rises, and leaves a ramp to the filter; filtered, it
///      was most of the energy put into the hand beyond the ideal penalty's). A contact caught
///      while an ended one's force is still unloading starts the filter from that force (a let-go
///      at the device maximum). A material boundary under a pressed finger changes the stiffness
///      scale by at most maxForceStep/8 of force an update. Where the surface under the goal has
///      fitted clean (FingerPlane::smooth) for kFingerDepthMemory, there is no noise to filter and
///      the offset passes through: on clean geometry the force follows the surface without the
///      filter's lag.
///    - *Steps*: a step of the surface under the stencil (over stepDepth, under the cut) is
///      ramped in over the ramp time only as a step up from a force of a step's size or more;
///      from less, the bounded push grows it, and a step down is unloaded by the filter. A ramp
///      holding more than the surface gives with the finger under stepDepth in hands its force
///      to the filter (handOverRamp()).
///    - *Within reach*: in contact, a HIP above the sensor surface at its own x–y is not free
///      while the surface within r/2 of it is still above it (a few pixels read far back under
///      the fingertip): the contact goes on while the HIP is under the stencil's plane and does
///      not press on, deeper by its own motion than by the surface's (withinReach(),
///      pressesOn()). A contact that ends with a surface above the HIP within 3r/4 (a rim the
///      fingertip slides off) unloads its last force from maxForceStep/8, the step doubling to
///      maxForceStep/4, and by the spring's share of the HIP's own rise (within maxForceStep/4),
///      never by more than the offset filter's share of what is left (a light contact rolls off
///      over a few updates, not in one step), while that surface stays within 3r/4; then it is 0
///      (releaseCovered()).
///    - *Caught again*: a finger let go behind an occluder (or by a cut) is caught by the surface
///      it was held on as soon as that surface is within its held depth (plus the ramped step)
///      again, e.g. when the occluder leaves; before, it stayed free until lifted out. A finger
///      caught (or a new contact made) deeper than the HIP moved plus pushDepth gets its force
///      at the bounded push's rate (limitPush(), maxForceStep/16 an update), not in steps of
///      maxForceStep: the surface came back over the finger, as an arriving surface does.
///    - *Saturation*: a command at the device maximum (within kFingerAtMaximum) for
///      kFingerSaturationTime lets the finger go (whatever Reengage says): the device cannot push
///      it out, and a force held at the maximum is what a user must never feel for long.
///    - *Holes* (DepthFrameView::holeBelow; docs/architecture.md §3 "Holes"): HeightField puts a
///      hole's vertex 1 m under the box, so a hole is free space and its border a cliff; the
///      stencil's median ignores a minority of hole taps. A hole that opens under a pressed
///      finger (the shadow band a structured-light sensor casts beside an occluder, a dropout)
///      is the surface unseen, as under an occluder, not the surface gone: the finger is held on
///      it (the proxy keeps its height and its offset from the HIP, the depth no more than it
///      was, its direction kept while the HIP is deeper than that) for kFingerDepthMemory while it
///      stays within r of where the hole opened and under the proxy's height, then its force
///      unloads by maxForceStep/8 an update along its last direction; measured again a cut off the
///      held surface, the finger is free and caught by what is there (finger_hole.cpp), its force
///      unloading by maxForceStep/8 an update while that covers it, as after a covering trip
///      (releaseCovered()). A free
///      finger that meets a hole finds free space.
/// 5b. **The penalty contact** (RendererConfig::fingerContact; GodObject, steps 2–5, by
///    default): with FingerContact::Penalty the contact is the penalty of the plane under the
///    HIP's own x–y (finger_contact.cpp): the proxy is the HIP's projection on it, moving at most
///    the HIP's motion plus r/4 an update, a function of the HIP and the time alone, so beside a
///    moving edge no two solutions can take turns. It keeps steps 3–5's capture depth, cuts,
///    bounded push and saturation, and is free above the sensor surface at the HIP's own x–y
///    where that was measured. FingerContact::Adaptive takes it while the HIP rests (its x–y
///    speed, smoothed over FingerParameters::speedTime, under restSpeed, until it passes
///    slideSpeed: a press, a hold, a tap) and the god-object while it slides; a switch
///    that moves the proxy by more than a ramped step ramps the force in (ForceStage::shape()).
///    At a cut the penalty's proxy is re-seated on the new surface at once, as the god-object's
///    is (the force stage ramps the change in or the finger is let go, as Reengage says).
/// 6. **Friction** (RendererConfig::staticFriction, dynamicFriction; friction.h; applied by
///    FingerOutput::filter(), the ball renderer's too): the proxy of
///    steps 2–4 is the frictionless goal; in contact the friction cone holds the proxy where it
///    was while the tangential force is within μs·Fn and lets it slide at μd·Fn otherwise. The
///    goal, not the held proxy, is what the next update slides on from. A cut or a lost contact
///    lets go. Frames with a material track (DepthFrameView::material) give μs, μd and a
///    stiffness scale per pixel instead, read under the goal each update (material_field.h:
///    bilinear, and Eq. 1 in time).
/// 7. **Force** k·(proxy − HIP) − b·v, shaped by ForceStage::shape() (non-finite → zero, clamp to
/// the
///    device maximum, ramp, slew ≤ maxForceStep per update).
///
/// Cost: 9 height lookups per plane fit (9 more where the centre's tap stands over the plane), at
/// most 2 + kFingerIterations fits (3 + 2·kFingerIterations beside a wall) and one raw lookup an
/// update sliding (17 more where the raw lookup is under the HIP in contact: withinReach(); 9 more
/// where the descent stopped more than r short of the projection: keepOnPatch()), two fits and one
/// raw lookup resting; nothing per frame.
///
/// Thread-safety: thread-bound (the haptic thread); no allocation.

#include <cmath>
#include <cstdint>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "depthtouch/haptics/finger_output.h"
#include "depthtouch/haptics/finger_parameters.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics {

/// The hysteresis between two solutions of the proxy, as a share of the distance at stake: a
/// glide (a move of the proxy cut short at r/4 plus the HIP's own move) is taken only when it
/// brings the surface point nearer the HIP by this share of its length, and the surface at the
/// HIP's own x–y replaces a proxy held more than r to the side only when it is nearer the HIP by
/// this share of the held proxy's distance. Beside an edge that moves a little each update, two
/// far solutions cannot take turns.
inline constexpr double kFingerHysteresis = 0.02;
/// An object's side, met as a wall (finger_wall.cpp), is steeper than this slope: the height
/// difference over ±r, divided by 2r (45°).
inline constexpr double kFingerWallSlope = 1.0;
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
    /// nor pushed above the backdrop at its foot; the median ignores a lone flying pixel), and
    /// no more than r/4 under what was measured at the centre (its tap and the median of its
    /// pixel and the eight around it), unless that stands a cut or more over the median (an
    /// object over the finger): on a top narrower than the stencil the median is beside it, m.
    double height = 0.0;
    double gx = 0.0;     ///< ∂S/∂x (dimensionless).
    double gy = 0.0;     ///< ∂S/∂y.
    /// The nine interpolated heights, row-major from (x − r, y − r) (hole taps as HeightField
    /// gives them, 1 m under the box), m.
    double taps[9] = {};
    /// Whether the taps kept by the outlier rule span a plane; if not, the plane is flat at their
    /// median.
    bool spanned = true;
    /// How well the nine taps fit a quadric, 0..1: 1 where their RMS residual is under r/50
    /// (smooth geometry at the fingertip's scale), falling to 0 at r/25 (an edge, a step, noise);
    /// the weight of the curvature correction and of the centre's slope (finger_plane.cpp).
    double smooth = 0.0;
};

/// \brief Fits the plane of the 3×3 stencil of half-width \a r (m) at (x, y) on \a field.
/// Points off the grid are clamped to its border. \pre field.valid(), r > 0.
FingerPlane fitFingerPlane(const HeightField &field, double x, double y, double r) noexcept;

/// \brief The closest point of \a plane to \a p (m), and the signed distance of \a p below it
/// (positive: \a p is under the plane), m.
glm::dvec3 projectOnPlane(const FingerPlane &plane, const glm::dvec3 &p, double &below) noexcept;

/// \brief The fingertip's contact state, one value carried from update to update
/// (FingerRenderer::state()). reset() makes it Free. Each transition has one named guard,
/// checked in update() in this order; a transition not listed keeps the state:
///
///                through a side            corner
///         ┌─────────────────────► OnWall ──────────┐
///         │                                        ▼
///  reset► Free ────────── caught ──────────────► Touching ─── hole ───► OverHole
///         ▲  │ ◄──────────── out ─────────────────── │  ▲ ◄── measured ──── │
///     out │  │ deep                             trip │  │                   │ cut,
///         │  ▼                                       ▼  │ caught again      ▼ unloaded
///         └─ Behind ◄────────────────────────────────┘  │                  Free
///              └────────────────────────────────────────┘
///
/// (OnWall and OverHole also trip to Behind, and OnWall goes out to Free: the list below has
/// every arrow.)
///
/// The transitions, from → to: *guard* (where it is checked):
/// - Touching → OverHole: *hole*, the spot under the pressed finger turned to a hole
///   (holdOverHole()).
/// - OverHole → Touching: *measured*, the spot is measured again: the surface it was held on.
/// - OverHole → Free: *cut*, measured again a cut off the held surface; *unloaded*, the hold's
///   force is spent.
/// - Free → Touching: *caught*, under the surface no deeper than captureDepth (enter()), or at
///   any depth through a gap narrower than the fingertip (roomBefore(): on the surface either
///   side of it).
/// - Free → Behind: *deep*, under it deeper than that: it came from the side, or the surface
///   jumped onto it (enter()).
/// - Behind → Touching: *caught again*, the surface it was held on is within heldDepth +
///   stepDepth (enter()).
/// - Free → OnWall: *through a side*, the path since the last update crossed a side steeper than
///   kFingerWallSlope with room for the fingertip in front of it (enterWall(), roomBefore()).
/// - OnWall → Touching: *corner*, the top is nearer than the side by r (wallContact()).
/// - Touching, OnWall → Free: *out*, above the sensor surface at its x–y with nothing within
///   holdReach above it (withinReach()), or out from under the stencil's plane (slide()).
/// - Behind → Free: *out*, above the sensor surface at its x–y.
/// - Touching, OnWall, OverHole → Behind: *trip*, a cut with Reengage::Release, an occluder over
///   the finger, or the device maximum held for kFingerSaturationTime.
enum class FingerState : std::uint8_t {
    Free,     ///< No contact: the HIP is in front of what the camera saw.
    Behind,   ///< Under the surface without contact: came from the side, or was let go there.
    Touching, ///< On the finger-scale surface: the god-object's or the penalty's contact.
    OnWall,   ///< On an object's side, met through it (finger_wall.cpp).
    OverHole, ///< Pressed where a hole opened: held on the unseen surface (finger_hole.cpp).
};

/// \return \a state's name as logs and `bench feel --dump` write it: "free", "behind",
/// "touching", "on-wall" or "over-hole".
[[nodiscard]] constexpr const char *fingerStateName(FingerState state) noexcept
{
    switch (state) {
    case FingerState::Free:
        return "free";
    case FingerState::Behind:
        return "behind";
    case FingerState::Touching:
        return "touching";
    case FingerState::OnWall:
        return "on-wall";
    case FingerState::OverHole:
        return "over-hole";
    }
    return "?";
}

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
    /// The forces only: the depths of the parameter table keep the stiffness of construction.
    void setStiffness(double newtonsPerMetre) noexcept override;
    /// The saturation watch (kFingerSaturationTime) compares gain × |F| with the device maximum.
    void setOutputGain(double gain) noexcept override { output_.setOutputGain(gain); }
    [[nodiscard]] Method method() const noexcept override { return Method::Finger; }

    [[nodiscard]] const HeightField &surface() const noexcept { return field_; }
    [[nodiscard]] const HeightField *heightField() const noexcept override { return &field_; }
    [[nodiscard]] const RendererConfig &config() const noexcept { return config_; }
    /// \return the stencil half-width in effect, m.
    [[nodiscard]] double radius() const noexcept { return p_.radius; }
    [[nodiscard]] double fingertipRadius() const noexcept override { return p_.radius; }
    /// \return the contact state after the last update (FingerState).
    [[nodiscard]] FingerState state() const noexcept { return state_; }
    [[nodiscard]] const char *contactStateName() const noexcept override
    {
        return fingerStateName(state_);
    }
    /// \return the parameter table in effect.
    [[nodiscard]] const FingerParameters &parameters() const noexcept { return p_; }

private:
    /// One update's proxy before friction and force: what the output stage takes (FingerGoal:
    /// proxy, contact, trip, stepped, unseen, touching) and what the search keeps.
    struct Candidate : FingerGoal {
        FingerPlane plane{};    ///< The last plane fitted.
        double below = 0.0;     ///< How far the HIP is under the plane, m.
        bool letGo = false;     ///< Let go whatever Reengage says (occluder, saturation).
        bool saturated = false; ///< Let go at the device maximum.
        /// A proxy held to the side was replaced by the surface at the HIP's own x–y: its
        /// direction from the HIP turns at a bounded rate (limitPush()).
        bool switched = false;
        /// limitPush() bounded the proxy: where it was found, on the surface (m).
        bool bounded = false;
        glm::dvec3 found{};
        glm::dvec2 glide{}; ///< glide()'s direction (unit), or zero.
        /// The next state's flags while the update decides (nextState()): on an object's side,
        /// and under the surface without contact. They start as the state at the update's start.
        bool wall = false;
        bool behind = false;
        /// limitPush() held the proxy at its bound this update (the next update is pushed_).
        bool pushing = false;
        /// enterWall() found the HIP's path through a gap narrower than the fingertip: it was on
        /// the surface either side, not in free space in front of a wall (roomBefore()).
        bool throughGap = false;
    };
    /// What FingerState::OverHole holds (holdOverHole(), finger_hole.cpp).
    struct HoleHold {
        double since = 0.0; ///< Haptic time the hole opened, s.
        glm::dvec2 at{};    ///< The HIP's x–y then, m.
        double depth = 0.0; ///< |proxy − HIP| then: the held depth's bound, m.
        glm::dvec3 dir{};   ///< The held force's direction (unit), HIP to proxy.
    };
    /// What FingerState::OnWall holds (enterWall(), wallContact(), finger_wall.cpp).
    struct WallHold {
        glm::dvec2 normal{}; ///< The side's outward horizontal normal (unit).
        double depth = 0.0;  ///< The HIP's depth behind the side along it, last update, m.
    };
    /// \return whether the finger is in contact at the update's start (Touching, OnWall or
    /// OverHole; holdOverHole() may end it before the search).
    [[nodiscard]] bool touching() const noexcept
    {
        return state_ == FingerState::Touching || state_ == FingerState::OnWall ||
               state_ == FingerState::OverHole;
    }
    /// \return the state the update \a c leaves: its contact, on a wall, held over a hole,
    /// behind the surface or free.
    [[nodiscard]] static FingerState nextState(const Candidate &c) noexcept;
    /// \return whether a switch between the contacts moves the proxy by more than stepDepth
    /// (the candidate \a c against the last update's proxy): only then is it ramped in.
    [[nodiscard]] bool switchSteps(const Candidate &c) const noexcept;

    /// Steps 1–5 of the file comment: this update's contact in \a c (the hold over a hole, the
    /// penalty while resting, out of reach, the wall, the slide or a new capture), and whether a
    /// switch or a step of the surface ramps the force in. \a raw: the sensor surface at the HIP's
    /// x–y (sensorHeight(), m; NaN off the grid); \a over: the HIP is over the grid.
    void search(const glm::dvec3 &hip, double raw, bool over, double t, Candidate &c) noexcept;
    /// The trip guards of FingerState: the device maximum held too long lets the finger go; a
    /// trip with Reengage::Release (or a let-go) leaves it behind the surface; no contact puts the
    /// proxy on the HIP.
    void letGo(const glm::dvec3 &hip, Candidate &c) noexcept;
    /// What the next update starts from: the state, the proxy, the last plane and depth.
    void remember(const glm::dvec3 &hip, const Candidate &c) noexcept;
    /// In contact: slide on from the last proxy (steps 2 and 4 of the file comment).
    /// \a raw: the sensor surface at the HIP's own x–y, m (over the HIP: slide() runs inside).
    void slide(const glm::dvec3 &hip, double raw, Candidate &c) const noexcept;
    /// The proxy \a c from slide()'s descent kept on the patch its plane was fitted to: where it
    /// lies more than r from the plane's centre (the plane extrapolated) and inside the sensor
    /// surface at its own x–y (the median of its pixel and the eight around it, by more than r/4
    /// and at most a cut), it is the plane's point r from the centre toward it.
    void keepOnPatch(Candidate &c) const noexcept;
    /// Not in contact: a new contact from the HIP, or a finger behind the surface caught again.
    void capture(const glm::dvec3 &hip, Candidate &c) noexcept;
    /// The penalty contact (finger_contact.cpp): the whole update's contact from the plane under
    /// the HIP's own x–y; \a raw: sensorHeight() there, m. \pre the HIP is over the grid.
    void penalty(const glm::dvec3 &hip, double raw, Candidate &c) noexcept;
    /// \return the sensor surface at the HIP's own x–y, m (above it is free space): the height
    /// there, or, in contact where that is under the HIP, the median of the heights at the HIP
    /// and one pixel around it (one pixel read far back is not free space under a pressed
    /// finger). \pre the HIP is over the grid.
    [[nodiscard]] double sensorHeight(const glm::dvec3 &hip) const noexcept;
    /// \return whether a sliding contact goes on with the HIP above the sensor surface at its
    /// own x–y: some surface within half the finger radius of the HIP's x–y
    /// (haptics::reachHeight(), the disc bench feel judges phantom force by, halved) is above the
    /// HIP; slide() then ends the contact where the HIP leaves the stencil's plane, and update()
    /// where the HIP presses on (pressesOn()). False where \a raw (sensorHeight(), m) is NaN (off
    /// the grid) or a hole, out of contact, on a wall, or without fix (a).
    [[nodiscard]] bool withinReach(const glm::dvec3 &hip, double raw) const noexcept;
    /// \return whether the contact's depth (|proxy − HIP|, m) grew since last update more by the
    /// HIP's own motion along the contact normal than by the surface's: a contact held by its
    /// reach alone ends where the HIP presses on (a finger pressed down beside a rim), not where
    /// the plane's noise deepens it under a resting finger.
    [[nodiscard]] bool pressesOn(const glm::dvec3 &hip, const glm::dvec3 &proxy) const noexcept;
    /// \return the highest measured surface (m, box frame) at the HIP's x–y and on rings of
    /// \a radius/2 and \a radius (m) around it (reachHeight(), feel.h); NaN where none is.
    [[nodiscard]] double reachAbove(const glm::dvec3 &hip, double radius) const noexcept;
    /// Whether a finger not in contact, \a below (m) under the surface, comes into contact: a new
    /// contact no deeper than the capture depth, or a finger let go caught again by the surface it
    /// was held on; else it is behind the surface (behind_ set).
    void enter(double below, Candidate &c) noexcept;
    /// \return whether this update (HIP \a hip, time \a t) takes the penalty contact: always for
    /// FingerContact::Penalty, never for GodObject; for Adaptive while the HIP rests (its x–y
    /// speed, smoothed over FingerParameters::speedTime, under restSpeed; back to the god-object
    /// over slideSpeed).
    bool restingContact(const glm::dvec3 &hip, double t) noexcept;
    /// The hold over a hole that opened under the pressed finger (finger_hole.cpp): \a raw
    /// (sensorHeight(), m, NaN off the grid) was not measured. \return whether this update's
    /// contact is that hold (\a c set: the proxy, its depth, the last plane); false, and the hold
    /// forgotten, where the spot was measured, the finger was free or on a wall, or the hold has
    /// unloaded.
    bool holdOverHole(const glm::dvec3 &hip, double raw, double t, Candidate &c) noexcept;
    /// Never a force with a downward part: a proxy under the HIP becomes the HIP's projection on
    /// its plane (along the plane's normal, z up), or with the HIP above that plane the sensor
    /// surface \a raw (m) straight above the HIP.
    void pushUp(const glm::dvec3 &hip, double raw, Candidate &c) const noexcept;
    /// The contact straight up from the HIP: the proxy on the sensor surface \a raw (m) at the
    /// HIP's own x–y, the plane fitted there (a finger under the surface whose stencil's median
    /// lies beside an object's silhouette).
    void straightUp(const glm::dvec3 &hip, double raw, Candidate &c) const noexcept;
    /// \return the HIP's own motion since the last update plus pushDepth, m: how far a bounded
    /// push's direction turns across an update (limitPush()), and the most a wall's depth
    /// shrinks by; the depths themselves grow by the HIP's motion into the surface only.
    [[nodiscard]] double pushReach(const glm::dvec3 &hip) const noexcept;
    /// \return how far the stencil \a now (refitted where the last update's plane was) moved
    /// since that update: the median over its taps of |now − then|, m; a tap that is or was a hole
    /// or on a hole's cliff (HeightField::besideHole()) moved 0 (a hole opening is no cut). A cut
    /// moves the whole patch; an object's silhouette passing over the finger moves some of the
    /// taps only, and is no cut.
    [[nodiscard]] double stencilStep(const FingerPlane &now) const noexcept;
    /// \return whether \a p (m) is in free space: off the grid or above the surface at its x–y.
    [[nodiscard]] bool freeAt(const glm::dvec3 &p) const noexcept;
    /// The outward horizontal normal \a n of an object's side at \a at (m): the direction of
    /// steepest descent of the heights ±r around it (read once, where the HIP came through).
    /// \return false where the surface there is no steeper than kFingerWallSlope (no wall).
    bool wallNormal(const glm::dvec3 &at, glm::dvec2 &n) const noexcept;
    /// A free HIP that came under the surface through an object's side (finger_wall.cpp): \return
    /// whether it did, with \a c the wall contact (wall_ set); false for a path through the top or
    /// a HIP that was not free at the last update.
    bool enterWall(const glm::dvec3 &hip, Candidate &c) noexcept;
    /// \return whether a fingertip fits in front of a side crossed at \a out (m) whose outward
    /// normal is \a n (unit): no surface (the median of a pixel and the eight around it, not a
    /// hole) stands at out's height or higher within r of it along n. False: the path came
    /// through a gap narrower than the fingertip; the side is no wall (enterWall() sets
    /// Candidate::throughGap) and the finger is caught at any depth (capture()).
    [[nodiscard]] bool roomBefore(const glm::dvec3 &out, const glm::dvec2 &n) const noexcept;
    /// On a wall: the proxy HIP + s·n on the object's side found again along its normal (s moves
    /// at a bounded rate), turning onto the top (\a raw, m) over the upper edge, or the ordinary
    /// contact once the top is nearer than the side by r.
    void wallContact(const glm::dvec3 &hip, double raw, Candidate &c) noexcept;
    /// Bounds the growth of the HIP's depth under the proxy (a surface sweeping in).
    /// While bounded, the push's direction (pushDir_) turns toward the candidate's by at most
    /// pushReach() across an update; the depth is the candidate's, up to the bound.
    void limitPush(const glm::dvec3 &hip, Candidate &c) noexcept;

    /// The god-object on the finger-scale surface from q = (\a startX, \a startY) (m): the proxy
    /// (m), the last plane fitted (\a plane), the first one, at q (\a start), and how far the HIP
    /// is under \a plane (\a below, m).
    glm::dvec3 solve(const glm::dvec3 &hip, double startX, double startY, FingerPlane &plane,
                     FingerPlane &start, double &below) const noexcept;

    /// The proxy moves (x–y) at most as far as the HIP did plus r/4 per update: where the optimum
    /// jumps (from an object's side onto its top, from a wall to the surface behind it) the proxy
    /// glides there over a few updates instead of stepping the force. \return the proxy, on the
    /// surface; \a plane is refitted where it stops short, and \a moved is how far it went then
    /// (m; 0 when the optimum was within reach). It glides from surfaceProxy_; while pushed, a
    /// glide back against the last one (\a dir then keeps lastGlide_) stays where it starts.
    /// \a dir: the glide's x–y direction (unit), zero when within reach.
    glm::dvec3 glide(const glm::dvec3 &hip, const glm::dvec3 &proxy, FingerPlane &plane,
                     double &moved, glm::dvec2 &dir) const noexcept;

    RendererConfig config_;
    HeightField field_;
    FingerParameters p_; ///< The parameter table (fingerParameters()), fixed at construction.
    /// The force output stage: filter, unload, spring, ramp, slew, clamp, saturation watch.
    FingerOutput output_;
    glm::dvec3 lastHip_{}; ///< HIP of the last update, m.
    glm::dvec3 proxy_{};
    /// The last update's proxy on the surface: proxy_, or where limitPush() found it before
    /// bounding it (m). The glide starts from it.
    glm::dvec3 surfaceProxy_{};
    glm::dvec2 lastGlide_{};                ///< The last update's glide direction (unit), or zero.
    FingerState state_ = FingerState::Free; ///< The contact state (FingerState).
    WallHold wall_;                         ///< FingerState::OnWall's side.
    bool enterAnyDepth_ = true; ///< After reset(): a HIP found inside comes into contact.
    /// The last plane fitted in the last update (a cut moves most of its taps, see stencilStep()).
    FingerPlane lastPlane_;
    double lastDepth_ = 0.0; ///< |proxy − HIP| of the last update in contact, else 0, m.
    /// limitPush() bounded the last update's proxy, in contact (Candidate::pushing, remembered).
    bool pushed_ = false;
    glm::dvec3 pushDir_{};   ///< The bounded push's direction from the HIP (unit).
    double heldDepth_ = 0.0; ///< The held depth when an occluder or a cut let the finger go, m.
    HoleHold hole_;          ///< FingerState::OverHole's hold.
    double lastT_ = std::nan(""); ///< Haptic time of the last update, s.
    double speed_ = 0.0;          ///< The HIP's x–y speed, smoothed, m/s.
    bool resting_ = false;        ///< FingerContact::Adaptive: the penalty contact is in use.
};

} // namespace depthtouch::haptics
