#pragma once
/// \file
/// \brief Feel figures of a haptic run: what a viewer's finger meets on real depth video (false
/// safety trips, pop-through, phantom force, force spikes, ripple while held), computed from the
/// per-update rows of a replay or of the player's force log and the height of the surface under
/// the finger. Used by `depthtouch bench feel`, the demo's summary and the scenario tests.
///
/// Definitions (all per update; thresholds in FeelThresholds):
/// - **trip**: the renderer's safety released or re-seated the proxy (`released`); it is a *real
///   cut* when the surface under the proxy moved by more than the cut threshold between the two
///   depth frames around that update (`surfaceCut`), an *arrival trip* while the finger is covered
///   by an arriving surface or an occluder over a held finger (below), else a *false trip*.
/// - **pop-through**: after the first contact, the HIP is more than `depthMargin` inside the
///   surface (FeelSample::depthInside, else under it at its own x–y) and |F| < `popForce`.
/// - **phantom force**: the HIP is more than `depthMargin` above the surface at its own x–y and |F|
///   > `phantomForce`, and above all the surface within the fingertip's reach (FeelSample::
///   reachSurfaceZ: a fingertip of radius r still rests on an edge r beside its centre, as a
///   finger leaving a table's edge does), and the force is not falling at the force stage's step
///   limit (`forceStep`: a release in progress, renderer.h ForceStage). Where there is no surface
///   (off the grid, or a hole: nothing was measured) neither phantom force nor pop-through is
///   judged.
/// - **spike**: |F(n) − F(n−1)| > `spikeStep` in one update, counted while `sliding`.
/// - **ripple**: RMS of |F| about its mean over the updates marked `held` (HIP still, pressed in),
///   also given relative to that mean (the force just-noticeable difference is 5–10 %).
/// - **pressed spikes**: spikes counted over every update marked `pressed`, `sliding` or `held`
///   (the finger pressed in, whatever it does), per second of those updates; the same count of the
///   ideal penalty (`idealForce`) on the same updates is the yardstick (a real step in the surface
///   is a spike of the ideal penalty too).
/// - **sign-reversal spike**: a spike (|ΔF(n)| > `spikeStep`) whose change points against the
///   change of the update before (ΔF(n)·ΔF(n−1) < 0, |ΔF(n−1)| > `alternationStep`): a force that
///   jumps and comes back, or a limit cycle. Counted over every update, per second of the run.
/// - **alternating run**: the longest chain of consecutive updates whose force changes all exceed
///   `alternationStep` and each point against the one before (a proxy that alternates between two
///   points every update gives one change per update: a run as long as the cycle lasts). A single
///   jump and return is a run of 2. The ideal penalty's own run on the same updates is reported
///   beside it (FeelFigures::idealLongestAlternation), as the spikes' yardstick is.
/// - **time to regain contact** (holds beside an occluder, `heldSurfaceZ` given): an occluder is
///   over the finger while the surface under the HIP is not the held surface (more than
///   `depthMargin` above it, or no surface); from the first update after it where the surface under
///   the HIP is again the held surface and the HIP is under it, the time until |F| ≥ `popForce`.
///   Never regained before the hold ends: the time to its end (and counted as missed). Pop-through
///   and phantom force are not counted while an occluder is over the finger, also after the hold
///   has ended, until the finger is out of it (lifted out through an object that came over it).
/// - **covered by an arriving surface** (any stroke, `surfaceRise` given): the surface under the
///   HIP's own x–y rose faster than `pushRate` (a person walking in front of the finger, an
///   object's side sweeping over it), also across a hole (a stereo shadow or a time-of-flight
///   dropout runs ahead of a moving edge): a surface that comes back out of a hole higher than it
///   was last measured there rose by the difference in that update (no renderer saw it come); one
///   back at its height after a dropout rose by nothing and covers nothing. What each update's rise
///   exceeds a push-out at `pushRate` by adds to the *swept depth*, a fall of the surface takes
///   from it (never more than the HIP's depth under the surface; 0 once the HIP is out). While it
///   exceeds `depthMargin` the finger is covered (a hole over the HIP, an arrived object's own
///   shadow or dropout, keeps it until the surface there is measured again): the finger may be
///   pushed out at a bounded rate or let go (docs/benchmarks.md), so neither pop-through nor
///   phantom force is counted, and a trip there is an *arrival trip*, not a false one. Spikes, the
///   alternating run and the time at the device maximum are counted as everywhere.
/// - **pull-down force**: time with the force pointing down more than `phantomForce` (Fz <
///   −`phantomForce`): a height field's surface only pushes up and out, so a spring that pulls the
///   finger down (toward or into the surface) is a fault wherever the finger is.
/// - **time at the device maximum**: the longest run of consecutive updates with |F| ≥
///   `deviceMaxForce`·(1 − 1e-3) and no safety trip among them.
/// - **energy into the hand** (passivity.h, Hannaford & Ryu's observer): E = Σ F(n−1)·(HIP(n) −
///   HIP(n−1)), the net work the commanded force did on the hand over the run; the same sum of the
///   ideal god-object's force (`idealPenalty`, from nearestSurface(): passive on a still surface),
///   clamped to `deviceMaxForce` as a device renders it) on the same path; their difference is the
///   energy the renderer generated beyond the work the (moving) surface itself did. Neither is
///   summed while the finger is covered by an arriving surface or an occluder (as pop-through and
///   phantom force are not: the renderer may push out at a bounded rate or let go there), nor over
///   the move into or out of it. That difference is the surface's work only where both forces
///   take the same work from it: deeper under a surface than a side is near, the ideal's nearest
///   point is on that side (its force within 30° of horizontal), and a proxy that does not pop
///   through still pushes up. The moves held under such an ideal force while the renderer's is up
///   or nothing are summed apart (`energyExcessSidewaysMj`, docs/benchmarks.md, "The energy
///   yardstick's nearest point on a side").
/// Units: s, m, N (scene-box frame, docs/architecture.md §3). Thread-safety: reentrant; allocates
/// (not for the haptic thread).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <span>

#include <glm/vec3.hpp>

namespace depthtouch::haptics {

/// \brief One update as the feel figures need it.
struct FeelSample {
    double t = 0.0;          ///< Time, s (monotonic over the run: play time, not media time).
    glm::dvec3 hip{};        ///< HIP, m.
    glm::dvec3 force{};      ///< Commanded force, N.
    glm::dvec3 proxy{};      ///< The renderer's proxy, m (for --dump).
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
    bool pressed = false;    ///< Pressed in (any stroke phase under the surface; see the file).
    /// |F| of the ideal penalty on this update, k·max(0, surfaceZ − hip.z), N; NaN: not given.
    double idealForce = std::nan("");
    /// The ideal god-object's force on this update, N: k·(nearest surface point − HIP) under the
    /// surface (nearestSurface()), zero above it; NaN: not given (no ideal energy is summed).
    glm::dvec3 idealPenalty{std::nan("")};
    /// The ideal ball's force on this update (a ball of the renderer's fingertip radius on the
    /// reference surface; `bench feel --dump --dump-ball-ideal`'s logged strokes only,
    /// ball_ideal.h), N; NaN: not given. Not judged.
    glm::dvec3 ballIdealPenalty{std::nan("")};
    /// Height of the surface a held finger rests on (without any occluder), m; NaN: not a hold.
    double heldSurfaceZ = std::nan("");
    /// How far the surface under the HIP's x–y rose since the update before (the same x–y, the
    /// surface one update earlier), m; where the update before had a hole there, since the
    /// surface was last measured at that x–y (a renderer sees nothing in a hole: what came
    /// while it hid the surface arrives in this update); NaN: not known (no arrival is judged).
    double surfaceRise = std::nan("");
    /// The highest surface within the fingertip's reach of the HIP's x–y (a disc of the
    /// renderer's finger radius), m; NaN: a point contact, or not known (surfaceZ alone judges
    /// phantom force).
    double reachSurfaceZ = std::nan("");
    /// The renderer's contact state after the update, by name (fingerStateName(): "free",
    /// "touching", …) for the fingertip renderer; null for a renderer without one (for --dump).
    const char *state = nullptr;
    double updateSeconds = 0.0; ///< Wall time of the update, s (0 when not measured).
};

/// \return the highest of \a heightAt(x, y) (m; NaN where nothing was measured) at (\a x, \a y)
/// and at 8 points each on circles of radius/2 and \a radius (m) around it: the surface within a
/// fingertip's reach (FeelSample::reachSurfaceZ); NaN where none of them is measured.
template <class HeightAt>
double reachHeight(const HeightAt &heightAt, double x, double y, double radius)
{
    double best = heightAt(x, y);
    for (int ring = 1; ring <= 2; ++ring)
        for (int k = 0; k < 8; ++k) {
            const double a = 0.25 * std::numbers::pi * k;
            const double d = 0.5 * ring * radius;
            const double h = heightAt(x + d * std::cos(a), y + d * std::sin(a));
            if (std::isfinite(h) && !(h <= best))
                best = h;
        }
    return best;
}

/// \brief depthInside()'s search, which also gives where the nearest surface point is: \a nearest
/// (when not null) is set to it, m (the point straight above the HIP when nothing nearer is
/// found). \return the distance, m. The ideal god-object's proxy (Zilles & Salisbury 1995), whose
/// spring k·(nearest − HIP) is the force of the potential ½·k·distance², passive on a still
/// surface (FeelSample::idealPenalty). Searched on rings \a step (m) apart in \a directions
/// directions, out to \a reach (m) at most (the ideal ball's search, ball_ideal.h, is the same
/// on the surface its lowest point rests on).
template <class HeightAt>
double nearestSurface(const HeightAt &heightAt, const glm::dvec3 &hip, double vertical,
                      glm::dvec3 *nearest, double step = 0.2e-3, int directions = 24,
                      double reach = std::numeric_limits<double>::infinity())
{
    double best = vertical;
    glm::dvec3 at{hip.x, hip.y, hip.z + vertical};
    for (double ring = step; ring < std::min(best, reach); ring += step) {
        for (int k = 0; k < directions; ++k) {
            const double a = 2.0 * std::numbers::pi * k / directions;
            const double x = hip.x + ring * std::cos(a);
            const double y = hip.y + ring * std::sin(a);
            const double h = heightAt(x, y);
            if (!std::isfinite(h))
                continue;
            const double dz = std::max(h - hip.z, 0.0);
            const double d = std::sqrt(ring * ring + dz * dz);
            if (d < best) {
                best = d;
                at = {x, y, hip.z + dz};
            }
        }
    }
    if (nearest != nullptr)
        *nearest = at;
    return best;
}

/// \return the distance from \a hip (m) to the nearest point of the surface \a heightAt(x, y) (m;
/// NaN where nothing was measured or off the frame), searched on rings 0.2 mm apart in 24
/// directions out to \a vertical (the depth under the surface at the HIP's x–y, which bounds it),
/// m: FeelSample::depthInside, the depth pop-through is judged by (a HIP just beside an object's
/// steep side is that far inside it, not the height of the side).
template <class HeightAt>
double depthInside(const HeightAt &heightAt, const glm::dvec3 &hip, double vertical)
{
    return nearestSurface(heightAt, hip, vertical, nullptr);
}

/// \return the local plane's penalty force at \a hip (m) on the surface \a heightAt(x, y) (m; NaN
/// where nothing was measured) at stiffness \a k (N/m), N: k·d·n, n the surface's unit normal under
/// the HIP (central differences over ±0.3 mm; straight up where a difference is not measured) and d
/// the HIP's depth under the surface along it, (h − z)·n_z: the god-object on the surface's local
/// plane (Zilles & Salisbury 1995). Zero above the surface or where \a h (the height under the
/// HIP, m) is NaN. `bench feel`'s force RMS error on clean surfaces is measured against it; its
/// energy yardstick is the nearest point's (nearestSurface(), FeelSample::idealPenalty), which,
/// unlike this one, is a potential's force on a steep side.
template <class HeightAt>
glm::dvec3 planePenalty(const HeightAt &heightAt, const glm::dvec3 &hip, double h, double k)
{
    if (!std::isfinite(h) || h <= hip.z)
        return glm::dvec3{0.0};
    constexpr double e = 0.3e-3;
    const double hx0 = heightAt(hip.x - e, hip.y);
    const double hx1 = heightAt(hip.x + e, hip.y);
    const double hy0 = heightAt(hip.x, hip.y - e);
    const double hy1 = heightAt(hip.x, hip.y + e);
    glm::dvec3 n{0.0, 0.0, 1.0};
    if (std::isfinite(hx0) && std::isfinite(hx1) && std::isfinite(hy0) && std::isfinite(hy1)) {
        const glm::dvec3 g{-(hx1 - hx0) / (2 * e), -(hy1 - hy0) / (2 * e), 1.0};
        n = g / std::sqrt(g.x * g.x + g.y * g.y + g.z * g.z);
    }
    return k * (h - hip.z) * n.z * n;
}

/// \brief Thresholds of the figures (the defaults are the goals of docs/benchmarks.md).
struct FeelThresholds {
    double depthMargin = 1e-3;   ///< m, for pop-through and phantom force.
    double popForce = 0.1;       ///< N: under this while inside is pop-through.
    double phantomForce = 0.2;   ///< N: above this while outside is phantom force.
    double spikeStep = 0.5;      ///< N per update.
    double alternationStep = 0.05; ///< N per update: smallest change of an alternating run.
    double deviceMaxForce = 8.5;   ///< N (the Falcon): time at the maximum.
    /// N per update: the force stage's step limit (RendererConfig::maxForceStep); a force falling
    /// by it (within 1 %) is a release in progress, not phantom force.
    double forceStep = 2.0;
    /// m/s: a surface arriving faster than this covers the finger (a renderer that pushes the
    /// finger out at a bounded rate, 0.16 m/s for the finger renderer's defaults, cannot follow).
    double pushRate = 0.15;
};

/// \brief The figures of one run (or of several runs summed, see accumulate()).
struct FeelFigures {
    double seconds = 0.0;         ///< Time covered, s.
    double slidingSeconds = 0.0;  ///< Time marked sliding, s.
    std::size_t updates = 0;
    std::size_t trips = 0;        ///< Safety trips (released).
    std::size_t realCutTrips = 0; ///< Of them, at a real cut (surfaceCut).
    std::size_t arrivalTrips = 0; ///< Of them, not at a cut, while covered by an arriving surface.
    std::size_t falseTrips = 0;   ///< trips − realCutTrips − arrivalTrips.
    double coveredMs = 0.0;       ///< Time covered by an arriving surface, ms.
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
    double pressedSeconds = 0.0;  ///< Time marked pressed, sliding or held, s.
    std::size_t pressedSpikes = 0; ///< Spikes over those updates.
    double pressedSpikesPerSecond = 0.0;
    std::size_t idealSpikes = 0; ///< Spikes of the ideal penalty over the same updates.
    double idealSpikesPerSecond = 0.0;
    std::size_t reversalSpikes = 0;       ///< Sign-reversal spikes (every update).
    double reversalSpikesPerSecond = 0.0; ///< reversalSpikes / seconds.
    /// The sign-reversal spikes of the ideal penalty (FeelSample::idealPenalty, clamped to the
    /// device maximum) on the same path, beside the renderer's; 0 where it is not given. A spring
    /// that lets go as the hand leaves the surface drops its whole force in the update it is out:
    /// after a climb (a force that was rising) that drop is one (docs/benchmarks.md, "Lift-offs").
    std::size_t idealReversalSpikes = 0;
    double idealReversalSpikesPerSecond = 0.0; ///< idealReversalSpikes / seconds.
    std::size_t longestAlternation = 0;        ///< Updates, the longest alternating run.
    /// Updates, the longest alternating run of the ideal penalty (FeelSample::idealPenalty, clamped
    /// to the device maximum) on the same path, beside the renderer's; 0 where it is not given. A
    /// point's: deep under ridges finer than a fingertip (a keyboard's keys) its nearest surface
    /// point jumps between about equally near ones, so it runs longer than a fingertip's force
    /// would (docs/benchmarks.md, "Keys finer than a fingertip").
    std::size_t idealLongestAlternation = 0;
    std::size_t regainEvents = 0; ///< Occluders that left a held finger.
    std::size_t regainMissed = 0; ///< Of them, contact not regained before the hold ended.
    double regainMs = 0.0;        ///< The longest time to regain contact, ms (0: no event).
    double atMaxMs = 0.0;         ///< The longest time at the device maximum without a trip, ms.
    double pullDownMs = 0.0;      ///< Time with a downward force (Fz < −phantomForce), ms.
    /// Energy the commanded force put into the hand (PassivityObserver), mJ; summed by
    /// accumulate().
    double energyMj = 0.0;
    /// The same of the ideal penalty on the same path (FeelSample::idealPenalty), mJ; summed.
    double idealEnergyMj = 0.0;
    /// energyMj − idealEnergyMj of one run, mJ: what the renderer generated beyond the surface's
    /// own work; accumulate() keeps the largest of its runs (the worst stroke). NaN where no row
    /// gave the ideal penalty.
    double energyExcessMj = std::nan("");
    /// Of energyExcessMj, the part over the moves held under an ideal force within 30° of
    /// horizontal (its nearest point on a side, |F_z| < |F|/2, over `phantomForce`) while the
    /// renderer's force pointed more than 30° up or was under `phantomForce`: the yardstick's own
    /// jump to a side, which a proxy that does not pop through does not make, mJ. accumulate()
    /// keeps the worst stroke's (the run whose energyExcessMj it keeps). NaN with energyExcessMj.
    double energyExcessSidewaysMj = std::nan("");
    /// The largest energy the force had put into the hand at any time in one run, mJ (≥ 0;
    /// PassivityObserver::peak()); accumulate() keeps the largest.
    double energyPeakMj = 0.0;
    /// The largest change of the commanded force from one update (row) to the next, N: the
    /// demo's "no force step over 1 N per update" (issue goal); a trip's unload counts too.
    /// accumulate() keeps the largest.
    double maxStepN = 0.0;
    /// pressedSpikes / idealSpikes; NaN when the ideal penalty has no spike.
    [[nodiscard]] double spikeRatio() const noexcept
    {
        return idealSpikes > 0
                   ? static_cast<double>(pressedSpikes) / static_cast<double>(idealSpikes)
                   : std::nan("");
    }
};

/// \brief Computes the figures of one run of consecutive updates.
/// \param rows the updates in time order; the first row's force step is taken from zero.
[[nodiscard]] FeelFigures computeFeel(std::span<const FeelSample> rows,
                                      const FeelThresholds &thresholds = {});

/// \brief Adds \a run's counts and times to \a total (rates and percentiles recomputed from the
/// sums where they can be; ripple, update percentiles, the longest alternating run, the time to
/// regain contact and the time at the maximum: the worst of the two).
void accumulate(FeelFigures &total, const FeelFigures &run) noexcept;

} // namespace depthtouch::haptics
