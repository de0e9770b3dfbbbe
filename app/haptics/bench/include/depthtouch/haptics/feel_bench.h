#pragma once
/// \file
/// \brief `depthtouch bench feel`'s core: replays the strokes of feel_scenes.h on each scene with
/// each renderer setting at 1 kHz, times every update (steady_clock around update()), computes the
/// feel figures (feel.h) and writes the table, CSV, JSON and gnuplot PNG charts.
///
/// Per update the surface under the HIP is read from a HeightField over the same frames,
/// interpolated at the update's time (the renderer's own surface model), and the update is a real
/// cut when the surface under the proxy (before or after the update) or the HIP moves by more than
/// the cut threshold between the frames around it. Units: s, m, N; times in the outputs in µs and
/// ms. Thread-safety: run on one thread; not for the haptic thread (allocates).

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
    FeelFigures figures{};
    std::vector<double>
        updateSeconds; ///< Every timed update, s (pooled for the rows' percentiles).
};

/// \brief The figures of one scene (or of all, scene "all") with one setting.
struct FeelRow {
    std::string scene;
    std::string setting;
    std::size_t strokes = 0;
    /// accumulate() over the strokes, but the update percentiles of all their updates pooled.
    FeelFigures total{};
    double realTripsPerSecond = 0.0; ///< realCutTrips / slidingSeconds.
    double worstSpikesPerSecond = 0.0; ///< The largest spikes/s of one sliding stroke.
    std::string worstStroke;      ///< Its name.
};

/// \brief Issue 15's goals.
struct FeelGoals {
    double maxPopThroughMs = 10.0;   ///< Summed over the strokes.
    double maxPhantomMs = 10.0;      ///< Summed over the strokes.
    double maxSpikesPerSecond = 2.0; ///< Average over the sliding time.
    double maxStrokeSpikesPerSecond = 4.0; ///< On any stroke.
    double deviceMaxForce = 8.5;     ///< N (the Falcon).
};

/// \brief Everything one run measured.
struct FeelReport {
    std::vector<FeelRow> rows;        ///< Per scene × setting, in scene order.
    std::vector<FeelRow> totals;      ///< Per setting over all scenes (scene "all").
    std::vector<FeelStrokeResult> strokes;
    std::vector<std::string> notes;   ///< Settings or scenes skipped, and why.
    FeelGoals goals{};
    double seconds = 0.0;             ///< Wall time of the replays, s.
};

/// \brief Replays \a strokes of \a scene with \a setting. \return one result per stroke, or the
/// renderer's error (e.g. a method not built yet).
Result<std::vector<FeelStrokeResult>> runFeelStrokes(const FeelScene &scene,
                                                     const std::vector<Stroke> &strokes,
                                                     const FeelSetting &setting);

/// \brief Runs every setting on every scene with its strokes (\a strokes[i] for \a scenes[i]).
/// \param progress may be empty; called with a line per scene × setting done.
FeelReport runFeelBenchmark(const std::vector<FeelScene> &scenes,
                            const std::vector<std::vector<Stroke>> &strokes,
                            const std::vector<FeelSetting> &settings,
                            const std::function<void(const std::string &)> &progress = {});

/// \brief Prints the table and the goals (met / not met per setting) to stdout.
void printFeelReport(const FeelReport &report);

/// \brief Writes feel.csv (per scene × setting and the totals), feel_strokes.csv, feel.json and,
/// with gnuplot, feel_vs_speed.png into \a dir (created). \return false with \a error set when a
/// file cannot be written; \a note says when the chart is missing (no gnuplot).
bool writeFeelOutputs(const FeelReport &report, const std::string &dir, std::string &error,
                      std::string &note);

} // namespace depthtouch::haptics::bench
