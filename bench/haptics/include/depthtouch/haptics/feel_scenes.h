#pragma once
/// \file
/// \brief Content and strokes for the feel figures (feel.h): depth videos held in memory (synthetic
/// scenes seen through a Kinect-style sensor model, or real frames), and the strokes a finger makes
/// on them (press, slide, hold, lift; across silhouettes; still presses). Used by `depthtouch bench
/// feel` and the haptic scenario tests.
///
/// Frames and units (docs/architecture.md §3): nearness samples (0 = far plane, v_max = near plane)
/// filling the scene box; positions in the scene-box frame, m (x right, y up, z toward the viewer,
/// origin at the box centre); times in s, frame i at i / fps. Sensor depth is mapped to nearness
/// the way `depthtouch encode` does (depth/conversion.h): near/far from the robust range
/// (1 %..99 %) of the first 5 frames, 1/Z mapping, rounded to 8 bits (what the H.264 4:0:0 depth
/// stream decodes to) unless 16 bits are asked for. Holes are kept as the receiver sees them
/// (depth/occupancy.h): code 0 under DepthFrameView::holeBelow = occupancyFor(bits,
/// false).threshold, measured nearness lifted by occupiedLevel() above the guard band; the
/// reference surface has no surface there (ReferenceSurface::height() is NaN). `keepHoles = false`
/// gives the older mapping (holes filled by push-pull, no occupancy). The H.264 coding loss itself
/// is not modelled. Thread-safety: reentrant functions; a FeelScene is a value (share it
/// read-only); ReferenceSurface and SceneFrameProvider are thread-bound. Not for the haptic thread
/// (they allocate).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "depthtouch/depth/plane.h"
#include "depthtouch/haptics/depth_frame.h"
#include "depthtouch/haptics/depth_noise.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/haptics/replay.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::haptics::bench {

/// \brief A line across a silhouette (a depth step the finger should climb or step down), box
/// frame, m.
struct SilhouetteCrossing {
    std::string what;  ///< E.g. "head edge", "forearm".
    glm::dvec2 from{}; ///< Start (x, y), m, on the lower side.
    glm::dvec2 to{};   ///< End, m, past the step.
};

/// \brief A depth video in memory, ready to touch.
struct FeelScene {
    std::string name;
    SceneBox box{};
    double fps = 30.0;
    int width = 0;  ///< W, samples.
    int height = 0; ///< H, rows.
    SampleFormat format = SampleFormat::Gray8;
    /// The touched frames: W·H samples each, rows packed, 16-bit in host byte order.
    std::vector<std::vector<std::uint8_t>> frames;
    /// The true surface (Gray16 nearness, same mapping): the clean scene for synthetic content, the
    /// 5×5 median of the frames for real content. Strokes follow it.
    std::vector<std::vector<std::uint16_t>> reference;
    /// W×H: 1 where the sensor measured in at least 90 % of the frames (all 1 when unknown).
    depth::Plane<std::uint8_t> valid;
    std::vector<SilhouetteCrossing> crossings; ///< Silhouettes to cross (synthetic scenes).
    std::uint32_t holeBelow = 0;          ///< Of the touched frames (DepthFrameView::holeBelow).
    std::uint32_t referenceHoleBelow = 0; ///< Of the reference frames (the frames' in 16 bits).

    [[nodiscard]] std::size_t frameCount() const noexcept { return frames.size(); }
    [[nodiscard]] double duration() const noexcept
    {
        return frames.empty() ? 0.0 : static_cast<double>(frames.size() - 1) / fps;
    }
    /// \return a view of touched frame \a i (PTS i / fps). \pre i < frameCount().
    [[nodiscard]] DepthFrameView frame(std::size_t i) const noexcept;
    /// \return a view of reference frame \a i (Gray16). \pre i < frameCount().
    [[nodiscard]] DepthFrameView referenceFrame(std::size_t i) const noexcept;
};

/// \brief The built-in synthetic scenes.
enum class SyntheticScene : std::uint8_t {
    Table,   ///< A tilted table top filling the view: smooth, only sensor noise.
    Head,    ///< A head-sized sphere before a backdrop: a 13–20 mm silhouette step in the box.
    Forearm, ///< A 9 mm-wide bar (a forearm, in box units) lying before a table and a back wall.
    /// A backdrop with dark print and a forearm-like capsule coming up from the bottom of the view
    /// that sweeps across it from left to right once in the clip: an occluder passing in front of
    /// a finger held on the backdrop, and beside one held above its rounded end.
    Occluder,
    /// A hand typing, seen from about 1 m above a desk (the content of a real time-of-flight clip
    /// the other scenes miss): a desk 1.06 m away, a keyboard of 29 × 6 raised keycaps on it
    /// (centred 3 cm above the optical axis; 15 mm pitch, 11 mm flat tops with a dark legend, 10 mm
    /// over their plate, itself 12 mm over the desk: key edges are depth steps of about 3.5 mm in
    /// the box, ridges to swipe across), and over its right part (the hand's axis 9 cm right of the
    /// optical axis, its knuckles 3.5 cm below it) a palm with four fingers (capsules) whose tips
    /// strike keys at 3–6 Hz, each with its own phase, rising 2–3.5 cm between strikes and
    /// alternating between two neighbouring keys (so they sweep past the keys beside them), and a
    /// forearm from the bottom edge of the view; the hand and forearm sway sideways ±2 cm at 0.3 Hz
    /// (at most 3.8 cm/s). Positions before the camera's pan (1 cm/s). Crossings: "keys" (along a
    /// row of keys left of the hand) and "forearm".
    Typing,
    /// The table of Table with what stands or lies on it narrower than a fingertip (in the default
    /// box, 0.1 m wide: r = 1.5 mm, and 1 mm of the box is about 11 mm of the scene): a board
    /// standing on its long edge across the view along X (10 mm thick, 50 mm tall: a top 0.9 mm
    /// wide, 0.6 r, about 5 mm over the table in the box; a book, a phone or a ruler on edge),
    /// still, and a cable lying 9 cm below it (12 mm thick: 1.1 mm wide, about 1 mm tall), pulled
    /// to and fro down the table by ±1 cm at 0.25 Hz (at most 1.6 cm/s). A plane fitted across
    /// 2r sees the table there. Crossing: "ridge" (across the board's top under the optical axis,
    /// the top's middle at the middle).
    Ridges,
};

/// \brief The depth camera model a synthetic scene is seen through.
enum class SensorModel : std::uint8_t {
    StructuredLight, ///< Kinect v1 (applyKinectNoise()).
    TimeOfFlight,    ///< Azure Kinect-like (applyTofNoise()).
    ActiveStereo,    ///< RealSense-like (applyStereoNoise()).
};

/// \return "sl", "tof" or "stereo".
const char *sensorModelName(SensorModel model) noexcept;

/// \return "synthetic-table", "synthetic-head", "synthetic-forearm", "synthetic-occluder",
/// "synthetic-typing" or "synthetic-ridges".
const char *syntheticSceneName(SyntheticScene scene) noexcept;

/// \brief Options of makeSyntheticScene(). The camera is a Kinect v1 (fx = fy = 585 px at 640×480,
/// scaled with the width); it pans at about 1 cm/s and the objects sway, so every frame differs.
struct SyntheticSceneOptions {
    int width = 640;
    int height = 480;
    double fps = 30.0;
    double seconds = 3.0; ///< Clip length, s (frames = round(seconds·fps)).
    int bits = 8;         ///< 8 (Gray8, the default video) or 16 (Gray16).
    SceneBox box{};
    KinectNoiseOptions noise{}; ///< The sensor model (noise.seed picks the draws).
    SensorModel sensor = SensorModel::StructuredLight;
    TofNoiseOptions tof{};       ///< With SensorModel::TimeOfFlight.
    StereoNoiseOptions stereo{}; ///< With SensorModel::ActiveStereo.
    bool noisy = true;           ///< false: the clean scene through the same mapping.
    bool keepHoles = true;       ///< See the file comment.
};

/// \return the name makeSyntheticScene() gives \a scene seen through \a sensor:
/// syntheticSceneName(), with "-tof" or "-stereo" appended for those sensors (no bit depth).
std::string syntheticFeelSceneName(SyntheticScene scene, SensorModel sensor);

/// \brief Renders \a scene (clean metric depth), applies the sensor model, maps it like `depthtouch
/// encode`. The name is syntheticFeelSceneName().
/// \return the scene, or Errc::InvalidArgument for bad options (size < 16, fps ≤ 0, bits
/// not 8 or 16, no frame).
Result<FeelScene> makeSyntheticScene(SyntheticScene scene,
                                     const SyntheticSceneOptions &options = {});

/// \brief Maps sensor depth (mm, 0 = invalid, the layout of a Kinect depth PNG) to a FeelScene the
/// way `depthtouch encode` does (see the file comment). \param cleanMetres optional noiseless
/// depth, m, one per frame: then the reference surface is it through the same mapping (a hole
/// where the sensor measured nothing, when holes are kept); else the 5×5 median of the frames (of
/// the measured samples in the window, a hole where the sample is one). \return
/// Errc::InvalidArgument when there is no frame, sizes differ, bits is not 8 or 16, or the first
/// frames have no valid sample.
Result<FeelScene>
sceneFromSensorDepth(std::string name, const std::vector<depth::Plane<std::uint16_t>> &mm,
                     double fps, const SceneBox &box, int bits = 8,
                     const std::vector<depth::Plane<float>> *cleanMetres = nullptr,
                     bool keepHoles = true);

/// \brief A FeelScene from decoded nearness frames (a depth video: 8-bit samples in
/// Plane<uint16_t> with \a format Gray8, or 16-bit with Gray16). Reference: 5×5 median; valid: all.
/// \return Errc::InvalidArgument when there is no frame or sizes differ.
Result<FeelScene> sceneFromNearness(std::string name,
                                    const std::vector<depth::Plane<std::uint16_t>> &frames,
                                    SampleFormat format, double fps, const SceneBox &box);

/// \brief The touched frames of a scene for replay() (PTS i / fps). Keeps a reference to the scene.
class SceneFrameProvider final : public FrameProvider {
public:
    explicit SceneFrameProvider(const FeelScene &scene) noexcept : scene_(scene) {}
    [[nodiscard]] std::size_t frameCount() const noexcept override { return scene_.frameCount(); }
    Result<DepthFrameView> frame(std::size_t i) noexcept override;

private:
    const FeelScene &scene_;
};

/// \brief The reference surface h(t, x, y): a HeightField over the reference frames, interpolated
/// in time (paper Eq. 1). Keeps a reference to the scene.
class ReferenceSurface {
public:
    explicit ReferenceSurface(const FeelScene &scene);
    /// \return the height at time \a t (s) over (x, y) (m), m; NaN off the grid and where a
    /// corner of the grid cell under (x, y) is a hole in the frame in effect.
    [[nodiscard]] double height(double t, double x, double y);
    /// \return the field set to time \a t (for searches around a point: holes lie 1 m under the
    /// box there, see HeightField), or null when the scene has no frame.
    [[nodiscard]] const HeightField *at(double t);

private:
    const FeelScene &scene_;
    HeightField field_;
    std::size_t current_ = static_cast<std::size_t>(-1);
};

/// \brief Phase lengths of a stroke, s, and the hover height, m.
struct StrokeTiming {
    double rest = 0.05;  ///< Hover before the press and after the lift.
    double press = 0.15; ///< From `above` over the surface to `depth` in.
    double slide = 1.0;  ///< Sliding (out along the line and back), or the still press for Press.
    double hold = 0.5;   ///< Held still, pressed in, after the slide.
    double lift = 0.15;  ///< Back to `above` over the surface.
    double above = 5e-3; ///< Hover height, m.
    [[nodiscard]] double total() const noexcept { return 2 * rest + press + slide + hold + lift; }
};

/// \brief What a stroke does.
enum class StrokeKind : std::uint8_t {
    Slide, ///< Press, slide out along a line and back over smooth valid surface, hold, lift.
    Cross, ///< Across a silhouette (SilhouetteCrossing), tracing the contour as a 4 mm fingertip
           ///< would: rising before the step and up its side at the stroke's speed.
    Press, ///< Press and hold still for slide + hold.
};

/// \return "slide", "cross" or "press".
const char *strokeKindName(StrokeKind kind) noexcept;

/// \brief The stroke families of makeFamilyStrokes() (None: a makeStrokes() stroke).
enum class StrokeFamily : std::uint8_t {
    None,
    Swipe,  ///< Back and forth across a silhouette at 20–50 cm/s.
    Press,  ///< Pressed 0.5 or 6 mm in at 5–10 cm/s, held 0.3 s, released at the same speed.
    Circle, ///< Circles of radius 8 mm around a silhouette point (crossing it twice a turn).
    Tap,    ///< Taps at 5 Hz: from 3 mm above to 2 mm in and back.
    Trace,  ///< Along a silhouette, on its near side, at 5–10 cm/s.
    Hold,   ///< Still, pressed 1 or 3 mm in: beside a moving object, under a passing occluder, on
            ///< an edge, on flickering pixels, at a hole's border, on a still surface.
};

/// \return "-", "swipe", "press", "circle", "tap", "trace" or "hold".
const char *strokeFamilyName(StrokeFamily family) noexcept;

/// \brief One haptic update of a stroke: time, HIP and what the finger is doing.
struct StrokeSample {
    double t = 0.0;       ///< s (the frames' clock).
    glm::dvec3 hip{};     ///< m, scene-box frame.
    bool sliding = false; ///< Moving along the surface, pressed in.
    bool held = false;    ///< Still (in x–y), pressed in.
    bool pressed = false; ///< Under the surface it follows (any phase).
    /// Holds: the height of the held surface under the HIP (followed while it drifts, kept while
    /// something rises over it), m; NaN otherwise.
    double heldZ = std::nan("");
};

/// \brief Where and how one stroke goes.
struct StrokeSpec {
    StrokeKind kind = StrokeKind::Slide;
    glm::dvec2 from{};   ///< Press point (x, y), m.
    glm::dvec2 to{};     ///< Far end of the slide (ignored for Press), m.
    double startT = 0.0; ///< s.
    double depth = 1e-3; ///< How far in the HIP is pressed under the reference surface, m (> 0).
    double speed = 0.05; ///< Slide speed, m/s (> 0).
    std::string name;
};

/// \brief A stroke sampled at the haptic rate.
struct Stroke {
    std::string name;
    StrokeKind kind = StrokeKind::Slide;
    StrokeFamily family = StrokeFamily::None;
    std::string where;  ///< Where a family stroke was placed ("silhouette", "moving", ...).
    double depth = 0.0; ///< m.
    double speed = 0.0; ///< m/s (0 for Press).
    std::vector<StrokeSample> samples;
};

/// \brief Samples one stroke at \a rate Hz: hover `above` the reference surface, press in to
/// `depth` under it, slide back and forth between from and to (from→to→from→…) at `speed` for
/// `timing.slide` s (Press: stay still), hold, lift, hover. The HIP's z follows the reference
/// surface under it at every sample (NaN heights, off the grid, keep the last height).
Stroke makeStroke(const FeelScene &scene, const StrokeSpec &spec, const StrokeTiming &timing = {},
                  double rate = 1000.0);

/// \brief Which strokes makeStrokes() places.
struct StrokePlan {
    std::vector<double> depths{1e-3, 3e-3}; ///< m.
    std::vector<double> speeds{0.05, 0.10}; ///< m/s.
    int slidesPerSetting =
        2;                 ///< Slides per depth × speed, at seeded places on smooth valid surface.
    bool crossings = true; ///< One Cross stroke per scene crossing × depth × speed.
    int presses = 1;       ///< Press strokes per depth.
    StrokeTiming timing{}; ///< slide is shortened to fit the clip (at least 0.3 s).
    double rate = 1000.0;  ///< Samples per second.
    std::uint64_t seed = 7; ///< Placement draws.
};

/// \brief The strokes of \a plan on \a scene. A slide's line is kept 4 mm inside the box, over
/// pixels valid in the scene's mask, and off silhouettes (the reference rises by less than 1 mm per
/// 0.5 mm along it at its start, middle and end times); a setting with no such line after 400 draws
/// is skipped.
std::vector<Stroke> makeStrokes(const FeelScene &scene, const StrokePlan &plan = {});

/// \brief Where the content of a scene is hardest, per pixel (box metres; see analyseScene()).
struct SceneFeatures {
    /// The largest change of the reference between consecutive frames, m (NaN: never measured).
    depth::Plane<float> motion;
    /// RMS of the touched frames about the reference, m (the sensor's flicker; NaN: none).
    depth::Plane<float> flicker;
    /// Fraction of the frames in which the touched sample is a hole.
    depth::Plane<float> holeFraction;
    /// How far something rose over the pixel and left again: the largest reference height above
    /// its height in the first and last frames (which agree within 2 mm), m; 0 when they differ.
    depth::Plane<float> rise;
    depth::Plane<std::uint16_t> firstCovered; ///< First frame risen more than 3 mm over it.
    depth::Plane<std::uint16_t> lastCovered;  ///< Last such frame.
};

/// \return the feature maps of \a scene.
SceneFeatures analyseScene(const FeelScene &scene);

/// \brief A silhouette point: a depth step of the reference of more than `minStep` over 4 px.
struct SilhouettePoint {
    int column = 0;
    int row = 0;
    glm::dvec2 at{};   ///< Box (x, y), m.
    glm::dvec2 up{};   ///< Unit x–y direction toward the near (higher) side.
    double step = 0.0; ///< Height difference over the 4 px, m.
};

/// \return the silhouette points of reference frame \a frame (at least \a margin, m, inside the
/// box), at most every other pixel.
std::vector<SilhouettePoint> findSilhouettes(const FeelScene &scene, std::size_t frame,
                                             double minStep = 3e-3, double margin = 12e-3);

/// \brief Which strokes makeFamilyStrokes() places (counts per scene).
struct FamilyPlan {
    int places = 2;                                ///< Swipes per speed, circles, taps.
    std::vector<double> swipeSpeeds{0.20, 0.50};   ///< m/s.
    double swipeDepth = 2e-3;                      ///< m.
    double swipeReach = 10e-3;                     ///< Either side of the silhouette, m.
    std::vector<double> pressDepths{0.5e-3, 6e-3}; ///< m.
    std::vector<double> pressSpeeds{0.05, 0.10};   ///< m/s, in and out.
    double pressHold = 0.3;                        ///< s.
    double circleRadius = 8e-3;                    ///< m.
    double circleSpeed = 0.10;                     ///< m/s.
    double circleDepth = 2e-3;                     ///< m.
    /// One more circle (circleRadius) at this speed, m/s, placed after all other strokes with its
    /// own draws (seed + 101), so the others keep their places; 0: none.
    double fastCircleSpeed = 0.30;
    /// With it, a swipe at this speed, m/s, along the scene's crossing named "keys" when it has
    /// one (the typing scene's row of keys); 0: none.
    double keysSwipeSpeed = 0.50;
    /// With them, a press pressDepths.back() deep at pressSpeeds.front() onto the top of the
    /// scene's crossing named "ridge" when it has one (the middle of the crossing: a top narrower
    /// than a fingertip); false: none.
    bool ridgePress = true;
    double tapHz = 5.0;
    double tapDepth = 2e-3;                      ///< m under the surface at the bottom.
    double tapAbove = 3e-3;                      ///< m over it at the top.
    std::vector<double> traceSpeeds{0.05, 0.10}; ///< m/s.
    double traceDepth = 2e-3;                    ///< m.
    std::vector<double> holdDepths{1e-3, 3e-3};  ///< m.
    double moveSeconds = 1.0; ///< Swipes, circles, traces, taps: the main phase, s.
    double holdSeconds = 1.5; ///< Holds (an occluder's hold spans its passage), s.
    double rate = 1000.0;     ///< Samples per second.
    std::uint64_t seed = 11;  ///< Placement draws.
};

/// \brief The six families of strokes of \a plan on \a scene, placed where the content is hardest
/// (see StrokeFamily): silhouettes from findSilhouettes() at each stroke's time, moving regions,
/// passing occluders, flicker and hole borders from analyseScene(); seeded. After them, with draws
/// of their own: a fast circle (FamilyPlan::fastCircleSpeed) on a silhouette, a fast swipe along
/// the "keys" crossing (FamilyPlan::keysSwipeSpeed) and a deep press on the "ridge" crossing's top
/// (FamilyPlan::ridgePress); they do not move the others. A stroke
/// with no place to go is left out and named in \a notes (when given).
std::vector<Stroke> makeFamilyStrokes(const FeelScene &scene, const FamilyPlan &plan = {},
                                      std::vector<std::string> *notes = nullptr);

/// \return the stroke as a trajectory for replay() (times kept: replay() starts at t = 0 and holds
/// the first row until the stroke starts).
std::vector<TrajectorySample> toTrajectory(const Stroke &stroke);

} // namespace depthtouch::haptics::bench
