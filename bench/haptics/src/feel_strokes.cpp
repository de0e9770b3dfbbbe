/// \file
/// \brief The feel bench's strokes: sampling a stroke over the reference surface and placing
/// strokes on a scene (see feel_scenes.h).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/feel_scenes.h"
#include "depthtouch/platform/enum_names.h"
#include "feel_families_internal.h"

namespace depthtouch::haptics::bench {

namespace {

using detail::Draws;

constexpr double kMargin = 4e-3;   ///< Slides keep this far inside the box, m.
constexpr double kStep = 0.5e-3;   ///< Path check spacing, m.
constexpr double kMaxRise = 1e-3;  ///< Largest reference change per kStep on a smooth slide, m.

using detail::pingPong;

double boxHeight(const FeelScene &s) noexcept
{
    return s.box.width * (s.height - 1) / (s.width - 1);
}

bool validAt(const FeelScene &s, const glm::dvec2 &p) noexcept
{
    const double px = (s.width - 1) / s.box.width;
    const int c = static_cast<int>(std::lround(p.x * px + 0.5 * (s.width - 1)));
    const int r = static_cast<int>(std::lround(0.5 * (s.height - 1) - p.y * px));
    for (int dr = -2; dr <= 2; ++dr)
        for (int dc = -2; dc <= 2; ++dc) {
            const int cc = c + dc;
            const int rr = r + dr;
            if (cc < 0 || rr < 0 || cc >= s.width || rr >= s.height || s.valid.empty() ||
                s.valid.at(cc, rr) == 0)
                return false;
        }
    return true;
}

/// True when the line from \a a to \a b stays inside the margin, over valid pixels and off
/// silhouettes of the reference at each of \a times.
bool lineOk(const FeelScene &s, ReferenceSurface &ref, const glm::dvec2 &a, const glm::dvec2 &b,
            std::initializer_list<double> times)
{
    const double len = glm::length(b - a);
    const int n = std::max(1, static_cast<int>(std::ceil(len / kStep)));
    const double hx = 0.5 * s.box.width - kMargin;
    const double hy = 0.5 * boxHeight(s) - kMargin;
    for (int i = 0; i <= n; ++i) {
        const glm::dvec2 p = a + (b - a) * (static_cast<double>(i) / n);
        if (std::fabs(p.x) > hx || std::fabs(p.y) > hy || !validAt(s, p))
            return false;
    }
    for (double t : times) {
        double prev = ref.height(t, a.x, a.y);
        for (int i = 1; i <= n; ++i) {
            const glm::dvec2 p = a + (b - a) * (static_cast<double>(i) / n);
            const double h = ref.height(t, p.x, p.y);
            if (!std::isfinite(h) || !std::isfinite(prev) || std::fabs(h - prev) > kMaxRise)
                return false;
            prev = h;
        }
    }
    return true;
}

/// Radius of the fingertip that traces a contour (a cross stroke), m.
/// \return the height of the bottom of a fingertip resting on the reference at time \a t over the
/// point \a along (m) of the line \a from → \a to (detail::rolledHeight(), 16 taps either side,
/// clamped to the line), m; NaN when the surface is nowhere under it.
double rolledHeight(ReferenceSurface &ref, double t, const glm::dvec2 &from, const glm::dvec2 &to,
                    double along)
{
    const double len = glm::length(to - from);
    const glm::dvec2 dir = len > 0.0 ? (to - from) / len : glm::dvec2(1.0, 0.0);
    return detail::rolledHeight(
        ref, t, [&](double d) { return from + dir * std::clamp(along + d, 0.0, len); }, 16);
}

/// A finger tracing a contour: it moves at \a speed along the 3-D path of the rolled height (up
/// a silhouette's side at the same speed as along the surface), ping-ponging over the line.
class ContourTracer {
public:
    ContourTracer(ReferenceSurface &ref, const glm::dvec2 &from, const glm::dvec2 &to, double speed)
        : ref_(ref), from_(from), to_(to), len_(glm::length(to - from)), speed_(speed)
    {
    }
    /// Advances to time \a t by \a dt (s; 0 = only place) and \return the HIP's x–y and the
    /// height it follows, m.
    glm::dvec3 step(double t, double dt)
    {
        const double target = rolledHeight(ref_, t, from_, to_, along_);
        if (!std::isfinite(z_))
            z_ = target;
        const double reach = speed_ * dt;
        if (std::isfinite(target) && std::fabs(target - z_) > reach) {
            z_ += target > z_ ? reach : -reach; // up or down a silhouette's side
        } else {
            if (std::isfinite(target))
                z_ = target;
            // Along the line, slower where the path is steep (constant speed in 3-D).
            const double ahead = rolledHeight(ref_, t, from_, to_, along_ + dir_ * 1e-4);
            const double slope =
                std::isfinite(ahead) && std::isfinite(target) ? (ahead - target) / 1e-4 : 0.0;
            along_ += dir_ * reach / std::sqrt(1.0 + slope * slope);
            if (along_ >= len_ || along_ <= 0.0) {
                along_ = std::clamp(along_, 0.0, len_);
                dir_ = -dir_;
            }
        }
        const glm::dvec2 xy = len_ > 0.0 ? from_ + (to_ - from_) * (along_ / len_) : from_;
        return {xy.x, xy.y, z_};
    }

private:
    ReferenceSurface &ref_;
    glm::dvec2 from_;
    glm::dvec2 to_;
    double len_;
    double speed_;
    double along_ = 0.0;
    double dir_ = 1.0;
    double z_ = std::nan("");
};

std::string label(const char *what, double depth, double speed, int k)
{
    char buf[96];
    if (speed > 0.0)
        std::snprintf(buf, sizeof buf, "%s d%.0fmm v%.0fcm/s #%d", what, depth * 1e3, speed * 1e2,
                      k);
    else
        std::snprintf(buf, sizeof buf, "%s d%.0fmm #%d", what, depth * 1e3, k);
    return buf;
}

} // namespace

const char *strokeKindName(StrokeKind kind) noexcept
{
    static constexpr std::array<const char *, 3> kNames = {"slide", "cross", "press"};
    return platform::enumName(kind, kNames, "?");
}

Stroke makeStroke(const FeelScene &scene, const StrokeSpec &spec, const StrokeTiming &tm,
                  double rate)
{
    Stroke out;
    out.name = spec.name;
    out.kind = spec.kind;
    out.depth = spec.depth;
    out.speed = spec.kind == StrokeKind::Press ? 0.0 : spec.speed;
    ReferenceSurface ref(scene);
    const double p0 = tm.rest;
    const double p1 = p0 + tm.press;
    const double p2 = p1 + tm.slide;
    const double p3 = p2 + tm.hold;
    const double p4 = p3 + tm.lift;
    const auto n = static_cast<std::size_t>(std::floor(tm.total() * rate + 1e-9)) + 1;
    out.samples.reserve(n);
    double lastH = ref.height(spec.startT, spec.from.x, spec.from.y);
    if (!std::isfinite(lastH))
        lastH = 0.0;
    const bool moves = spec.kind != StrokeKind::Press;
    ReferenceSurface traceRef(scene);
    ContourTracer tracer(traceRef, spec.from, spec.to, spec.speed);
    for (std::size_t k = 0; k < n; ++k) {
        const double tl = static_cast<double>(k) / rate;
        const double t = spec.startT + tl;
        const double travelled = moves ? spec.speed * std::clamp(tl - p1, 0.0, p2 - p1) : 0.0;
        glm::dvec2 xy = pingPong(spec.from, spec.to, travelled);
        double traced = std::nan("");
        if (spec.kind == StrokeKind::Cross) {
            // Across a silhouette the finger traces the contour (see ContourTracer).
            const bool sliding = tl >= p1 && tl < p2;
            const glm::dvec3 at = tracer.step(t, sliding ? 1.0 / rate : 0.0);
            xy = {at.x, at.y};
            traced = at.z;
        }
        double offset = tm.above;
        if (tl >= p0 && tl < p1)
            offset = tm.above + (-spec.depth - tm.above) * (tl - p0) / tm.press;
        else if (tl >= p1 && tl < p3)
            offset = -spec.depth;
        else if (tl >= p3 && tl < p4)
            offset = -spec.depth + (tm.above + spec.depth) * (tl - p3) / tm.lift;
        const double h = std::isfinite(traced) ? traced : ref.height(t, xy.x, xy.y);
        if (std::isfinite(h))
            lastH = h;
        StrokeSample s;
        s.t = t;
        s.hip = {xy.x, xy.y, lastH + offset};
        s.sliding = moves && tl >= p1 && tl < p2;
        s.held = (!moves && tl >= p1 && tl < p2) || (tl >= p2 && tl < p3);
        out.samples.push_back(s);
    }
    return out;
}

std::vector<Stroke> makeStrokes(const FeelScene &scene, const StrokePlan &plan)
{
    std::vector<Stroke> out;
    if (scene.frameCount() == 0)
        return out;
    StrokeTiming tm = plan.timing;
    const double others = tm.total() - tm.slide;
    tm.slide = std::max(0.3, std::min(tm.slide, scene.duration() - others));
    const double avail = std::max(0.0, scene.duration() - tm.total());
    int count = 0;
    const auto startAt = [&]() { return avail * std::fmod(0.618034 * count++, 1.0); };
    const double p1 = tm.rest + tm.press;
    Draws draws(plan.seed);
    ReferenceSurface ref(scene);
    const double hx = 0.5 * scene.box.width - kMargin;
    const double hy = 0.5 * boxHeight(scene) - kMargin;
    const auto place = [&](StrokeSpec spec, double reach) {
        for (int attempt = 0; attempt < 400; ++attempt) {
            spec.from = {(2.0 * draws.next() - 1.0) * hx, (2.0 * draws.next() - 1.0) * hy};
            const double a = 2.0 * 3.14159265358979 * draws.next();
            spec.to = spec.from + glm::dvec2{std::cos(a), std::sin(a)} * reach;
            const double t0 = spec.startT + p1;
            if (lineOk(scene, ref, spec.from, spec.to,
                       {t0, t0 + 0.5 * tm.slide, t0 + tm.slide + tm.hold})) {
                out.push_back(makeStroke(scene, spec, tm, plan.rate));
                return;
            }
        }
    };
    for (double d : plan.depths) {
        for (double v : plan.speeds) {
            for (int k = 0; k < plan.slidesPerSetting; ++k) {
                StrokeSpec spec{StrokeKind::Slide,          {}, {}, startAt(), d, v,
                                label("slide", d, v, k + 1)};
                place(spec, 0.5 * v * tm.slide);
            }
            if (!plan.crossings)
                continue;
            for (const SilhouetteCrossing &c : scene.crossings) {
                StrokeSpec spec{StrokeKind::Cross, c.from, c.to, startAt(), d, v,
                                label(("cross " + c.what).c_str(), d, v, 1)};
                out.push_back(makeStroke(scene, spec, tm, plan.rate));
            }
        }
        for (int k = 0; k < plan.presses; ++k) {
            StrokeSpec spec{
                StrokeKind::Press, {}, {}, startAt(), d, 0.0, label("press", d, 0.0, k + 1)};
            place(spec, 1e-3); // a 1 mm patch around the press point must be smooth and valid
        }
    }
    return out;
}

std::vector<TrajectorySample> toTrajectory(const Stroke &stroke)
{
    std::vector<TrajectorySample> out;
    out.reserve(stroke.samples.size());
    for (const StrokeSample &s : stroke.samples)
        out.push_back({s.t, s.hip.x, s.hip.y, s.hip.z});
    return out;
}

} // namespace depthtouch::haptics::bench
