/// \file
/// \brief The feel bench's six stroke families (see feel_scenes.h, makeFamilyStrokes()): each
/// stroke's path and sampling, and the placer that puts them where the content is hardest, on the
/// silhouettes and feature pixels of feel_placement.cpp.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <functional>
#include <numbers>
#include <utility>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/feel_scenes.h"
#include "depthtouch/platform/enum_names.h"
#include "feel_families_internal.h"

namespace depthtouch::haptics::bench {

namespace {

using detail::Candidates;
using detail::Draws;
using detail::kMm;

using detail::kTipRadius;
constexpr double kRest = 0.05;          ///< Hover before and after a stroke, s.
constexpr double kAbove = 3e-3;         ///< Hover height, m.
constexpr double kApproachSpeed = 0.05; ///< Press-in and lift speed of all but the presses, m/s.
/// A moving stroke climbs (or steps down) a silhouette's side at most this many times faster than
/// it moves along (the hand lifts over an edge as it goes on: a fast stroke runs into the side).
constexpr double kClimb = 4.0;
/// A moving stroke's hand does not follow the rolled height's jitter update by update (the ball's
/// taps crossing hole pixels and noise: 0.1-0.2 mm up and down at 1 kHz over bonn-crowd's holes):
/// the height it follows moves only where the rolled height leaves a band of ± this around it (a
/// play operator), m.
constexpr double kPlay = 0.1e-3;

/// The frame whose PTS is the last at or before \a t.
std::size_t frameAt(const FeelScene &s, double t) noexcept
{
    const double f = std::floor(t * s.fps + 1e-9);
    return f <= 0.0 ? 0 : std::min(s.frameCount() - 1, static_cast<std::size_t>(f));
}

/// The height a held finger rests on: follows the reference while it drifts (at most kFollow
/// m/s, within kBand of the tracked height), goes down after it as it recedes (at kRecede m/s, a
/// press's speed: a hand does not fall 10 mm in one update when what it pressed on leaves or comes
/// back out of a hole lower), keeps its height while something rises over it (an occluder) or the
/// reference is a hole.
class HeldSurface {
public:
    static constexpr double kFollow = 0.03; ///< m/s.
    static constexpr double kBand = 1e-3;   ///< m.
    static constexpr double kRecede = 0.1;  ///< m/s, the fastest press (FamilyPlan::pressSpeeds).
    double step(double h, double dt) noexcept
    {
        if (!std::isfinite(z_)) {
            z_ = h;
        } else if (std::isfinite(h) && h <= z_ + kBand) {
            const double reach = kFollow * dt;
            z_ = h < z_ - kBand ? std::max(h, z_ - kRecede * dt)
                                : std::clamp(h, z_ - reach, z_ + reach);
        }
        return z_;
    }
    [[nodiscard]] double z() const noexcept { return z_; }

private:
    double z_ = std::nan("");
};

/// An x–y path parametrised by arc length (ping-pong lines, circles, a point).
struct Path {
    std::function<glm::dvec2(double)> at; ///< Position after travelling s, m.
};

Path linePath(glm::dvec2 from, glm::dvec2 to)
{
    return {[from, to](double s) { return detail::pingPong(from, to, s); }};
}

Path circlePath(glm::dvec2 centre, double radius, double phase)
{
    return {[centre, radius, phase](double s) {
        const double a = phase + s / radius;
        return centre + radius * glm::dvec2{std::cos(a), std::sin(a)};
    }};
}

/// The bottom of a fingertip resting on the reference over the path at \a s
/// (detail::rolledHeight(), 8 taps either side along the path), m; NaN when no surface is under it.
double rolledHeight(ReferenceSurface &ref, double t, const Path &path, double s)
{
    return detail::rolledHeight(
        ref, t, [&path, s](double d) { return path.at(s + d); }, 8);
}

/// What one stroke does, phase by phase.
struct Motion {
    StrokeFamily family = StrokeFamily::Hold;
    Path path{};         ///< x–y; a moving stroke's main phase travels it at `speed`.
    double speed = 0.0;  ///< m/s along the path (0: still).
    double depth = 1e-3; ///< m under the surface in the main phase.
    double approach = kApproachSpeed; ///< m/s, in and out.
    double main = 1.0;                ///< Main phase, s.
    double startT = 0.0;              ///< s.
};

/// Samples a stroke: hover, approach (from kAbove over the surface to `depth` under it), main
/// phase, lift, hover. Moving strokes go along their path at their speed and roll a fingertip over
/// the surface, climbing a silhouette's side at most kClimb times as fast; still ones rest on the
/// held surface (HeldSurface). Taps: the main phase is the taps themselves.
Stroke sampleStroke(const FeelScene &scene, const Motion &m, const FamilyPlan &plan)
{
    Stroke out;
    out.family = m.family;
    out.kind = m.speed > 0.0 ? StrokeKind::Slide : StrokeKind::Press;
    out.depth = m.depth;
    out.speed = m.speed;
    ReferenceSurface ref(scene);
    const bool tap = m.family == StrokeFamily::Tap;
    const double in = tap ? 0.0 : (kAbove + m.depth) / m.approach;
    const double p0 = kRest;
    const double p1 = p0 + in;
    const double p2 = p1 + m.main;
    const double p3 = p2 + in;
    const double total = p3 + kRest;
    const auto n = static_cast<std::size_t>(std::floor(total * plan.rate + 1e-9)) + 1;
    const double dt = 1.0 / plan.rate;
    out.samples.reserve(n);
    HeldSurface held;
    double s = 0.0;          // along the path
    double z = std::nan(""); // the rolled height followed by a moving stroke
    double lastH = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
        const double tl = static_cast<double>(k) * dt;
        const double t = m.startT + tl;
        const bool mainPhase = tl >= p1 && tl < p2;
        double base = std::nan("");
        if (m.speed > 0.0) {
            const double target = rolledHeight(ref, t, m.path, s);
            if (!std::isfinite(z))
                z = target;
            const double reach = m.speed * dt;
            const double climb = kClimb * reach;
            if (std::isfinite(target)) { // up or down a silhouette's side, also before and after
                const double follow = std::clamp(z, target - kPlay, target + kPlay);
                z += std::clamp(follow - z, -climb, climb);
            }
            if (mainPhase)
                s += reach;
            base = z;
        } else {
            const glm::dvec2 p = m.path.at(0.0);
            base = held.step(ref.height(t, p.x, p.y), dt);
        }
        if (std::isfinite(base))
            lastH = base;
        double offset = kAbove;
        if (tap) {
            if (mainPhase)
                offset =
                    kAbove - (kAbove + m.depth) * (0.5 - 0.5 * std::cos(2.0 * std::numbers::pi *
                                                                        plan.tapHz * (tl - p1)));
        } else if (tl >= p0 && tl < p1) {
            offset = kAbove - (kAbove + m.depth) * (tl - p0) / (p1 - p0);
        } else if (mainPhase) {
            offset = -m.depth;
        } else if (tl >= p2 && tl < p3) {
            offset = -m.depth + (kAbove + m.depth) * (tl - p2) / (p3 - p2);
        }
        const glm::dvec2 xy = m.path.at(s);
        StrokeSample smp;
        smp.t = t;
        smp.hip = {xy.x, xy.y, lastH + offset};
        smp.pressed = offset < 0.0;
        smp.sliding = mainPhase && m.speed > 0.0;
        smp.held = mainPhase && m.speed <= 0.0 && !tap;
        if (m.family == StrokeFamily::Hold && mainPhase)
            smp.heldZ = held.z();
        out.samples.push_back(smp);
    }
    return out;
}

/// \return the duration of a stroke of \a m (without its start time), s.
double strokeSeconds(const Motion &m) noexcept
{
    const double in = m.family == StrokeFamily::Tap ? 0.0 : (kAbove + m.depth) / m.approach;
    return 2.0 * kRest + 2.0 * in + m.main;
}

[[gnu::format(printf, 1, 2)]] std::string fmt(const char *f, ...)
{
    char buf[96];
    va_list args;
    va_start(args, f);
    std::vsnprintf(buf, sizeof buf, f, args);
    va_end(args);
    return buf;
}

/// Places one scene's strokes family by family (makeFamilyStrokes()): on a silhouette at the
/// stroke's time, or on a feature pixel of detail::placePixels(); seeded, in a fixed order (one
/// sequence of draws and start times for the scene).
class FamilyPlacer {
public:
    FamilyPlacer(const FeelScene &scene, const FamilyPlan &plan, std::vector<std::string> *notes)
        : scene_(scene), plan_(plan), notes_(notes), draws_(plan.seed), duration_(scene.duration()),
          w_(static_cast<std::size_t>(scene.width)), feat_(analyseScene(scene)), ref_(scene),
          pixels_(detail::placePixels(scene, feat_))
    {
    }
    void swipes();
    void presses();
    /// One circle at \a speed (m/s) around a silhouette point, its phase drawn, named \a name.
    void circle(double speed, const std::string &name);
    void circles();
    void traces();
    void taps();
    void holds();
    void fastStrokes();
    std::vector<Stroke> take() { return std::move(out_); }

private:
    /// \return the scene's crossing named \a what, or null.
    const SilhouetteCrossing *crossing(const char *what) const;
    void keysSwipe();
    void ridgePress();
    /// Sets a stroke's path on a silhouette point; false when the point does not suit it.
    using SetPath = std::function<bool(Motion &, const SilhouettePoint &)>;

    void note(const std::string &what);
    double startFor(double seconds);
    void onSilhouette(Motion m, double reach, const SetPath &set, const std::string &name);
    std::pair<glm::dvec2, bool> nearSide(const SilhouettePoint &e, double by, double t);
    void stillOnEdge(const Motion &m, double by, const std::string &name);
    bool stillAt(Motion m, std::size_t i, const std::string &name, const std::string &where,
                 double coverFrom = -1.0, double coverTo = -1.0);
    void drawAt(Candidates &from, Motion m, const std::string &name, const std::string &where);

    const FeelScene &scene_;
    const FamilyPlan &plan_;
    std::vector<std::string> *notes_;
    std::vector<Stroke> out_;
    Draws draws_;
    double duration_;
    int count_ = 0;
    std::size_t w_;
    SceneFeatures feat_;
    ReferenceSurface ref_;
    detail::PlacePixels pixels_;
};

void FamilyPlacer::note(const std::string &what)
{
    if (notes_ != nullptr)
        notes_->push_back(scene_.name + ": " + what);
}

/// Start times spread over the clip (golden-ratio sequence), so strokes meet different frames.
double FamilyPlacer::startFor(double seconds)
{
    const double avail = std::max(0.0, duration_ - seconds);
    return avail * std::fmod(0.618034 * count_++, 1.0);
}

/// Silhouette strokes: swipes across, circles around, traces along, presses and taps on the near
/// side. The silhouette is looked for at the start of the stroke's main phase.
void FamilyPlacer::onSilhouette(Motion m, double reach, const SetPath &set, const std::string &name)
{
    m.startT = startFor(strokeSeconds(m));
    const double tMain = m.startT + kRest + (kAbove + m.depth) / m.approach;
    std::vector<SilhouettePoint> edges =
        findSilhouettes(scene_, frameAt(scene_, tMain), 3e-3, reach + 5e-3);
    for (int attempt = 0; attempt < 40 && !edges.empty(); ++attempt) {
        const std::size_t k = draws_.pick(edges.size());
        if (!set(m, edges[k])) {
            edges[k] = edges.back();
            edges.pop_back();
            continue;
        }
        Stroke st = sampleStroke(scene_, m, plan_);
        st.name = name;
        st.where = "silhouette";
        out_.push_back(std::move(st));
        return;
    }
    note(name + ": no silhouette to place it on");
}

/// The near side of a silhouette, \a by m from the step; false when it is no surface there.
std::pair<glm::dvec2, bool> FamilyPlacer::nearSide(const SilhouettePoint &e, double by, double t)
{
    const glm::dvec2 p = e.at + e.up * by;
    return std::pair{p, std::isfinite(ref_.height(t, p.x, p.y))};
}

/// A still stroke (press, tap, hold) on a silhouette's near side, \a by m from the step.
void FamilyPlacer::stillOnEdge(const Motion &m, double by, const std::string &name)
{
    onSilhouette(
        m, 2 * kMm,
        [&](Motion &mm2, const SilhouettePoint &e) {
            const auto [p, ok] = nearSide(e, by, mm2.startT);
            mm2.path = linePath(p, p);
            return ok;
        },
        name);
}

/// A still stroke at pixel \a i; [\a coverFrom, \a coverTo]: the time the main phase must cover
/// (occluders; none when negative).
bool FamilyPlacer::stillAt(Motion m, std::size_t i, const std::string &name,
                           const std::string &where, double coverFrom, double coverTo)
{
    const int c = static_cast<int>(i % w_);
    const int r = static_cast<int>(i / w_);
    const glm::dvec2 p = detail::pixelXY(scene_, c, r);
    m.path = linePath(p, p);
    const double in = m.family == StrokeFamily::Tap ? 0.0 : (kAbove + m.depth) / m.approach;
    if (coverFrom >= 0.0) {
        // Press 0.4 s before the occluder comes, hold until 0.4 s after it has gone.
        m.startT = std::max(0.0, coverFrom - 0.4 - in - kRest);
        const double end = std::min(duration_, coverTo + 0.4);
        m.main = std::max(0.3, end - (m.startT + kRest + in));
    } else {
        m.startT = startFor(strokeSeconds(m));
    }
    if (!std::isfinite(ref_.height(m.startT, p.x, p.y)))
        return false;
    Stroke st = sampleStroke(scene_, m, plan_);
    st.name = name;
    st.where = where;
    out_.push_back(std::move(st));
    return true;
}

/// A still stroke on a pixel drawn from \a from (40 tries).
void FamilyPlacer::drawAt(Candidates &from, Motion m, const std::string &name,
                          const std::string &where)
{
    for (int attempt = 0; attempt < 40; ++attempt) {
        const std::size_t i = from.draw(draws_);
        if (i == static_cast<std::size_t>(-1))
            break;
        if (where == "occluder") {
            const double a = feat_.firstCovered.samples[i] / scene_.fps;
            const double b = feat_.lastCovered.samples[i] / scene_.fps;
            if (stillAt(m, i, name, where, a, b))
                return;
        } else if (stillAt(m, i, name, where)) {
            return;
        }
    }
    note(name + ": no " + where + " pixel to place it on");
}

void FamilyPlacer::swipes()
{
    for (double v : plan_.swipeSpeeds)
        for (int k = 0; k < plan_.places; ++k) {
            const Motion m{.family = StrokeFamily::Swipe,
                           .speed = v,
                           .depth = plan_.swipeDepth,
                           .main = plan_.moveSeconds};
            onSilhouette(
                m, plan_.swipeReach,
                [&](Motion &mm2, const SilhouettePoint &e) {
                    mm2.path =
                        linePath(e.at - e.up * plan_.swipeReach, e.at + e.up * plan_.swipeReach);
                    return true;
                },
                fmt("swipe %.0f cm/s #", v * 100) + std::to_string(k + 1));
        }
}

void FamilyPlacer::presses()
{
    for (double d : plan_.pressDepths)
        for (double v : plan_.pressSpeeds) {
            const Motion m{
                .family = StrokeFamily::Press, .depth = d, .approach = v, .main = plan_.pressHold};
            // Alternately on a silhouette's near side and beside a moving object.
            if (count_ % 2 == 0)
                stillOnEdge(m, 1 * kMm, fmt("press %.1f mm %.0f cm/s edge", d / kMm, v * 100));
            else
                drawAt(pixels_.moving, m, fmt("press %.1f mm %.0f cm/s moving", d / kMm, v * 100),
                       "moving");
        }
}

void FamilyPlacer::circle(double speed, const std::string &name)
{
    const Motion m{.family = StrokeFamily::Circle,
                   .speed = speed,
                   .depth = plan_.circleDepth,
                   .main = plan_.moveSeconds};
    const double phase = 2.0 * std::numbers::pi * draws_.next();
    onSilhouette(
        m, plan_.circleRadius + kTipRadius,
        [&](Motion &mm2, const SilhouettePoint &e) {
            // The circle's centre on the silhouette: it crosses it twice a turn.
            mm2.path = circlePath(e.at, plan_.circleRadius, phase);
            return true;
        },
        name);
}

void FamilyPlacer::circles()
{
    for (int k = 0; k < plan_.places; ++k)
        circle(plan_.circleSpeed,
               fmt("circle r%.0f mm #", plan_.circleRadius / kMm) + std::to_string(k + 1));
}

void FamilyPlacer::traces()
{
    for (double v : plan_.traceSpeeds) {
        const Motion m{.family = StrokeFamily::Trace,
                       .speed = v,
                       .depth = plan_.traceDepth,
                       .main = plan_.moveSeconds};
        onSilhouette(
            m, 10 * kMm,
            [&](Motion &mm2, const SilhouettePoint &e) {
                // Along an edge that stays put (an edge that sweeps past is a swipe's business).
                const float moved = feat_.motion.at(e.column, e.row);
                if (!(moved < 3e-3f))
                    return false;
                const auto [p, ok] = nearSide(e, 1 * kMm, mm2.startT);
                const glm::dvec2 along{-e.up.y, e.up.x};
                // The step must run on along the whole line.
                for (double k : {-8.0, -4.0, 4.0, 8.0}) {
                    const glm::dvec2 q = e.at + along * (k * kMm);
                    const glm::dvec2 hi = q + e.up * (1 * kMm);
                    const glm::dvec2 lo = q - e.up * (1.5 * kMm);
                    const double step =
                        ref_.height(mm2.startT, hi.x, hi.y) - ref_.height(mm2.startT, lo.x, lo.y);
                    if (!(step > 3 * kMm))
                        return false;
                }
                mm2.path = linePath(p - along * (8 * kMm), p + along * (8 * kMm));
                return ok;
            },
            fmt("trace %.0f cm/s", v * 100));
    }
}

void FamilyPlacer::taps()
{
    Candidates &holeBorder = pixels_.holeBorder;
    // Whole taps: one cut short would end at its bottom and the lift would jump to the hover.
    const double taps = std::max(1.0, std::round(plan_.moveSeconds * plan_.tapHz));
    for (int k = 0; k < plan_.places; ++k) {
        const Motion m{
            .family = StrokeFamily::Tap, .depth = plan_.tapDepth, .main = taps / plan_.tapHz};
        const std::string name = fmt("tap %.0f Hz ", plan_.tapHz);
        if (k % 2 == 1) {
            drawAt(holeBorder.empty() ? pixels_.moving : holeBorder, m,
                   name + (holeBorder.empty() ? "moving" : "hole border"),
                   holeBorder.empty() ? "moving" : "hole");
            continue;
        }
        stillOnEdge(m, 1 * kMm, name + "edge");
    }
}

void FamilyPlacer::holds()
{
    for (double d : plan_.holdDepths) {
        const Motion m{.family = StrokeFamily::Hold, .depth = d, .main = plan_.holdSeconds};
        const std::string depthName = fmt("hold %.0f mm ", d / kMm);
        drawAt(pixels_.moving, m, depthName + "beside moving", "moving");
        drawAt(pixels_.occluded, m, depthName + "under occluder", "occluder");
        drawAt(pixels_.flicker, m, depthName + "flicker", "flicker");
        drawAt(pixels_.holeBorder, m, depthName + "hole border", "hole");
        drawAt(pixels_.still, m, depthName + "still", "still");
        // On an edge: the near side of a silhouette, 0.5 mm from the step.
        stillOnEdge(m, 0.5 * kMm, depthName + "edge");
    }
}

/// The fast circle, the swipe along the keys and the press on the ridge (FamilyPlan::
/// fastCircleSpeed, keysSwipeSpeed, ridgePress), last and from draws of their own (seed + 101):
/// the strokes before them keep their places.
void FamilyPlacer::fastStrokes()
{
    draws_ = Draws(plan_.seed + 101);
    if (plan_.fastCircleSpeed > 0.0)
        circle(plan_.fastCircleSpeed, fmt("circle r%.0f mm %.0f cm/s #1", plan_.circleRadius / kMm,
                                          plan_.fastCircleSpeed * 100));
    keysSwipe();
    ridgePress();
}

const SilhouetteCrossing *FamilyPlacer::crossing(const char *what) const
{
    const auto c = std::find_if(scene_.crossings.begin(), scene_.crossings.end(),
                                [what](const SilhouetteCrossing &x) { return x.what == what; });
    return c == scene_.crossings.end() ? nullptr : &*c;
}

void FamilyPlacer::keysSwipe()
{
    const SilhouetteCrossing *keys = crossing("keys");
    if (plan_.keysSwipeSpeed <= 0.0 || keys == nullptr)
        return;
    Motion m{.family = StrokeFamily::Swipe,
             .path = linePath(keys->from, keys->to),
             .speed = plan_.keysSwipeSpeed,
             .depth = plan_.swipeDepth,
             .main = plan_.moveSeconds};
    m.startT = startFor(strokeSeconds(m));
    Stroke st = sampleStroke(scene_, m, plan_);
    st.name = fmt("swipe %.0f cm/s keys", plan_.keysSwipeSpeed * 100);
    st.where = "keys";
    out_.push_back(std::move(st));
}

void FamilyPlacer::ridgePress()
{
    const SilhouetteCrossing *ridge = crossing("ridge");
    if (!plan_.ridgePress || ridge == nullptr || plan_.pressDepths.empty() ||
        plan_.pressSpeeds.empty())
        return;
    const double d = plan_.pressDepths.back();
    const double v = plan_.pressSpeeds.front();
    const glm::dvec2 top = 0.5 * (ridge->from + ridge->to);
    Motion m{.family = StrokeFamily::Press,
             .path = linePath(top, top),
             .depth = d,
             .approach = v,
             .main = plan_.pressHold};
    m.startT = startFor(strokeSeconds(m));
    Stroke st = sampleStroke(scene_, m, plan_);
    st.name = fmt("press %.1f mm %.0f cm/s ridge", d / kMm, v * 100);
    st.where = "ridge";
    out_.push_back(std::move(st));
}

} // namespace

const char *strokeFamilyName(StrokeFamily family) noexcept
{
    static constexpr std::array<const char *, 7> kNames = {"-",   "swipe", "press", "circle",
                                                           "tap", "trace", "hold"};
    return platform::enumName(family, kNames, "?");
}

std::vector<Stroke> makeFamilyStrokes(const FeelScene &scene, const FamilyPlan &plan,
                                      std::vector<std::string> *notes)
{
    if (scene.frameCount() == 0)
        return {};
    FamilyPlacer placer(scene, plan, notes);
    placer.swipes();
    placer.presses();
    placer.circles();
    placer.traces();
    placer.taps();
    placer.holds();
    placer.fastStrokes();
    return placer.take();
}

} // namespace depthtouch::haptics::bench
