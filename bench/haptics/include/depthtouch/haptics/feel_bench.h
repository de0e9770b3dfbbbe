#pragma once
/// \file
/// \brief `depthtouch bench feel`'s core: replays the strokes of feel_scenes.h on each scene with
/// each renderer setting at 1 kHz, times every update (steady_clock around update()), computes the
/// feel figures (feel.h) and writes the table, CSV, JSON and gnuplot PNG charts.
///
/// Per update the surface under the HIP is the scene's reference surface (ReferenceSurface: the
/// clean scene, or the 5×5 median of real frames; no surface at holes), interpolated at the
/// update's time; the ideal penalty is k·max(0, reference − HIP z) on the same update; and the
/// update is a real cut when the touched surface under the proxy (before or after the update) or
/// the HIP moves by more than the cut threshold between the frames around it. Units: s, m, N; times
/// in the outputs in µs and ms. Thread-safety: run on one thread; not for the haptic thread
/// (allocates).

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "depthtouch/haptics/feel.h"
#include "depthtouch/haptics/feel_scenes.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/scene/material.h"

namespace depthtouch::haptics::bench {

/// \brief One renderer setting to measure ("modified-ramp" etc.).
struct FeelSetting {
    std::string name;
    Method method = Method::Modified;
    RendererConfig config{};
    /// The frames carry a material track (`finger-materials`: see feelMaterial() in
    /// feel_bench.cpp): skin and cloth squares under every stroke.
    bool materials = false;
};

/// The material track of `finger-materials`: squares of this many pixels alternating skin and
/// cloth (docs/materials.md presets), so that every stroke crosses material boundaries.
inline constexpr int kFeelMaterialBlock = 24;
inline constexpr scene::Material kFeelSkin{0.75, 0.6, 0.45};
inline constexpr scene::Material kFeelCloth{0.6, 0.85, 0.65};

/// Friction of the `finger-friction` setting (friction.h): μs and μd of a dry fingertip on a
/// smooth surface. Breaking away drops the tangential force by k·(μs − μd)·depth, 0.24 N pressed
/// 3 mm in at 800 N/m: under the 0.5 N of a force spike (feel.h).
inline constexpr double kFeelStaticFriction = 0.5;
inline constexpr double kFeelDynamicFriction = 0.4;

/// \brief The settings for \a methods: finger (its defaults; then `finger-ramp`, `finger-friction`
/// with kFeelStaticFriction and kFeelDynamicFriction, `finger-materials`, `finger-r1mm`,
/// `finger-r2mm`), modified with Reengage::Release and Reengage::Ramp, proxy-graph, mesh-bvh, in
/// that order where asked.
std::vector<FeelSetting> feelSettings(const std::vector<Method> &methods);

/// \brief The figures of one stroke with one setting.
struct FeelStrokeResult {
    std::string scene;
    std::string setting;
    std::string stroke;
    StrokeKind kind = StrokeKind::Slide;
    StrokeFamily family = StrokeFamily::None;
    std::string where; ///< Stroke::where.
    FeelFigures figures{};
    std::vector<double>
        updateSeconds; ///< Every timed update, s (pooled for the rows' percentiles).
    /// The per-update rows, kept only for strokes that `--dump` names (feel_dump/).
    std::vector<FeelSample> log;
    /// "scene|setting|stroke", what `--dump` matches.
    [[nodiscard]] std::string key() const { return scene + "|" + setting + "|" + stroke; }
};

/// \brief The figures of one scene (or of all, scene "all") with one setting.
struct FeelRow {
    std::string scene;
    std::string setting;
    std::string family = "all"; ///< A stroke family's name, or "all".
    std::size_t strokes = 0;
    /// accumulate() over the strokes, but the update percentiles of all their updates pooled.
    FeelFigures total{};
    double realTripsPerSecond = 0.0;   ///< realCutTrips / slidingSeconds.
    double worstSpikesPerSecond = 0.0; ///< The largest spikes/s of one sliding stroke.
    std::string worstStroke;           ///< Its name.
};

/// \brief The feel goals, each judged on the worst family × scene × setting row (the figures of a
/// row summed or taken at their worst over its strokes, see accumulate()).
struct FeelGoals {
    double maxPopThroughMs = 10.0;      ///< Summed over a row's strokes.
    double maxPhantomMs = 0.0;          ///< Summed over a row's strokes.
    std::size_t maxAlternation = 3;     ///< Updates, the longest alternating run.
    double maxReversalsPerSecond = 1.0; ///< Sign-reversal spikes per second.
    /// Spikes per second pressed, in the hold, tap and press families (and in every family: no
    /// more than the ideal penalty's on the same path).
    double maxStillSpikesPerSecond = 2.0;
    double maxRegainMs = 50.0;   ///< After an occluder leaves a held finger.
    double maxAtMaxMs = 5.0;     ///< At the device maximum without a trip.
    double maxPullDownMs = 0.0;  ///< With a downward force (a height field only pushes).
    double deviceMaxForce = 8.5; ///< N (the Falcon).
    /// Energy the renderer put into the hand beyond the ideal penalty's on the same path, on any
    /// one stroke, mJ (FeelFigures::energyExcessMj; passivity.h): a renderer that generates no
    /// energy of its own gives back no more than the ideal penalty.
    double maxExcessEnergyMj = 0.0;
    // Older goals, kept for the scenario tests of makeStrokes()' slides.
    double maxSpikesPerSecond = 2.0;       ///< Average over the sliding time.
    double maxStrokeSpikesPerSecond = 4.0; ///< On any stroke.
};

/// \brief One goal judged on the worst row of one setting.
struct GoalVerdict {
    std::string goal;   ///< E.g. "pop-through <= 10 ms".
    double worst = 0.0; ///< The worst row's figure.
    std::string where;  ///< That row: "scene / family".
    bool met = true;
    /// The same figure of the ideal penalty on that row's paths, where the goal has one beside it
    /// (the alternating run: FeelFigures::idealLongestAlternation; the sign-reversal spikes per
    /// second: FeelFigures::idealReversalSpikesPerSecond); NaN where not.
    double ideal = std::nan("");
    /// A figure of that row that reads the verdict, printed after it (the energy goal: its part
    /// where the ideal's nearest point is on a side, FeelFigures::energyExcessSidewaysMj); empty
    /// where none.
    std::string aside{};
};

/// \return the verdicts of \a goals for \a setting over \a familyRows (rows of other settings
/// are skipped), in FeelGoals' order.
std::vector<GoalVerdict> judgeGoals(const std::vector<FeelRow> &familyRows,
                                    const std::string &setting, const FeelGoals &goals);

/// \brief Everything one run measured.
struct FeelReport {
    std::vector<FeelRow> rows;       ///< Per scene × setting, in scene order.
    std::vector<FeelRow> familyRows; ///< Per scene × setting × family.
    /// Per setting: force RMS error against the ideal god-object (k·depth along the normal) on the
    /// clean scenes, N (NaN when not measured), in settings order.
    std::vector<std::pair<std::string, double>> cleanRms;
    std::vector<FeelRow> totals; ///< Per setting over all scenes (scene "all").
    std::vector<FeelStrokeResult> strokes;
    std::vector<std::string> notes; ///< Settings or scenes skipped, and why.
    FeelGoals goals{};
    double seconds = 0.0; ///< Wall time of the replays, s.
};

/// \brief Replays \a strokes of \a scene with \a setting. \return one result per stroke, or the
/// renderer's error (e.g. a method not built yet). A stroke whose key() contains \a dump (not
/// empty) keeps its per-update rows in FeelStrokeResult::log; with \a ballIdeal, those rows also
/// carry the ideal ball's force (FeelSample::ballIdealPenalty, ball_ideal.h: up to 10⁵ lookups an
/// update, seconds a stroke).
Result<std::vector<FeelStrokeResult>>
runFeelStrokes(const FeelScene &scene, const std::vector<Stroke> &strokes,
               const FeelSetting &setting, const std::string &dump = {}, bool ballIdeal = false);

/// \brief Replays \a strokes on a clean scene with \a setting. \return the RMS of |F − F_ideal|
/// over the pressed updates, N, where F_ideal = k·d·n, n the reference's normal under the HIP and
/// d the HIP's depth under the reference along it (the god-object on a smooth surface).
Result<double> cleanForceRms(const FeelScene &scene, const std::vector<Stroke> &strokes,
                             const FeelSetting &setting);

/// \brief Runs every setting on every scene with its strokes (\a strokes[i] for \a scenes[i]),
/// then on \a clean scenes (cleanForceRms(), \a cleanStrokes[i] for \a clean[i]).
/// \param progress may be empty; called with a line per scene × setting done.
/// \param dump keep the rows of the strokes whose key() contains it (runFeelStrokes()), with the
/// ideal ball's force in them where \a ballIdeal.
FeelReport runFeelBenchmark(const std::vector<FeelScene> &scenes,
                            const std::vector<std::vector<Stroke>> &strokes,
                            const std::vector<FeelSetting> &settings,
                            const std::function<void(const std::string &)> &progress = {},
                            const std::vector<FeelScene> &clean = {},
                            const std::vector<std::vector<Stroke>> &cleanStrokes = {},
                            const std::string &dump = {}, bool ballIdeal = false);

/// \brief Prints the table and the goals (met / not met per setting) to stdout.
void printFeelReport(const FeelReport &report);

/// \brief Writes feel.csv (per scene × setting and the totals), feel_families.csv (per scene ×
/// setting × family), feel_strokes.csv, feel.json and, with gnuplot, feel.png (accuracy on clean
/// geometry against robustness on real clips, point size the update cost) into \a dir (created).
/// The kept rows of strokes (`--dump`) go to feel_dump/, one CSV per stroke: t (s), the HIP, the
/// proxy (mm, scene box), the force (N), the reference under the HIP and the held surface (mm),
/// the ideal penalty's |F| (N), and the trip, cut, pressed and covered-by-arrival flags.
/// \return false with \a error set when a file cannot be written; \a note says when the chart is
/// missing (no gnuplot).
bool writeFeelOutputs(const FeelReport &report, const std::string &dir, std::string &error,
                      std::string &note);

} // namespace depthtouch::haptics::bench
