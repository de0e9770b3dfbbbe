/// \file
/// \brief `depthtouch bench feel`: the replays and the figures (see feel_bench.h); the outputs are
/// in feel_report.cpp.

#include "depthtouch/haptics/feel_bench.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/ball_ideal.h"
#include "depthtouch/haptics/renderer_table.h"
#include "depthtouch/platform/percentile.h"

namespace depthtouch::haptics::bench {

namespace {

using Clock = std::chrono::steady_clock;

/// Frame whose PTS is the last at or before \a t (as replay() picks them).
std::size_t frameAt(const FeelScene &scene, double t) noexcept
{
    const double f = std::floor(t * scene.fps + 1e-9);
    if (f <= 0.0)
        return 0;
    return std::min(scene.frameCount() - 1, static_cast<std::size_t>(f));
}

/// How many frames back surfaceRise() looks for the last measured surface across a hole.
constexpr int kRiseLookBackFrames = 30;

/// Sets \a row's surfaceRise (m): how far the reference under the HIP's x–y rose since the update
/// before (at \a prevT), or, where that update had a hole there (a stereo shadow or a
/// time-of-flight dropout runs ahead of a moving edge; a flickering pixel), since the last frame
/// it was measured there (feel.h). A surface back at its height after a dropout rose by nothing;
/// one that came over the finger while the hole hid it (no renderer sees it before it is back)
/// rose by the whole step in this update. None measured in the kRiseLookBackFrames before: not
/// known (NaN).
void surfaceRise(const FeelScene &scene, ReferenceSurface &ref, double prevT, const StrokeSample &s,
                 FeelSample &row)
{
    const double before = ref.height(prevT, s.hip.x, s.hip.y);
    if (!std::isnan(before) || std::isnan(row.surfaceZ)) {
        row.surfaceRise = row.surfaceZ - before;
        return;
    }
    const double frame = std::floor(prevT * scene.fps + 1e-9);
    for (int k = 0; k < kRiseLookBackFrames && frame - k >= 0.0; ++k) {
        const double tk = (frame - k) / scene.fps; // the start of a frame at or before prevT
        const double h = ref.height(tk, s.hip.x, s.hip.y);
        if (!std::isnan(h)) {
            row.surfaceRise = row.surfaceZ - h;
            return;
        }
    }
}

/// True when the surface over (x, y) steps by more than \a cut between frame i−1 and i or i and i+1
/// at any corner of the grid cell under it.
bool cutAt(const FeelScene &scene, const HeightField &field, std::size_t i, const glm::dvec3 &p,
           double cut)
{
    if (!field.contains(p.x, p.y))
        return false;
    const int c0 = std::min(static_cast<int>(field.xToColumn(p.x)), scene.width - 2);
    const int r0 = std::min(static_cast<int>(field.yToRow(p.y)), scene.height - 2);
    const DepthFrameView cur = scene.frame(i);
    for (int k = -1; k <= 1; k += 2) {
        if ((k < 0 && i == 0) || (k > 0 && i + 1 >= scene.frameCount()))
            continue;
        const DepthFrameView other = scene.frame(k < 0 ? i - 1 : i + 1);
        for (int dr = 0; dr <= 1; ++dr)
            for (int dc = 0; dc <= 1; ++dc)
                if (std::fabs(field.frameZ(cur, c0 + dc, r0 + dr) -
                              field.frameZ(other, c0 + dc, r0 + dr)) > cut)
                    return true;
    }
    return false;
}

/// The material track of the `finger-materials` setting: kFeelMaterialBlock-pixel squares
/// alternating skin and cloth (kFeelSkin, kFeelCloth), as RGB24 codes on the scene's grid.
std::vector<std::uint8_t> feelMaterial(int w, int h)
{
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) {
            const bool skin = (c / kFeelMaterialBlock + r / kFeelMaterialBlock) % 2 == 0;
            scene::encodeMaterial(skin ? kFeelSkin : kFeelCloth,
                                  &rgb[(static_cast<std::size_t>(r) * static_cast<std::size_t>(w) +
                                        static_cast<std::size_t>(c)) *
                                       3]);
        }
    return rgb;
}

/// The ideal ball's search in a logged stroke (ballIdealPenalty()): rings 0.1 mm apart in 32
/// directions, a quarter of its default's lookups (a 6 mm press reads about 10⁵ heights an update).
constexpr double kBallRing = 0.1e-3;
constexpr int kBallDirections = 32;

/// Replays one stroke on a fresh renderer; fills \a rows; with \a errors, the squared force
/// errors against the ideal penalty (feel.h planePenalty()) of the pressed updates; with \a ball,
/// the ideal ball's force of the renderer's fingertip radius (ball_ideal.h: slow, for a logged
/// stroke) in FeelSample::ballIdealPenalty.
Result<void> replayStroke(const FeelScene &scene, const Stroke &stroke, const FeelSetting &setting,
                          const RendererConfig &cfg, std::vector<FeelSample> &rows,
                          std::vector<double> *errors = nullptr, bool ball = false)
{
    const std::vector<std::uint8_t> material =
        setting.materials ? feelMaterial(scene.width, scene.height) : std::vector<std::uint8_t>{};
    const scene::MaterialView materialView{setting.materials ? material.data() : nullptr,
                                           static_cast<std::size_t>(scene.width) * 3};
    auto made = makeRenderer(setting.method, cfg, scene.width, scene.height);
    if (!made)
        return unexpected(made.error());
    HapticRenderer &r = **made;
    HeightField truth(scene.box);
    truth.setCutThreshold(cfg.cutThreshold);
    const double cut = truth.cutThreshold();
    ReferenceSurface ref(scene);
    rows.clear();
    rows.reserve(stroke.samples.size());
    std::size_t current = std::numeric_limits<std::size_t>::max();
    glm::dvec3 prevProxy = stroke.samples.front().hip;
    double prevT = stroke.samples.front().t;
    for (const StrokeSample &s : stroke.samples) {
        const std::size_t i = frameAt(scene, s.t);
        if (i != current) {
            DepthFrameView a = scene.frame(i);
            DepthFrameView b = i + 1 < scene.frameCount() ? scene.frame(i + 1) : DepthFrameView{};
            a.material = materialView;
            if (b.data != nullptr)
                b.material = materialView;
            const DepthFrameView *next = i + 1 < scene.frameCount() ? &b : nullptr;
            DT_TRY(r.setFrames(a, next));
            DT_TRY(truth.setFrames(a, next));
            if (current == std::numeric_limits<std::size_t>::max())
                r.reset(s.hip);
            current = i;
        }
        const auto t0 = Clock::now();
        const HapticOutput out = r.update(s.hip, s.t);
        const auto t1 = Clock::now();
        truth.setTime(s.t, true);
        FeelSample row;
        row.t = s.t;
        row.hip = s.hip;
        row.force = out.force;
        row.proxy = out.proxy;
        row.state = r.contactStateName();
        row.surfaceZ = ref.height(s.t, s.hip.x, s.hip.y);
        // A fingertip reaches what is within its radius.
        if (const double radius = r.fingertipRadius(); radius > 0.0)
            row.reachSurfaceZ =
                reachHeight([&](double x, double y) { return ref.height(s.t, x, y); }, s.hip.x,
                            s.hip.y, radius);
        row.idealPenalty = glm::dvec3{0.0};
        if (row.surfaceZ > s.hip.z) {
            // The ideal god-object: its proxy is the nearest surface point (energy, feel.h).
            glm::dvec3 nearest{s.hip.x, s.hip.y, row.surfaceZ};
            if (const HeightField *rf = ref.at(s.t); rf != nullptr)
                row.depthInside = nearestSurface(
                    [rf](double x, double y) {
                        return rf->contains(x, y) ? rf->heightAt(x, y) : std::nan("");
                    },
                    s.hip, row.surfaceZ - s.hip.z, &nearest);
            row.idealPenalty = cfg.stiffness * (nearest - s.hip);
            row.idealForce = cfg.stiffness * (row.surfaceZ - s.hip.z);
        } else {
            row.idealForce = 0.0;
        }
        if (ball && r.fingertipRadius() > 0.0)
            if (const HeightField *rf = ref.at(s.t); rf != nullptr)
                row.ballIdealPenalty = ballIdealPenalty(*rf, s.hip, r.fingertipRadius(),
                                                        cfg.stiffness, kBallRing, kBallDirections);
        if (prevT < s.t) // the surface under the HIP's x–y one update earlier
            surfaceRise(scene, ref, prevT, s, row);
        prevT = s.t;
        row.pressed = s.pressed;
        row.heldSurfaceZ = s.heldZ;
        if (errors != nullptr && (s.pressed || s.sliding || s.held))
            errors->push_back(glm::length(
                out.force -
                planePenalty([&ref, &s](double x, double y) { return ref.height(s.t, x, y); },
                             s.hip, row.surfaceZ, cfg.stiffness)));
        row.released = out.released;
        row.surfaceCut = cutAt(scene, truth, i, prevProxy, cut) ||
                         cutAt(scene, truth, i, out.proxy, cut) ||
                         cutAt(scene, truth, i, s.hip, cut);
        row.sliding = s.sliding;
        row.held = s.held;
        row.updateSeconds = std::chrono::duration<double>(t1 - t0).count();
        rows.push_back(row);
        prevProxy = out.proxy;
    }
    return {};
}

FeelRow summarise(const std::string &scene, const std::string &setting,
                  const std::vector<FeelStrokeResult> &results, const std::string &family = "all")
{
    FeelRow row;
    row.scene = scene;
    row.setting = setting;
    row.family = family;
    std::vector<double> times;
    for (const FeelStrokeResult &s : results) {
        if (s.setting != setting || (scene != "all" && s.scene != scene) ||
            (family != "all" && family != strokeFamilyName(s.family)))
            continue;
        ++row.strokes;
        times.insert(times.end(), s.updateSeconds.begin(), s.updateSeconds.end());
        accumulate(row.total, s.figures);
        if (s.figures.slidingSeconds > 0.0 &&
            s.figures.spikesPerSecond >= row.worstSpikesPerSecond) {
            row.worstSpikesPerSecond = s.figures.spikesPerSecond;
            row.worstStroke = s.scene == scene ? s.stroke : s.scene + ": " + s.stroke;
        }
    }
    row.total.updateP50 = platform::percentile(times, 0.5);
    row.total.updateP999 = platform::percentile(std::move(times), 0.999);
    const FeelFigures &t = row.total;
    row.realTripsPerSecond =
        t.slidingSeconds > 0.0 ? static_cast<double>(t.realCutTrips) / t.slidingSeconds : 0.0;
    return row;
}

} // namespace

std::vector<FeelSetting> feelSettings(const std::vector<Method> &methods)
{
    std::vector<FeelSetting> out;
    const auto wants = [&](Method m) {
        for (Method x : methods)
            if (x == m)
                return true;
        return false;
    };
    for (const RendererEntry &entry : rendererTable()) {
        const Method m = entry.method;
        if (!wants(m))
            continue;
        RendererConfig c = RendererConfig::forMethod(m);
        if (m == Method::Modified) {
            c.reengage = Reengage::Release;
            out.push_back({"modified-release", m, c});
            c.reengage = Reengage::Ramp;
            out.push_back({"modified-ramp", m, c});
            continue;
        }
        out.push_back({methodName(m), m, c});
        if (m == Method::Finger) {
            // What the offset filter takes out: the force on the search's own proxy.
            c.smoothOffset = false;
            out.push_back({"finger-unfiltered", m, c});
            c.smoothOffset = true;
            // The other contacts (renderer.h FingerContact; the default is the god-object): the
            // penalty while the HIP rests, and the penalty everywhere.
            const FingerContact contact = c.fingerContact;
            c.fingerContact = FingerContact::Adaptive;
            out.push_back({"finger-adaptive", m, c});
            c.fingerContact = FingerContact::Penalty;
            out.push_back({"finger-penalty", m, c});
            c.fingerContact = contact;
            // The player's re-engagement, and the finger's size either side of its default.
            c.reengage = Reengage::Ramp;
            out.push_back({"finger-ramp", m, c});
            c.reengage = Reengage::Release;
            c.staticFriction = kFeelStaticFriction;
            c.dynamicFriction = kFeelDynamicFriction;
            out.push_back({"finger-friction", m, c});
            c.staticFriction = 0.0;
            c.dynamicFriction = 0.0;
            out.push_back({"finger-materials", m, c, true});
            c.fingerRadius = 1.0e-3;
            out.push_back({"finger-r1mm", m, c});
            c.fingerRadius = 2.0e-3;
            out.push_back({"finger-r2mm", m, c});
        }
    }
    return out;
}

Result<std::vector<FeelStrokeResult>> runFeelStrokes(const FeelScene &scene,
                                                     const std::vector<Stroke> &strokes,
                                                     const FeelSetting &setting,
                                                     const std::string &dump, bool ballIdeal)
{
    RendererConfig cfg = setting.config;
    cfg.box = scene.box;
    DT_TRY(cfg.validate());
    std::vector<FeelStrokeResult> out;
    std::vector<FeelSample> rows;
    for (const Stroke &stroke : strokes) {
        if (stroke.samples.empty())
            continue;
        FeelStrokeResult r{scene.name,   setting.name, stroke.name, stroke.kind, stroke.family,
                           stroke.where, {},           {},          {}};
        const bool logged = !dump.empty() && r.key().find(dump) != std::string::npos;
        DT_TRY(replayStroke(scene, stroke, setting, cfg, rows, nullptr, logged && ballIdeal));
        r.figures = computeFeel(rows);
        r.updateSeconds.reserve(rows.size());
        for (const FeelSample &row : rows)
            r.updateSeconds.push_back(row.updateSeconds);
        if (logged)
            r.log = rows;
        out.push_back(std::move(r));
    }
    return out;
}

Result<double> cleanForceRms(const FeelScene &scene, const std::vector<Stroke> &strokes,
                             const FeelSetting &setting)
{
    RendererConfig cfg = setting.config;
    cfg.box = scene.box;
    DT_TRY(cfg.validate());
    std::vector<FeelSample> rows;
    std::vector<double> errors;
    for (const Stroke &stroke : strokes)
        if (!stroke.samples.empty())
            DT_TRY(replayStroke(scene, stroke, setting, cfg, rows, &errors));
    if (errors.empty())
        return std::nan("");
    double sq = 0.0;
    for (double e : errors)
        sq += e * e;
    return std::sqrt(sq / static_cast<double>(errors.size()));
}

std::vector<GoalVerdict> judgeGoals(const std::vector<FeelRow> &rows, const std::string &setting,
                                    const FeelGoals &g)
{
    std::vector<GoalVerdict> out;
    const auto judge = [&](const std::string &goal, double limit, auto figure) {
        GoalVerdict v{.goal = goal, .worst = 0.0, .where = "-", .met = true};
        const FeelRow *worst = nullptr;
        for (const FeelRow &r : rows) {
            if (r.setting != setting)
                continue;
            const double x = figure(r);
            if (std::isnan(x))
                continue;
            if (worst == nullptr || x > v.worst) {
                v.worst = x;
                v.where = r.scene + " / " + r.family;
                worst = &r;
            }
        }
        v.met = worst == nullptr || v.worst <= limit + 1e-9;
        out.push_back(v);
        return worst;
    };
    const auto dbl = [](std::size_t n) { return static_cast<double>(n); };
    char buf[96];
    judge("false trips = 0", 0.0, [&](const FeelRow &r) { return dbl(r.total.falseTrips); });
    std::snprintf(buf, sizeof buf, "pop-through <= %.0f ms", g.maxPopThroughMs);
    judge(buf, g.maxPopThroughMs, [](const FeelRow &r) { return r.total.popThroughMs; });
    std::snprintf(buf, sizeof buf, "phantom force <= %.0f ms", g.maxPhantomMs);
    judge(buf, g.maxPhantomMs, [](const FeelRow &r) { return r.total.phantomMs; });
    std::snprintf(buf, sizeof buf, "alternating run <= %zu updates", g.maxAlternation);
    if (const FeelRow *w = judge(buf, dbl(g.maxAlternation),
                                 [&](const FeelRow &r) { return dbl(r.total.longestAlternation); }))
        out.back().ideal = dbl(w->total.idealLongestAlternation);
    std::snprintf(buf, sizeof buf, "sign-reversal spikes <= %.0f/s", g.maxReversalsPerSecond);
    if (const FeelRow *w = judge(buf, g.maxReversalsPerSecond,
                                 [](const FeelRow &r) { return r.total.reversalSpikesPerSecond; }))
        out.back().ideal = w->total.idealReversalSpikesPerSecond;
    judge("spikes/s - ideal penalty's <= 0", 0.0, [](const FeelRow &r) {
        return r.total.pressedSpikesPerSecond - r.total.idealSpikesPerSecond;
    });
    std::snprintf(buf, sizeof buf, "spikes <= %.0f/s in holds, taps, presses",
                  g.maxStillSpikesPerSecond);
    judge(buf, g.maxStillSpikesPerSecond, [](const FeelRow &r) {
        return r.family == "hold" || r.family == "tap" || r.family == "press"
                   ? r.total.pressedSpikesPerSecond
                   : std::nan("");
    });
    std::snprintf(buf, sizeof buf, "regain contact <= %.0f ms", g.maxRegainMs);
    judge(buf, g.maxRegainMs, [](const FeelRow &r) {
        return r.total.regainEvents > 0 ? r.total.regainMs : std::nan("");
    });
    std::snprintf(buf, sizeof buf, "at %.1f N without a trip <= %.0f ms", g.deviceMaxForce,
                  g.maxAtMaxMs);
    judge(buf, g.maxAtMaxMs, [](const FeelRow &r) { return r.total.atMaxMs; });
    std::snprintf(buf, sizeof buf, "pull-down force <= %.0f ms", g.maxPullDownMs);
    judge(buf, g.maxPullDownMs, [](const FeelRow &r) { return r.total.pullDownMs; });
    std::snprintf(buf, sizeof buf, "energy - ideal penalty's <= %.2f mJ", g.maxExcessEnergyMj);
    if (const FeelRow *w = judge(buf, g.maxExcessEnergyMj,
                                 [](const FeelRow &r) { return r.total.energyExcessMj; });
        w != nullptr && !std::isnan(w->total.energyExcessSidewaysMj)) {
        std::snprintf(buf, sizeof buf, " (%.2f of it where the ideal's nearest point is on a side)",
                      w->total.energyExcessSidewaysMj);
        out.back().aside = buf;
    }
    return out;
}

FeelReport runFeelBenchmark(const std::vector<FeelScene> &scenes,
                            const std::vector<std::vector<Stroke>> &strokes,
                            const std::vector<FeelSetting> &settings,
                            const std::function<void(const std::string &)> &progress,
                            const std::vector<FeelScene> &clean,
                            const std::vector<std::vector<Stroke>> &cleanStrokes,
                            const std::string &dump, bool ballIdeal)
{
    FeelReport report;
    const auto start = Clock::now();
    std::vector<bool> failed(settings.size(), false);
    for (std::size_t s = 0; s < scenes.size() && s < strokes.size(); ++s) {
        if (strokes[s].empty()) {
            report.notes.push_back(scenes[s].name + ": no stroke could be placed");
            continue;
        }
        for (std::size_t k = 0; k < settings.size(); ++k) {
            if (failed[k])
                continue;
            auto r = runFeelStrokes(scenes[s], strokes[s], settings[k], dump, ballIdeal);
            if (!r) {
                failed[k] = true;
                report.notes.push_back(settings[k].name + ": skipped (" + r.error().what + ")");
                continue;
            }
            report.strokes.insert(report.strokes.end(), r->begin(), r->end());
            report.rows.push_back(summarise(scenes[s].name, settings[k].name, report.strokes));
            for (StrokeFamily fam : {StrokeFamily::Swipe, StrokeFamily::Press, StrokeFamily::Circle,
                                     StrokeFamily::Tap, StrokeFamily::Trace, StrokeFamily::Hold}) {
                FeelRow row = summarise(scenes[s].name, settings[k].name, report.strokes,
                                        strokeFamilyName(fam));
                if (row.strokes > 0)
                    report.familyRows.push_back(std::move(row));
            }
            if (progress)
                progress(scenes[s].name + " / " + settings[k].name + ": " +
                         std::to_string(r->size()) + " strokes");
        }
    }
    for (std::size_t k = 0; k < settings.size(); ++k)
        if (!failed[k])
            report.totals.push_back(summarise("all", settings[k].name, report.strokes));
    for (std::size_t k = 0; k < settings.size(); ++k) {
        if (failed[k])
            continue;
        double sq = 0.0;
        std::size_t n = 0;
        for (std::size_t c = 0; c < clean.size() && c < cleanStrokes.size(); ++c) {
            auto rms = cleanForceRms(clean[c], cleanStrokes[c], settings[k]);
            if (rms && std::isfinite(*rms)) {
                sq += *rms * *rms;
                ++n;
            }
        }
        report.cleanRms.emplace_back(settings[k].name,
                                     n > 0 ? std::sqrt(sq / static_cast<double>(n)) : std::nan(""));
        if (progress && n > 0)
            progress("clean geometry / " + settings[k].name);
    }
    report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return report;
}

} // namespace depthtouch::haptics::bench
