/// \file
/// \brief The feel figures of a haptic run (see feel.h).

#include "depthtouch/haptics/feel.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

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

void rates(FeelFigures &f) noexcept
{
    f.falseTrips = f.trips - f.realCutTrips;
    f.spikesPerSecond =
        f.slidingSeconds > 0.0 ? static_cast<double>(f.spikes) / f.slidingSeconds : 0.0;
    f.falseTripsPerSecond =
        f.slidingSeconds > 0.0 ? static_cast<double>(f.falseTrips) / f.slidingSeconds : 0.0;
}

} // namespace

FeelFigures computeFeel(std::span<const FeelSample> rows, const FeelThresholds &th)
{
    FeelFigures f;
    f.updates = rows.size();
    const std::vector<double> dt = rowDurations(rows);
    bool contacted = false;
    glm::dvec3 prevForce{0.0};
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const FeelSample &r = rows[i];
        const double force = glm::length(r.force);
        const bool offSurface = std::isnan(r.surfaceZ);
        f.seconds += dt[i];
        if (r.sliding)
            f.slidingSeconds += dt[i];
        if (r.released) {
            ++f.trips;
            if (r.surfaceCut)
                ++f.realCutTrips;
        }
        if (!offSurface && r.hip.z < r.surfaceZ && force >= th.popForce)
            contacted = true;
        const double inside = std::isnan(r.depthInside) ? r.surfaceZ - r.hip.z : r.depthInside;
        if (contacted && !offSurface && inside > th.depthMargin && force < th.popForce)
            f.popThroughMs += 1e3 * dt[i];
        if ((offSurface || r.hip.z > r.surfaceZ + th.depthMargin) && force > th.phantomForce)
            f.phantomMs += 1e3 * dt[i];
        if (r.sliding && glm::length(r.force - prevForce) > th.spikeStep)
            ++f.spikes;
        f.maxForce = std::max(f.maxForce, force);
        prevForce = r.force;
    }
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
    total.popThroughMs += run.popThroughMs;
    total.phantomMs += run.phantomMs;
    total.spikes += run.spikes;
    total.rippleRms = std::max(total.rippleRms, run.rippleRms);
    total.rippleRelative = std::max(total.rippleRelative, run.rippleRelative);
    total.maxForce = std::max(total.maxForce, run.maxForce);
    total.updateP50 = std::max(total.updateP50, run.updateP50);
    total.updateP999 = std::max(total.updateP999, run.updateP999);
    rates(total);
}

} // namespace depthtouch::haptics
