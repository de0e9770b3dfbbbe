#pragma once
/// \file
/// \brief Feel figures of a haptic run: what a viewer's finger meets on real depth video (false
/// safety trips, pop-through, phantom force, force spikes, ripple while held), computed from the
/// per-update rows of a replay or of the player's force log and the height of the surface under
/// the finger. Used by `depthtouch bench feel`, the demo's summary and the scenario tests.
///
/// Definitions (all per update; thresholds in FeelThresholds):
/// - **trip**: the renderer's safety released or re-seated the proxy (`released`); it is a *real
/// cut*
///   when the surface under the proxy moved by more than the cut threshold between the two depth
///   frames around that update (`surfaceCut`), else a *false trip*.
/// - **pop-through**: after the first contact, the HIP is more than `depthMargin` inside the
///   surface (FeelSample::depthInside, else under it at its own x–y) and |F| < `popForce`.
/// - **phantom force**: the HIP is more than `depthMargin` above the surface at its own x–y (or off
///   the surface) and |F| > `phantomForce`.
/// - **spike**: |F(n) − F(n−1)| > `spikeStep` in one update, counted while `sliding`.
/// - **ripple**: RMS of |F| about its mean over the updates marked `held` (HIP still, pressed in),
///   also given relative to that mean (the force just-noticeable difference is 5–10 %).
/// Units: s, m, N (scene-box frame, docs/architecture.md §3). Thread-safety: reentrant; allocates
/// (not for the haptic thread).

#include <cmath>
#include <cstddef>
#include <span>

#include <glm/vec3.hpp>

namespace depthtouch::haptics {

/// \brief One update as the feel figures need it.
struct FeelSample {
    double t = 0.0;          ///< Time, s (monotonic over the run: play time, not media time).
    glm::dvec3 hip{};        ///< HIP, m.
    glm::dvec3 force{};      ///< Commanded force, N.
    double surfaceZ = 0.0;   ///< Height of the surface under the HIP, m; NaN when off the surface.
    /// How deep the HIP is inside: its distance to the nearest surface point, m, when it is under
    /// the surface (on a steep side this is far less than surfaceZ − hip.z). NaN: not measured,
    /// the vertical depth surfaceZ − hip.z is used.
    double depthInside = std::nan("");
    bool released = false;   ///< Safety tripped on this update.
    bool surfaceCut =
        false; ///< The surface under the proxy moved more than the cut threshold here.
    bool sliding = false;    ///< Part of a slide (the HIP moving along the surface, pressed in).
    bool held = false;       ///< Part of a still press (for the ripple).
    double updateSeconds = 0.0; ///< Wall time of the update, s (0 when not measured).
};

/// \brief Thresholds of the figures (the defaults are issue 15's).
struct FeelThresholds {
    double depthMargin = 1e-3;   ///< m, for pop-through and phantom force.
    double popForce = 0.1;       ///< N: under this while inside is pop-through.
    double phantomForce = 0.2;   ///< N: above this while outside is phantom force.
    double spikeStep = 0.5;      ///< N per update.
};

/// \brief The figures of one run (or of several runs summed, see accumulate()).
struct FeelFigures {
    double seconds = 0.0;         ///< Time covered, s.
    double slidingSeconds = 0.0;  ///< Time marked sliding, s.
    std::size_t updates = 0;
    std::size_t trips = 0;        ///< Safety trips (released).
    std::size_t realCutTrips = 0; ///< Of them, at a real cut (surfaceCut).
    std::size_t falseTrips = 0;   ///< trips − realCutTrips.
    double popThroughMs = 0.0;    ///< Time in pop-through, ms.
    double phantomMs = 0.0;       ///< Time with phantom force, ms.
    std::size_t spikes = 0;       ///< Spikes while sliding.
    double spikesPerSecond = 0.0; ///< spikes / slidingSeconds (0 when not sliding).
    double falseTripsPerSecond = 0.0; ///< falseTrips / slidingSeconds.
    double rippleRms = 0.0;       ///< N, while held.
    double rippleRelative = 0.0;  ///< rippleRms / mean |F| while held (0 when no force).
    double maxForce = 0.0;        ///< N.
    double updateP50 = 0.0;       ///< s, of the measured updates (0 when none).
    double updateP999 = 0.0;      ///< s.
};

/// \brief Computes the figures of one run of consecutive updates.
/// \param rows the updates in time order; the first row's force step is taken from zero.
[[nodiscard]] FeelFigures computeFeel(std::span<const FeelSample> rows,
                                      const FeelThresholds &thresholds = {});

/// \brief Adds \a run's counts and times to \a total (rates and percentiles recomputed from the
/// sums where they can be; ripple and update percentiles: the worst of the two).
void accumulate(FeelFigures &total, const FeelFigures &run) noexcept;

} // namespace depthtouch::haptics
