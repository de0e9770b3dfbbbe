#pragma once
/// \file
/// \brief Haptic renderers for depth video: the modified proxy graph (paper IV) and, for comparison
/// only, its baselines (`proxy-graph` = the same class with fixes a–c off, `mesh-bvh` in
/// mesh_bvh.h).
///
/// One update per haptic tick: `update(hip, t)` → proxy, force. Units (docs/architecture.md §3): m,
/// s, N, N/m, N·s/m; positions in the scene-box frame (x right, y up, z toward the viewer).
/// Thread-safety of every renderer: thread-bound (the haptic thread). update() and setFrames() are
/// noexcept and never allocate; all memory is taken at construction.

#include <cstdint>
#include <memory>
#include <string_view>

#include <glm/vec3.hpp>

#include "depthtouch/haptics/collision.h"
#include "depthtouch/haptics/depth_frame.h"
#include "depthtouch/haptics/friction.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/haptics/proxy_solver.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/scene/stiffness.h"

namespace depthtouch::haptics {

/// \brief Which renderer (the `--method` option).
enum class Method : std::uint8_t {
    Modified,   ///< Modified proxy graph, fixes (a)(b)(c) on: the paper's renderer (section IV).
    ProxyGraph, ///< Walker & Salisbury on sample-and-hold frames: fixes off (baseline).
    MeshBvh,    ///< Full triangle mesh + AABB tree rebuilt for every frame (baseline).
    Finger,     ///< Fingertip proxy on the finger-scale surface (finger_renderer.h): the default.
    Ball, ///< The fingertip as a ball: one proxy solve on the swept surface (ball_renderer.h).
};

/// \return "modified", "proxy-graph", "mesh-bvh" or "finger".
const char *methodName(Method method) noexcept;
/// \brief Parses a methodName(). \return Errc::InvalidArgument for any other text.
Result<Method> parseMethod(std::string_view text) noexcept;

/// \brief How the fingertip renderer (Method::Finger) meets its finger-scale surface.
enum class FingerContact : std::uint8_t {
    /// The penalty of the patch under the HIP's own x–y: the force is k times the HIP's depth
    /// along the normal of the finger-scale plane there, a continuous function of the HIP and the
    /// time (finger_contact.cpp). No search, so no two solutions can take turns.
    Penalty,
    /// The god-object on the finger-scale surface: the proxy slides on from where it was
    /// (finger_renderer.h, steps 2–5), held against a silhouette's wall.
    GodObject,
    /// The penalty while the HIP rests (a press, a hold, a tap: no god-object's search to take
    /// turns between two solutions), the god-object while it slides (held against a silhouette's
    /// wall); a switch ramps the force in.
    Adaptive,
};

/// \brief Parses "god-object", "penalty" or "adaptive". \return Errc::InvalidArgument otherwise.
Result<FingerContact> parseFingerContact(std::string_view text) noexcept;

/// \brief What force-jump safety does once it trips (paper IV.C and beyond).
enum class Reengage : std::uint8_t {
    Release, ///< Paper IV.C: the proxy collocates with the HIP (zero force) and may stay inside.
    Ramp,    ///< The proxy is re-seated on the surface above the HIP and the force ramps in.
};

/// \brief The re-engagement `play` and `touch` run by default (their --reengage), one value for
/// both so a stroke measured with `touch` is rendered as `play` renders it (issue 61): Ramp.
/// RendererConfig::reengage keeps Release, the paper's.
inline constexpr Reengage kCommandReengage = Reengage::Ramp;

/// \return "release" or "ramp", the --reengage word of \a reengage.
constexpr const char *reengageName(Reengage reengage) noexcept
{
    return reengage == Reengage::Ramp ? "ramp" : "release";
}

/// \brief Renderer parameters. Defaults are the paper's method with its three fixes on
/// (docs/architecture.md §3); `play` and `touch` differ only in `reengage`, kCommandReengage (Ramp)
/// by default.
struct RendererConfig {
    SceneBox box{};            ///< Scene box the frames fill, m.
    double stiffness = 800.0;  ///< k, N/m (scene::kMinStiffness..kMaxStiffness, stiffness.h).
    double damping = 0.0;      ///< b, N·s/m (≥ 0); F −= b·v_HIP while in contact.
    double maxForce = 8.5;     ///< Device maximum, N (> 0): |F| is clamped to it.
    bool correction = true;    ///< Fix (a), paper IV.A: lift the previous proxy with the surface.
    bool interpolation = true; ///< Fix (b), paper IV.B Eq. 1: interpolate frames i → i+1.
    bool safety = true;        ///< Fix (c), paper IV.C: force-jump safety.
    /// Force-jump threshold, N per update. Default 2 N: at k = 800 N/m a stroke at 1 m/s into a
    /// steep smooth wall changes the force by at most k·1 mm = 0.8 N per 1 ms update and surface
    /// motion that is interpolated (< cut threshold per frame) adds < 0.3 N, so smooth use never
    /// trips; a cut of half the box depth (20 mm) changes the unclamped force by 16 N, so it always
    /// trips. The check uses the unclamped force, so it trips even when the clamped force was
    /// already at the maximum.
    double maxForceStep = 2.0;
    Reengage reengage = Reengage::Release; ///< Action after a trip.
    double rampTime = 0.25;                ///< Ramp duration for Reengage::Ramp, s (> 0).
    /// Vertices moving more than this between two frames are not interpolated (held, then stepped
    /// at the frame boundary) so a cut stays visible to safety, m. NaN = 0.25·box depth.
    double cutThreshold = std::nan("");
    /// Coarse-to-fine proxy descent (beyond the paper; solveProxyCoarseToFine()): on frames whose
    /// pixel spacing is finer than this, the descent starts where the HIP projects onto the tangent
    /// plane over ±k vertices, k = floor(coarseSpacing / spacing), when that is within k cells and
    /// the HIP moved less than k cells since the last update; a proxy with farther to go first
    /// slides over every k-th vertex, then over the full grid. The update cost then stops growing
    /// with the depth resolution. m; 0 = always the full grid from the previous proxy. NaN = box
    /// width / 719 (a 720-pixel frame's spacing: frames up to 720 wide never use it; 1080p has
    /// k = 2).
    double coarseSpacing = std::nan("");
    /// Fingertip renderer (Method::Finger) only: half-width r of the 3×3 stencil whose
    /// least-squares plane is the surface the finger touches, m. Noise and quantisation at pixel
    /// scale are averaged over it and slopes taken over 2r; edges are rounded over about r.
    /// NaN = 0.015 × box width (1.5 mm in the default 0.1 m box: 10 pixels of a 640-wide frame;
    /// in `bench feel` 1 mm let the finger through on the forearm scene and 2 mm spiked crossing
    /// it, while 1.5 mm met every goal).
    double fingerRadius = std::nan("");
    /// Fingertip renderer only: the force follows the search's proxy through the offset filter
    /// (FingerRenderer::smoothOffset(): depth noise at speed turned the force back and forth at the
    /// servo rate). Off: the force follows the search's proxy itself (`bench feel`'s
    /// `finger-unfiltered`, and the tests of the search's own stability).
    bool smoothOffset = true;
    /// Fingertip renderer only: how the finger meets the surface (FingerContact). GodObject by
    /// default: Adaptive takes the longest alternating run of `bench feel`'s holds, presses and
    /// taps from 20 to 3 updates, but pressed 2-8 mm into the moving wave of `bench haptics` its
    /// force is 0.34 N RMS off where the god-object's is 0.04 N (docs/benchmarks.md).
    FingerContact fingerContact = FingerContact::GodObject;
    /// Static friction coefficient μs (dimensionless, 0..kMaxFriction) of the friction cone on
    /// the proxy (friction.h; Ruspini et al. 1997): the proxy stays while the tangential spring
    /// force is within μs·Fn. Methods Finger and Modified (and ProxyGraph); MeshBvh ignores it.
    /// 0 with dynamicFriction 0: no friction, the frictionless proxy bit for bit.
    double staticFriction = 0.0;
    /// Dynamic friction coefficient μd (dimensionless, 0..kMaxFriction): a sliding proxy keeps the
    /// tangential force at μd·Fn. Usually ≤ μs; μs − μd sets the force drop when the proxy breaks
    /// away (k·(μs − μd)·depth).
    double dynamicFriction = 0.0;

    /// Largest friction coefficient validate() accepts.
    static constexpr double kMaxFriction = 2.0;

    /// \return the configuration of \a method: Modified all fixes on; ProxyGraph and MeshBvh all
    /// off.
    static RendererConfig forMethod(Method method) noexcept;
    /// \return the fingertip's radius, m: fingerRadius, or 0.015 × box width where it is NaN.
    [[nodiscard]] double fingerRadiusInBox() const noexcept
    {
        return std::isnan(fingerRadius) ? 0.015 * box.width : fingerRadius;
    }
    /// \brief Checks ranges. \return Errc::InvalidArgument with a static message.
    [[nodiscard]] Result<void> validate() const noexcept;
};

/// \brief Result of one haptic update (one force-log row, docs/architecture.md §4).
struct HapticOutput {
    glm::dvec3 hip{};      ///< HIP, m.
    glm::dvec3 proxy{};    ///< Proxy after the update, m.
    glm::dvec3 force{};    ///< Commanded force, N (clamped, ramped, slew-limited).
    bool contact = false;  ///< Proxy held on the surface.
    bool released = false; ///< Safety tripped on this update.
    int constraints = 0;   ///< Active constraint planes at the proxy (0 in free space).
    /// Cost figures of this update: cells the collision walks visited (the proxy-to-HIP walk is
    /// skipped when the HIP is under the surface, its crossing then being certain).
    int cellsVisited = 0;
    int cellsTested = 0;
    int proxySteps = 0; ///< Triangles the proxy slid across.
};

/// \brief Interface shared by the renderers (tests, benchmark and the replay loop use it).
class HapticRenderer {
public:
    virtual ~HapticRenderer() = default;

    /// \brief Sets frame i (\a current) and the buffered frame i+1 (\a next, may be null).
    /// The views' pixels must stay alive and unchanged until the next setFrames().
    /// \return Errc::InvalidArgument for malformed frames or a size above the constructed maximum.
    [[nodiscard]] virtual Result<void> setFrames(const DepthFrameView &current,
                                                 const DepthFrameView *next) noexcept = 0;

    /// \brief One haptic update at haptic time \a t (s, the frames' clock) with HIP \a hip (m).
    /// \pre setFrames() succeeded at least once; \a t does not decrease.
    virtual HapticOutput update(const glm::dvec3 &hip, double t) noexcept = 0;

    /// \brief Forgets the proxy and force history; the proxy collocates with \a hip.
    virtual void reset(const glm::dvec3 &hip) noexcept = 0;

    /// \brief The frames' clock restarted (a seek or a loop): the next update's t may be smaller
    /// than the last. The proxy and the force are kept, so content that continues under the finger
    /// keeps its support; a surface that changed is what the renderer's safety handles.
    virtual void restartClock() noexcept {}

    /// \brief Changes the stiffness k, N/m, from the next update (a viewer's run-time setting;
    /// RendererConfig::stiffness is the start value): the spring force, the force-jump safety and
    /// the slew limit all act on the force at the new k, the force that is sent to the device.
    /// The last force is rescaled with it, so the change itself never trips safety; the slew
    /// limit (and the haptic task's force-rate limit) bring the command to the new force.
    /// Values outside scene::kMinStiffness..kMaxStiffness (stiffness.h) are ignored. Real-time
    /// safe.
    virtual void setStiffness(double newtonsPerMetre) noexcept = 0;

    /// \brief The factor, 0..1, by which the caller scales this renderer's force before the device
    /// (the haptic task's enable ramp, and its ramp back in after the watchdog zeroed the force),
    /// from the next update. A renderer whose safety watches the device maximum compares the
    /// force sent, gain × |F|, with it: a hand that sank while the force was off is pushed out by
    /// the ramp, not let go for a command the device was never sent. Values outside 0..1 are
    /// clamped, NaN ignored. Default 1; the base ignores it. Real-time safe.
    virtual void setOutputGain(double gain) noexcept { (void)gain; }

    [[nodiscard]] virtual Method method() const noexcept = 0;

    /// \name What a judge of the force reads from any renderer (`bench feel`, `bench haptics`,
    /// `haptics_cost`): so that a new method is a row of the renderer table and its own files,
    /// with no list of renderer types in the benches. Thread-bound as update(); read between
    /// updates.
    ///@{
    /// \return the height field the renderer touches, as of its last update (box frame, m; its
    /// holes 1 m under the box, HeightField), or null for a renderer that keeps none (mesh-bvh
    /// builds a mesh instead).
    [[nodiscard]] virtual const HeightField *heightField() const noexcept { return nullptr; }
    /// \return the fingertip's radius r (m) for a renderer whose proxy is a fingertip's rather
    /// than a point's (RendererConfig::fingerRadiusInBox()): it reaches what lies within r of the
    /// HIP's x–y, and its proxy may rest up to r/4 under the samples (a plane fit held within r/4
    /// of them, a ball on a rim); 0 for a point proxy (the paper's methods).
    [[nodiscard]] virtual double fingertipRadius() const noexcept { return 0.0; }
    /// \return the name of the contact state after the last update ("free", "touching"; the
    /// fingertip renderers' FingerState, fingerStateName()), or "" for a renderer without one.
    [[nodiscard]] virtual const char *contactStateName() const noexcept { return ""; }
    ///@}

protected:
    HapticRenderer() = default;
    HapticRenderer(const HapticRenderer &) = default;
    HapticRenderer &operator=(const HapticRenderer &) = default;
};

/// \brief The force limit every force stage applies (the renderers' ForceStage and the haptic
/// task's output): \return \a force (N) scaled down to |F| ≤ \a limit (N); a non-finite force
/// gives zero. Reentrant.
glm::dvec3 limitForce(const glm::dvec3 &force, double limit) noexcept;

/// \brief The slew limit of every force stage: \return \a previous moved toward \a target by at
/// most \a maxStep (N), then limitForce(·, \a maxForce). A non-finite target is taken as zero.
glm::dvec3 slewForce(const glm::dvec3 &previous, const glm::dvec3 &target, double maxStep,
                     double maxForce) noexcept;

/// \brief The force stage shared by all renderers: spring, damping, clamp, force-jump safety
/// (IV.C), ramp re-engagement and slew limit. Thread-bound; no allocation.
///
/// Two halves: apply() is paper IV.C as the `modified` renderer runs it (the trip is decided from
/// the force); spring() and shape() are for a renderer that decides the trip itself
/// (FingerRenderer, from the depth) and share the shaping: a non-finite force becomes zero, |F| is
/// clamped to maxForce, after a trip with a contact to re-engage the force ramps from the last
/// command over rampTime (only while the contact lasts: a finger that leaves is not pushed by a
/// ramp), and with safety on the command moves by at most maxForceStep per update.
class ForceStage {
public:
    explicit ForceStage(const RendererConfig &config) noexcept : config_(config) {}

    /// \brief One update of paper IV.C: the spring force, its jump trips safety, then the shaping.
    /// \param hip the HIP, m, scene-box frame.
    /// \param t haptic time, s.
    /// \param[in,out] proxy after the update; the HIP (Release) or re-seated (Ramp) on a trip.
    /// \param[in,out] contact the proxy is held on the surface; false after a Release trip.
    /// \param surfaceAboveHip height of the surface above the HIP, m, or NaN when there is none.
    /// \param[out] released safety tripped on this update.
    /// \param stiffnessScale scales the stiffness (a material under the proxy, material_field.h).
    /// \return the commanded force, N: finite, |F| ≤ maxForce.
    glm::dvec3 apply(const glm::dvec3 &hip, glm::dvec3 &proxy, bool &contact, double t,
                     double surfaceAboveHip, bool &released, double stiffnessScale = 1.0) noexcept;
    /// \return the unshaped force s·k·(proxy − hip), minus b·v_HIP in contact, N; records the
    /// HIP. \a stiffnessScale s scales the stiffness k (a surface's material, material_field.h).
    glm::dvec3 spring(const glm::dvec3 &hip, const glm::dvec3 &proxy, bool contact, double t,
                      double stiffnessScale = 1.0) noexcept;
    /// \brief Shapes \a raw (N) into the command of time \a t (s).
    /// \param contact the proxy is held on the surface (a ramp runs only while it is).
    /// \param trip safety tripped, or the surface stepped, on this update: the new force is ramped
    /// in from the last command, if there is a contact to re-engage.
    /// \return the command, N: finite, |F| ≤ maxForce.
    glm::dvec3 shape(glm::dvec3 raw, double t, bool contact, bool trip) noexcept;
    void reset() noexcept;
    /// \brief The frames' clock restarted (seek, loop): the next t may be smaller. The force
    /// history is kept (no kick); a ramp in progress continues where it was.
    void restartClock() noexcept { rebase_ = havePrev_; }
    /// \brief HapticRenderer::setStiffness(): k becomes \a newtonsPerMetre (ignored outside
    /// scene::kMinStiffness..kMaxStiffness) and the last unshaped force is rescaled to it, so the
    /// force-jump check compares forces at the same k.
    void setStiffness(double newtonsPerMetre) noexcept;
    [[nodiscard]] double stiffness() const noexcept { return config_.stiffness; }
    /// \return a ramp (after a trip or a ramped step) is in progress. Thread-bound, as the stage.
    [[nodiscard]] bool ramping() const noexcept { return ramping_; }
    /// \return the last command shape() returned, N (zero after reset()).
    [[nodiscard]] const glm::dvec3 &lastCommand() const noexcept { return prevCommand_; }
    /// \brief Ends a ramp in progress: from the next shape() the command follows the raw force,
    /// within maxForceStep an update (the fingertip renderer hands a ramp that holds more than
    /// the surface gives to its own bounded unload, finger_output.cpp).
    void endRamp() noexcept { ramping_ = false; }

private:
    RendererConfig config_;
    bool havePrev_ = false;
    bool rebase_ = false;
    glm::dvec3 prevRaw_{};
    glm::dvec3 prevCommand_{};
    glm::dvec3 prevHip_{};
    double prevT_ = 0.0;
    bool ramping_ = false;
    double rampStartT_ = 0.0;
    glm::dvec3 rampStart_{};
};

/// \brief The modified proxy graph renderer (paper IV) on an implicit height field; with fixes off
/// it is the `proxy-graph` baseline (Walker & Salisbury on sample-and-hold frames).
///
/// Per update: (a) lift the previous proxy by how far the surface under it rose since the last
/// update; (b) vertex heights interpolated by the haptic time (HeightField); collision detection by
/// 2-D DDA (collision.h); god-object proxy update (proxy_solver.h); with friction, the friction
/// cone (friction.h); force `k·(proxy − HIP)` − damping, clamped; (c) force-jump safety
/// (ForceStage). Per new frame: two pointers are stored (no mesh, no tree).
class ProxyGraphRenderer final : public HapticRenderer {
public:
    /// \param config validated by the caller (see RendererConfig::validate()).
    explicit ProxyGraphRenderer(const RendererConfig &config) noexcept;

    [[nodiscard]] Result<void> setFrames(const DepthFrameView &current,
                                         const DepthFrameView *next) noexcept override;
    HapticOutput update(const glm::dvec3 &hip, double t) noexcept override;
    void reset(const glm::dvec3 &hip) noexcept override;
    void restartClock() noexcept override { force_.restartClock(); }
    void setStiffness(double newtonsPerMetre) noexcept override
    {
        force_.setStiffness(newtonsPerMetre);
    }
    [[nodiscard]] Method method() const noexcept override
    {
        return config_.correction || config_.interpolation || config_.safety ? Method::Modified
                                                                             : Method::ProxyGraph;
    }

    /// The surface as of the last update (for tests and diagnostics).
    [[nodiscard]] const HeightField &surface() const noexcept { return field_; }
    [[nodiscard]] const HeightField *heightField() const noexcept override { return &field_; }
    [[nodiscard]] const RendererConfig &config() const noexcept { return config_; }

private:
    RendererConfig config_;
    HeightField field_;
    ForceStage force_;
    glm::dvec3 proxy_{};
    glm::dvec3 lastHip_{}; ///< HIP of the last update (how far it moved), m.
    bool haveProxy_ = false;
    double surfaceUnderProxy_ = 0.0; ///< h(proxy.xy) at the end of the last update, or NaN.
    CoarseGrid
        coarse_{}; ///< Coarse-to-fine grid for the frames set (RendererConfig::coarseSpacing).
    /// Friction on the proxy (RendererConfig::staticFriction): proxy_ stays the frictionless
    /// god-object, where the next update's collision walk starts; the force and the reported
    /// proxy are the friction cone's.
    FrictionCone friction_;
};

/// \brief Creates the renderer of \a method with \a config (its fix flags are used as given).
/// \param maxWidth, maxHeight largest frame the renderer will see (mesh-bvh preallocates for it).
/// \return Errc::InvalidArgument for a bad config, Errc::OutOfResources when allocation fails.
Result<std::unique_ptr<HapticRenderer>> makeRenderer(Method method, const RendererConfig &config,
                                                     int maxWidth, int maxHeight);

} // namespace depthtouch::haptics
