/// \file
/// \brief The feel figures of a haptic run (see feel.h).

#include "depthtouch/haptics/feel.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/passivity.h"
#include "depthtouch/platform/percentile.h"

namespace depthtouch::haptics {

namespace {

/// The time each row stands for, s: its step to the next row; the last row takes the median step
/// (0 for a single row). Negative steps (a clock that went back) count as 0.
std::vector<double> rowDurations(std::span<const FeelSample> rows)
{
    std::vector<double> d(rows.size(), 0.0);
    if (rows.size() < 2)
        return d;
    for (std::size_t i = 0; i + 1 < rows.size(); ++i)
        d[i] = std::max(0.0, rows[i + 1].t - rows[i].t);
    std::vector<double> steps(d.begin(), d.end() - 1);
    d.back() = platform::percentile(std::move(steps), 0.5);
    return d;
}

/// Ripple of |F| over the held rows: RMS about the mean and that RMS over the mean.
void ripple(std::span<const FeelSample> rows, FeelFigures &out)
{
    double sum = 0.0;
    std::size_t n = 0;
    for (const FeelSample &r : rows) {
        if (r.held) {
            sum += glm::length(r.force);
            ++n;
        }
    }
    if (n == 0)
        return;
    const double mean = sum / static_cast<double>(n);
    double sq = 0.0;
    for (const FeelSample &r : rows) {
        if (r.held) {
            const double e = glm::length(r.force) - mean;
            sq += e * e;
        }
    }
    out.rippleRms = std::sqrt(sq / static_cast<double>(n));
    out.rippleRelative = mean > 0.0 ? out.rippleRms / mean : 0.0;
}

void updatePercentiles(std::span<const FeelSample> rows, FeelFigures &out)
{
    std::vector<double> times;
    times.reserve(rows.size());
    for (const FeelSample &r : rows)
        if (r.updateSeconds > 0.0)
            times.push_back(r.updateSeconds);
    if (times.empty())
        return;
    out.updateP50 = platform::percentile(times, 0.5);
    out.updateP999 = platform::percentile(std::move(times), 0.999);
}

/// Occluders leaving a held finger (see feel.h): the longest time to regain contact.
class RegainTracker {
public:
    void row(const FeelSample &r, double force, const FeelThresholds &th, FeelFigures &f)
    {
        if (!std::isfinite(r.heldSurfaceZ)) {
            finish(r.t, f);
            // An occluder over the finger when the hold ended stays over it until the finger is
            // out of it (a hole hides it, it does not take it away).
            covered_ = covered_ && !(std::isfinite(r.surfaceZ) && r.hip.z >= r.surfaceZ);
            return;
        }
        const bool onHeld =
            std::isfinite(r.surfaceZ) && std::fabs(r.surfaceZ - r.heldSurfaceZ) <= th.depthMargin;
        const bool back = onHeld && r.hip.z < r.surfaceZ;
        if (!onHeld && (!std::isfinite(r.surfaceZ) || r.surfaceZ > r.heldSurfaceZ)) {
            if (waiting_) // the occluder came back before contact did
                finish(r.t, f);
            covered_ = true;
            return;
        }
        if (covered_ && back) {
            covered_ = false;
            waiting_ = true;
            since_ = r.t;
            ++f.regainEvents;
        }
        if (waiting_ && force >= th.popForce) {
            f.regainMs = std::max(f.regainMs, 1e3 * (r.t - since_));
            waiting_ = false;
        }
    }
    /// The hold (or the run) ended at \a t while waiting: missed.
    void finish(double t, FeelFigures &f)
    {
        if (!waiting_)
            return;
        f.regainMs = std::max(f.regainMs, 1e3 * (t - since_));
        ++f.regainMissed;
        waiting_ = false;
    }
    /// True while an occluder is over the held finger.
    [[nodiscard]] bool covered() const noexcept { return covered_; }

private:
    bool covered_ = false;
    bool waiting_ = false;
    double since_ = 0.0;
};

/// A surface arriving over the finger (see feel.h): the swept depth and whether it covers the HIP.
class ArrivalTracker {
public:
    void row(const FeelSample &r, double dt, const FeelThresholds &th) noexcept
    {
        // A hole hides what came over the finger, it does not take it away (as for the regain
        // of a held finger): the swept depth stays until the surface is measured again.
        if (std::isnan(r.surfaceZ))
            return;
        const double inside = r.surfaceZ - r.hip.z;
        if (!(inside > 0.0)) {
            swept_ = 0.0;
            return;
        }
        // Arriving faster than a bounded push-out could follow adds to the swept depth; a surface
        // that falls back takes its arrival away first.
        const double rise = std::isfinite(r.surfaceRise) ? r.surfaceRise : 0.0;
        const double push = th.pushRate * dt;
        const double gained = rise > push ? rise - push : std::min(rise, 0.0);
        swept_ = std::clamp(swept_ + gained, 0.0, inside);
    }
    [[nodiscard]] bool covered(const FeelThresholds &th) const noexcept
    {
        return swept_ > th.depthMargin;
    }

private:
    double swept_ = 0.0; // m
};

void rates(FeelFigures &f) noexcept
{
    const auto per = [](std::size_t n, double s) {
        return s > 0.0 ? static_cast<double>(n) / s : 0.0;
    };
    f.pressedSpikesPerSecond = per(f.pressedSpikes, f.pressedSeconds);
    f.idealSpikesPerSecond = per(f.idealSpikes, f.pressedSeconds);
    f.reversalSpikesPerSecond = per(f.reversalSpikes, f.seconds);
    f.idealReversalSpikesPerSecond = per(f.idealReversalSpikes, f.seconds);
    f.falseTrips = f.trips - f.realCutTrips - f.arrivalTrips;
    f.spikesPerSecond =
        f.slidingSeconds > 0.0 ? static_cast<double>(f.spikes) / f.slidingSeconds : 0.0;
    f.falseTripsPerSecond =
        f.slidingSeconds > 0.0 ? static_cast<double>(f.falseTrips) / f.slidingSeconds : 0.0;
}

/// \return the ideal penalty \a ideal (N; NaN: not given, then 0) as a device renders it:
/// clamped to \a maxForce.
glm::dvec3 renderedIdeal(const glm::dvec3 &ideal, double maxForce) noexcept
{
    if (!std::isfinite(ideal.x))
        return glm::dvec3{0.0};
    const double norm = glm::length(ideal);
    return norm > maxForce ? ideal * (maxForce / norm) : ideal;
}

/// \return the alternating run ending at an update whose force changed by \a step, the change
/// before it \a prevStep and the run ending there \a run (FeelFigures::longestAlternation: every
/// change over \a threshold and against the one before).
std::size_t alternationRun(std::size_t run, const glm::dvec3 &step, const glm::dvec3 &prevStep,
                           double threshold) noexcept
{
    if (!(glm::length(step) > threshold))
        return 0;
    const bool reverses = glm::dot(step, prevStep) < 0.0 && glm::length(prevStep) > threshold;
    return reverses && run > 0 ? run + 1 : 1;
}

/// \return whether a force change \a step (N) after \a prevStep is a sign-reversal spike: over
/// the spike step and against a change over the alternation step before it.
bool reversalSpike(const glm::dvec3 &step, const glm::dvec3 &prevStep,
                   const FeelThresholds &th) noexcept
{
    return glm::length(step) > th.spikeStep && glm::dot(step, prevStep) < 0.0 &&
           glm::length(prevStep) > th.alternationStep;
}

/// \return whether the forces held over the next move are the ideal's on a side and the
/// renderer's up or nothing (FeelFigures::energyExcessSidewaysMj): the ideal penalty \a ideal (N)
/// over `phantomForce` and within 30° of horizontal, the renderer's \a force (N) under
/// `phantomForce` or more than 30° up.
bool idealOnASide(const glm::dvec3 &force, const glm::dvec3 &ideal,
                  const FeelThresholds &th) noexcept
{
    const double i = glm::length(ideal);
    const double f = glm::length(force);
    return i > th.phantomForce && std::fabs(ideal.z) < 0.5 * i &&
           (f < th.phantomForce || force.z > 0.5 * f);
}

} // namespace

FeelFigures computeFeel(std::span<const FeelSample> rows, const FeelThresholds &th)
{
    FeelFigures f;
    f.updates = rows.size();
    const std::vector<double> dt = rowDurations(rows);
    bool contacted = false;
    glm::dvec3 prevForce{0.0};
    glm::dvec3 prevStep{0.0};
    double prevIdeal = 0.0;
    std::size_t run = 0; // the alternating run ending at this update
    glm::dvec3 prevIdealForce{0.0};
    glm::dvec3 prevIdealStep{0.0};
    std::size_t idealRun = 0; // the ideal penalty's alternating run ending at this update
    double atMax = 0.0;       // time at the maximum without a trip, ending at this update, ms
    RegainTracker regain;
    ArrivalTracker arrival;
    PassivityObserver energy;
    PassivityObserver idealEnergy;
    bool idealGiven = false;
    bool sideways = false;  // the forces held over the next move: the ideal's on a side
    double sidewaysJ = 0.0; // the excess over the moves held under such forces, J
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const FeelSample &r = rows[i];
        const double force = glm::length(r.force);
        const bool offSurface = std::isnan(r.surfaceZ);
        f.seconds += dt[i];
        if (r.sliding)
            f.slidingSeconds += dt[i];
        regain.row(r, force, th, f);
        const glm::dvec3 step = r.force - prevForce;
        const double stepLength = glm::length(step);
        if (i > 0)
            f.maxStepN = std::max(f.maxStepN, stepLength);
        if (reversalSpike(step, prevStep, th))
            ++f.reversalSpikes;
        run = alternationRun(run, step, prevStep, th.alternationStep);
        f.longestAlternation = std::max(f.longestAlternation, run);
        // The same run of the ideal penalty as a device renders it (clamped to its maximum): the
        // surface under the path, and the point's nearest-point jumps deep under fine ridges.
        const glm::dvec3 idealNow = renderedIdeal(r.idealPenalty, th.deviceMaxForce);
        const glm::dvec3 idealStep = idealNow - prevIdealForce;
        if (reversalSpike(idealStep, prevIdealStep, th))
            ++f.idealReversalSpikes;
        idealRun = alternationRun(idealRun, idealStep, prevIdealStep, th.alternationStep);
        f.idealLongestAlternation = std::max(f.idealLongestAlternation, idealRun);
        prevIdealForce = idealNow;
        prevIdealStep = idealStep;
        atMax =
            force >= th.deviceMaxForce * (1.0 - 1e-3) && !r.released ? atMax + 1e3 * dt[i] : 0.0;
        f.atMaxMs = std::max(f.atMaxMs, atMax);
        if (r.force.z < -th.phantomForce)
            f.pullDownMs += 1e3 * dt[i];
        const double ideal = std::isnan(r.idealForce) ? 0.0 : r.idealForce;
        if (r.pressed || r.sliding || r.held) {
            f.pressedSeconds += dt[i];
            if (stepLength > th.spikeStep)
                ++f.pressedSpikes;
            if (std::fabs(ideal - prevIdeal) > th.spikeStep)
                ++f.idealSpikes;
        }
        prevIdeal = ideal;
        prevStep = step;
        arrival.row(r, dt[i], th);
        const bool covered = regain.covered() || arrival.covered(th);
        if (covered) { // a renderer may push out at a bounded rate or let go: no energy is judged
            energy.breakPath();
            idealEnergy.breakPath();
            sideways = false;
        } else {
            idealGiven = idealGiven || std::isfinite(r.idealPenalty.x);
            const double before = energy.energy() - idealEnergy.energy();
            energy.update(r.hip, r.force);
            idealEnergy.update(r.hip, idealNow);
            if (sideways)
                sidewaysJ += energy.energy() - idealEnergy.energy() - before;
            sideways = idealOnASide(r.force, idealNow, th);
        }
        if (r.released) {
            ++f.trips;
            if (r.surfaceCut)
                ++f.realCutTrips;
            else if (covered)
                ++f.arrivalTrips;
        }
        if (covered) { // under an occluder or an arriving surface: neither pop-through nor phantom
            f.coveredMs += 1e3 * dt[i];
            prevForce = r.force;
            f.maxForce = std::max(f.maxForce, force);
            if (r.sliding && stepLength > th.spikeStep)
                ++f.spikes;
            continue;
        }
        if (!offSurface && r.hip.z < r.surfaceZ && force >= th.popForce)
            contacted = true;
        const double inside = std::isnan(r.depthInside) ? r.surfaceZ - r.hip.z : r.depthInside;
        if (contacted && !offSurface && inside > th.depthMargin && force < th.popForce)
            f.popThroughMs += 1e3 * dt[i];
        const double reach =
            std::isnan(r.reachSurfaceZ) ? r.surfaceZ : std::max(r.surfaceZ, r.reachSurfaceZ);
        const bool unloading = force < glm::length(prevForce) - 0.99 * th.forceStep;
        if (!offSurface && r.hip.z > reach + th.depthMargin && force > th.phantomForce &&
            !unloading)
            f.phantomMs += 1e3 * dt[i];
        if (r.sliding && glm::length(r.force - prevForce) > th.spikeStep)
            ++f.spikes;
        f.maxForce = std::max(f.maxForce, force);
        prevForce = r.force;
    }
    if (!rows.empty())
        regain.finish(rows.back().t + dt.back(), f);
    f.energyMj = 1e3 * energy.energy();
    f.energyPeakMj = 1e3 * energy.peak();
    f.idealEnergyMj = 1e3 * idealEnergy.energy();
    f.energyExcessMj = idealGiven ? f.energyMj - f.idealEnergyMj : std::nan("");
    f.energyExcessSidewaysMj = idealGiven ? 1e3 * sidewaysJ : std::nan("");
    ripple(rows, f);
    updatePercentiles(rows, f);
    rates(f);
    return f;
}

void accumulate(FeelFigures &total, const FeelFigures &run) noexcept
{
    total.seconds += run.seconds;
    total.slidingSeconds += run.slidingSeconds;
    total.updates += run.updates;
    total.trips += run.trips;
    total.realCutTrips += run.realCutTrips;
    total.arrivalTrips += run.arrivalTrips;
    total.coveredMs += run.coveredMs;
    total.popThroughMs += run.popThroughMs;
    total.phantomMs += run.phantomMs;
    total.spikes += run.spikes;
    total.rippleRms = std::max(total.rippleRms, run.rippleRms);
    total.rippleRelative = std::max(total.rippleRelative, run.rippleRelative);
    total.maxForce = std::max(total.maxForce, run.maxForce);
    total.updateP50 = std::max(total.updateP50, run.updateP50);
    total.updateP999 = std::max(total.updateP999, run.updateP999);
    total.pressedSeconds += run.pressedSeconds;
    total.pressedSpikes += run.pressedSpikes;
    total.idealSpikes += run.idealSpikes;
    total.reversalSpikes += run.reversalSpikes;
    total.idealReversalSpikes += run.idealReversalSpikes;
    total.longestAlternation = std::max(total.longestAlternation, run.longestAlternation);
    total.idealLongestAlternation =
        std::max(total.idealLongestAlternation, run.idealLongestAlternation);
    total.regainEvents += run.regainEvents;
    total.regainMissed += run.regainMissed;
    total.regainMs = std::max(total.regainMs, run.regainMs);
    total.atMaxMs = std::max(total.atMaxMs, run.atMaxMs);
    total.pullDownMs += run.pullDownMs;
    total.energyMj += run.energyMj;
    total.idealEnergyMj += run.idealEnergyMj;
    total.energyPeakMj = std::max(total.energyPeakMj, run.energyPeakMj);
    total.maxStepN = std::max(total.maxStepN, run.maxStepN);
    // The worst run's excess and its sideways part; NaN on either side: the other.
    if (!(total.energyExcessMj >= run.energyExcessMj) &&
        !(std::isnan(run.energyExcessMj) && !std::isnan(total.energyExcessMj))) {
        total.energyExcessMj = run.energyExcessMj;
        total.energyExcessSidewaysMj = run.energyExcessSidewaysMj;
    }
    rates(total);
}

} // namespace depthtouch::haptics
