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
/// the way `depthtouch encode` does by default (depth/conversion.h, depth/fill.h): near/far from
/// the robust range (1 %..99 %) of the first 5 frames, 1/Z mapping, holes filled by push-pull,
/// rounded to 8 bits (what the H.264 4:0:0 depth stream decodes to) unless 16 bits are asked for.
/// The H.264 coding loss itself is not modelled here (the bench encodes real captures through the
/// encoder). Thread-safety: reentrant functions; a FeelScene is a value (share it read-only);
/// ReferenceSurface and SceneFrameProvider are thread-bound. Not for the haptic thread (they
/// allocate).

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
};

/// \return "synthetic-table", "synthetic-head" or "synthetic-forearm".
const char *syntheticSceneName(SyntheticScene scene) noexcept;

/// \brief Options of makeSyntheticScene(). The camera is a Kinect v1 (fx = fy = 585 px at 640×480,
/// scaled with the width); it pans at about 1 cm/s and the objects sway, so every frame differs.
struct SyntheticSceneOptions {
    int width = 640;
    int height = 480;
    double fps = 30.0;
    double seconds = 3.0;          ///< Clip length, s (frames = round(seconds·fps)).
    int bits = 8;                  ///< 8 (Gray8, the default video) or 16 (Gray16).
    SceneBox box{};
    KinectNoiseOptions noise{};    ///< The sensor model (noise.seed picks the draws).
    bool noisy = true;             ///< false: the clean scene through the same mapping.
};

/// \brief Renders \a scene (clean metric depth), applies the sensor model, maps it like `depthtouch
/// encode`. \return the scene, or Errc::InvalidArgument for bad options (size < 16, fps ≤ 0, bits
/// not 8 or 16, no frame).
Result<FeelScene> makeSyntheticScene(SyntheticScene scene,
                                     const SyntheticSceneOptions &options = {});

/// \brief Maps sensor depth (mm, 0 = invalid, the layout of a Kinect depth PNG) to a FeelScene the
/// way `depthtouch encode` does by default (see the file comment). \param cleanMetres optional
/// noiseless depth, m, one per frame: then the reference surface is it through the same mapping;
/// else the 5×5 median of the frames. \return Errc::InvalidArgument when there is no frame, sizes
/// differ, bits is not 8 or 16, or the first frames have no valid sample.
Result<FeelScene>
sceneFromSensorDepth(std::string name, const std::vector<depth::Plane<std::uint16_t>> &mm,
                     double fps, const SceneBox &box, int bits = 8,
                     const std::vector<depth::Plane<float>> *cleanMetres = nullptr);

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
    /// \return the height at time \a t (s) over (x, y) (m), m; NaN off the grid.
    [[nodiscard]] double height(double t, double x, double y);

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

/// \brief One haptic update of a stroke: time, HIP and what the finger is doing.
struct StrokeSample {
    double t = 0.0;        ///< s (the frames' clock).
    glm::dvec3 hip{};      ///< m, scene-box frame.
    bool sliding = false;  ///< Moving along the surface, pressed in.
    bool held = false;     ///< Still (in x–y), pressed in.
};

/// \brief Where and how one stroke goes.
struct StrokeSpec {
    StrokeKind kind = StrokeKind::Slide;
    glm::dvec2 from{};     ///< Press point (x, y), m.
    glm::dvec2 to{};       ///< Far end of the slide (ignored for Press), m.
    double startT = 0.0;   ///< s.
    double depth = 1e-3;   ///< How far in the HIP is pressed under the reference surface, m (> 0).
    double speed = 0.05;   ///< Slide speed, m/s (> 0).
    std::string name;
};

/// \brief A stroke sampled at the haptic rate.
struct Stroke {
    std::string name;
    StrokeKind kind = StrokeKind::Slide;
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
    std::vector<double> depths{1e-3, 3e-3};   ///< m.
    std::vector<double> speeds{0.05, 0.10};   ///< m/s.
    int slidesPerSetting =
        2; ///< Slides per depth × speed, at seeded places on smooth valid surface.
    bool crossings = true;     ///< One Cross stroke per scene crossing × depth × speed.
    int presses = 1;           ///< Press strokes per depth.
    StrokeTiming timing{};     ///< slide is shortened to fit the clip (at least 0.3 s).
    double rate = 1000.0;      ///< Samples per second.
    std::uint64_t seed = 7;    ///< Placement draws.
};

/// \brief The strokes of \a plan on \a scene. A slide's line is kept 4 mm inside the box, over
/// pixels valid in the scene's mask, and off silhouettes (the reference rises by less than 1 mm per
/// 0.5 mm along it at its start, middle and end times); a setting with no such line after 400 draws
/// is skipped.
std::vector<Stroke> makeStrokes(const FeelScene &scene, const StrokePlan &plan = {});

/// \return the stroke as a trajectory for replay() (times kept: replay() starts at t = 0 and holds
/// the first row until the stroke starts).
std::vector<TrajectorySample> toTrajectory(const Stroke &stroke);

} // namespace depthtouch::haptics::bench
