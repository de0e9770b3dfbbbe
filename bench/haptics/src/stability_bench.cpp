#include "depthtouch/haptics/stability_bench.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <numbers>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/passivity.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/haptics/renderer_table.h"

namespace depthtouch::haptics::bench {

namespace {

constexpr int kFrameWidth = 160; // the depth frame of the plane: 0.63 mm pixels in the 0.1 m box
constexpr int kFrameHeight = 120;
constexpr int kRk4Steps = 16; // RK4 steps per servo period
constexpr const char *kWall = "wall";
constexpr const char *kUnfiltered = "finger-unfiltered"; // `bench feel`'s name for it too

/// The hand's acceleration, m/s², at position \a x and velocity \a v.
glm::dvec3 acceleration(const HandModel &hand, const glm::dvec3 &intent, const glm::dvec3 &force,
                        const glm::dvec3 &x, const glm::dvec3 &v) noexcept
{
    return (force - hand.damping * v - hand.stiffness * (x - intent)) / hand.mass;
}

/// The plane z = tan(slope)·x sampled into a Gray16 frame of the default scene box.
std::vector<std::uint16_t> planeFrame(const SceneBox &box, double slope)
{
    std::vector<std::uint16_t> px(static_cast<std::size_t>(kFrameWidth * kFrameHeight));
    const double spacing = box.width / (kFrameWidth - 1);
    for (int c = 0; c < kFrameWidth; ++c) {
        const double x = (c - (kFrameWidth - 1) * 0.5) * spacing;
        const double v = std::round((std::tan(slope) * x / box.depth + 0.5) * 65535.0);
        const auto code = static_cast<std::uint16_t>(std::clamp(v, 0.0, 65535.0));
        for (int r = 0; r < kFrameHeight; ++r)
            px[static_cast<std::size_t>(r * kFrameWidth + c)] = code;
    }
    return px;
}

/// What one run records per servo tick.
struct Trace {
    std::vector<double> penetration; // m, along the normal, positive inside
    std::vector<double> normalForce; // N
    std::vector<double> energy;      // J, the observer's E after the tick
};

/// \return the peak-to-peak of \a v over [from, from + count), m.
double peakToPeak(const std::vector<double> &v, std::size_t from, std::size_t count)
{
    const auto first = v.begin() + static_cast<std::ptrdiff_t>(from);
    const auto [lo, hi] = std::minmax_element(first, first + static_cast<std::ptrdiff_t>(count));
    return *hi - *lo;
}

/// Fills \a row's figures from \a trace (late window of \a late ticks, the earlier one
/// \a earlyGap ticks before it).
void judge(const Trace &trace, std::size_t late, std::size_t earlyGap, double period,
           const StabilityOptions &o, StabilityRow &row)
{
    const std::size_t n = trace.penetration.size();
    const std::size_t from = n - late;
    row.oscillation = peakToPeak(trace.penetration, from, late);
    row.oscillationEarly = peakToPeak(trace.penetration, from - earlyGap, late);
    double penSum = 0.0;
    double forceSum = 0.0;
    for (std::size_t i = from; i < n; ++i) {
        penSum += trace.penetration[i];
        forceSum += trace.normalForce[i];
    }
    row.penetrationMean = penSum / static_cast<double>(late);
    row.forceMean = forceSum / static_cast<double>(late);
    row.energyEnd = trace.energy.back();
    row.energyPeak = std::max(0.0, *std::max_element(trace.energy.begin(), trace.energy.end()));
    row.lateEnergy = trace.energy.back() - trace.energy[from - 1];
    if (row.oscillation >= o.tolerance) {
        row.outcome = row.oscillation < 0.5 * row.oscillationEarly ? "decaying" : "oscillates";
        return;
    }
    row.outcome = row.forceMean < 0.5 * row.forceExpected ? "let-through" : "settled";
    if (row.outcome != "settled")
        return;
    std::size_t contact = 0;
    while (contact < n && trace.penetration[contact] <= 0.0)
        ++contact;
    std::size_t last = contact;
    for (std::size_t i = contact; i < n; ++i)
        if (std::fabs(trace.penetration[i] - row.penetrationMean) > 0.5 * o.tolerance)
            last = i + 1;
    row.settleTime = static_cast<double>(last - contact) * period;
}

} // namespace

void stepHand(const HandModel &hand, const glm::dvec3 &intent, const glm::dvec3 &force,
              double period, int steps, HandState &s) noexcept
{
    const double h = period / steps;
    for (int i = 0; i < steps; ++i) {
        const glm::dvec3 a1 = acceleration(hand, intent, force, s.x, s.v);
        const glm::dvec3 v2 = s.v + 0.5 * h * a1;
        const glm::dvec3 a2 = acceleration(hand, intent, force, s.x + 0.5 * h * s.v, v2);
        const glm::dvec3 v3 = s.v + 0.5 * h * a2;
        const glm::dvec3 a3 = acceleration(hand, intent, force, s.x + 0.5 * h * v2, v3);
        const glm::dvec3 v4 = s.v + h * a3;
        const glm::dvec3 a4 = acceleration(hand, intent, force, s.x + h * v3, v4);
        s.x += h / 6.0 * (s.v + 2.0 * v2 + 2.0 * v3 + v4);
        s.v += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
    }
}

double colgateBound(double damping, double servoRate) noexcept
{
    return 2.0 * damping * servoRate;
}

double sampledSpringLimit(double mass, double damping, double servoRate) noexcept
{
    const double period = 1.0 / servoRate;
    const double a = damping / mass;
    const double e = std::exp(-a * period);
    return damping * (1.0 - e) / ((1.0 - e) / a - period * e);
}

StabilityRow runStabilityCase(const std::string &method, const StabilitySurface &surface,
                              double servoRate, double stiffness, const HandModel &hand,
                              const StabilityOptions &options)
{
    StabilityRow row;
    row.method = method;
    row.surface = surface.name;
    row.servoRate = servoRate;
    row.handDamping = hand.damping;
    row.stiffness = stiffness;
    row.colgateBound = colgateBound(hand.damping, servoRate);
    row.forceExpected = stiffness * hand.pressForce / (stiffness + hand.stiffness);

    const double slope = surface.slopeDeg * std::numbers::pi / 180.0;
    const glm::dvec3 normal(-std::sin(slope), 0.0, std::cos(slope));
    const glm::dvec3 origin(0.0);
    // The intent straight down, as deep along the normal as pressForce asks: on a slope the hand
    // also slides until its spring's pull along the plane is spent.
    const double depth = hand.pressForce / hand.stiffness;
    const glm::dvec3 intent = origin - glm::dvec3(0.0, 0.0, depth / std::cos(slope));
    HandState s;
    s.x = origin + hand.startHeight * normal;

    const double kRenderer = std::min(stiffness, scene::kMaxStiffness);
    row.workspaceScale = stiffness / kRenderer;
    const double scale = row.workspaceScale;
    std::unique_ptr<HapticRenderer> renderer;
    const std::vector<std::uint16_t> pixels = planeFrame(SceneBox{}, slope);
    if (method != kWall) {
        const bool unfiltered = method == kUnfiltered;
        const RendererEntry *entry =
            unfiltered ? &rendererEntry(Method::Finger) : findRenderer(method);
        if (entry == nullptr)
            return row; // outcome "": an unknown method (the sweep names only table rows)
        RendererConfig cfg = RendererConfig::forMethod(entry->method);
        cfg.stiffness = kRenderer;
        cfg.smoothOffset = !unfiltered;
        cfg.reengage = Reengage::Ramp; // as `play` runs it (RendererConfig::reengage)
        auto made = makeRenderer(entry->method, cfg, kFrameWidth, kFrameHeight);
        if (!made)
            return row;
        renderer = std::move(*made);
        const DepthFrameView view{reinterpret_cast<const std::uint8_t *>(pixels.data()),
                                  kFrameWidth,
                                  kFrameHeight,
                                  static_cast<std::size_t>(kFrameWidth) * 2,
                                  SampleFormat::Gray16,
                                  0.0};
        if (!renderer->setFrames(view, nullptr))
            return row;
        renderer->reset(origin + scale * (s.x - origin));
    }

    const double period = 1.0 / servoRate;
    const auto ticks = static_cast<std::size_t>(std::llround(options.duration * servoRate));
    const auto late = static_cast<std::size_t>(std::llround(options.lateWindow * servoRate));
    const auto earlyGap = static_cast<std::size_t>(std::llround(1.5 * servoRate));
    if (late < 1 || late + earlyGap >= ticks)
        return row; // outcome "": a run too short to judge
    Trace trace;
    trace.penetration.reserve(ticks);
    trace.normalForce.reserve(ticks);
    trace.energy.reserve(ticks);
    PassivityObserver observer;
    for (std::size_t n = 0; n < ticks; ++n) {
        const double pen = -glm::dot(normal, s.x - origin);
        glm::dvec3 force(0.0);
        if (renderer) {
            const HapticOutput out =
                renderer->update(origin + scale * (s.x - origin), static_cast<double>(n) * period);
            force = out.force;
            row.releases += out.released ? 1 : 0;
        } else if (pen > 0.0) {
            force = stiffness * pen * normal; // the ideal sampled spring: no limiter
        }
        observer.update(s.x, force);
        trace.penetration.push_back(pen);
        trace.normalForce.push_back(glm::dot(force, normal));
        trace.energy.push_back(observer.energy());
        stepHand(hand, intent, force, period, kRk4Steps, s);
    }
    judge(trace, late, earlyGap, period, options, row);
    return row;
}

std::vector<StabilityRow> runStabilitySweep(const StabilityOptions &options)
{
    std::vector<std::string> methods = options.methods;
    if (methods.empty()) {
        methods.emplace_back(kWall);
        for (const RendererEntry &e : rendererTable()) {
            methods.emplace_back(e.name);
            if (e.method == Method::Finger)
                methods.emplace_back(kUnfiltered);
        }
    }
    const StabilitySurface surfaces[] = {{"flat", 0.0}, {"sloped", 20.0}};
    const int steps = std::max(2, options.kSteps);
    std::vector<StabilityRow> rows;
    for (const std::string &method : methods)
        for (const StabilitySurface &surface : surfaces)
            for (const double rate : options.servoRates)
                for (const double b : options.dampings) {
                    HandModel hand;
                    hand.damping = b;
                    for (int i = 0; i < steps; ++i) {
                        const double k =
                            options.kMin * std::pow(options.kMax / options.kMin,
                                                    static_cast<double>(i) / (steps - 1));
                        rows.push_back(runStabilityCase(method, surface, rate, k, hand, options));
                    }
                }
    return rows;
}

std::vector<StabilityLimit> stabilityLimits(const std::vector<StabilityRow> &rows)
{
    std::vector<StabilityLimit> limits;
    for (const StabilityRow &r : rows) {
        if (limits.empty() || limits.back().method != r.method ||
            limits.back().surface != r.surface || limits.back().servoRate != r.servoRate ||
            limits.back().handDamping != r.handDamping) {
            limits.push_back(
                {r.method, r.surface, r.servoRate, r.handDamping, r.colgateBound, 0.0, 0.0});
        }
        StabilityLimit &l = limits.back();
        if (l.firstUnstable > 0.0)
            continue;
        if (r.stable())
            l.lastStable = r.stiffness;
        else
            l.firstUnstable = r.stiffness;
    }
    return limits;
}

} // namespace depthtouch::haptics::bench
