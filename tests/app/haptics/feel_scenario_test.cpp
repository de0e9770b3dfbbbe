/// \file
/// \brief The failures on the feel bench's synthetic scenes (a Kinect-v1 sensor model, 8-bit
/// depth as encode makes it): the finger renderer meets every feel goal, and the renderer it
/// replaces
/// (`modified`, paper IV) fails on the same strokes. The kitchen is checked end to end by
/// bench_feel_realdata (tests/app/cli).

#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/haptics/feel_bench.h"
#include "depthtouch/haptics/feel_scenes.h"

namespace depthtouch::haptics::bench {
namespace {

/// The figures of \a setting on \a scene over the bench's strokes, summed, and the worst stroke's
/// spikes per second.
struct StrokesRun {
    FeelFigures total;
    double worstSpikes = 0.0;
};

StrokesRun runStrokes(const FeelScene &scene, const std::vector<Stroke> &strokes,
                      const FeelSetting &setting)
{
    auto results = runFeelStrokes(scene, strokes, setting);
    EXPECT_TRUE(results) << (results ? "" : results.error().what);
    StrokesRun r;
    if (!results)
        return r;
    for (const FeelStrokeResult &s : *results) {
        accumulate(r.total, s.figures);
        r.worstSpikes = std::max(r.worstSpikes, s.figures.spikesPerSecond);
    }
    const FeelFigures &f = r.total;
    std::printf("%-18s %-17s false trips %zu, pop-through %.0f ms, phantom %.0f ms, spikes %.2f/s "
                "(worst stroke %.2f/s), max %.2f N\n",
                scene.name.c_str(), setting.name.c_str(), f.falseTrips, f.popThroughMs, f.phantomMs,
                f.spikesPerSecond, r.worstSpikes, f.maxForce);
    return r;
}

FeelSetting setting(const char *name)
{
    for (const FeelSetting &s : feelSettings({Method::Finger, Method::Modified}))
        if (s.name == name)
            return s;
    ADD_FAILURE() << "no setting " << name;
    return {};
}

/// The figures of the bench's setting \a renderer on its family stroke \a name on the synthetic
/// \a which scene (8-bit, holes kept, placed as `bench feel` places it), printed; empty figures
/// (and a failure) when the scene or the stroke cannot be made.
FeelFigures familyStroke(SyntheticScene which, const std::string &name,
                         SensorModel sensor = SensorModel::StructuredLight,
                         const char *renderer = "finger", int bits = 8)
{
    SyntheticSceneOptions options;
    options.sensor = sensor;
    options.bits = bits;
    auto scene = makeSyntheticScene(which, options);
    EXPECT_TRUE(scene) << (scene ? "" : scene.error().what);
    std::vector<Stroke> strokes;
    if (scene)
        for (Stroke &s : makeFamilyStrokes(*scene, FamilyPlan{}))
            if (s.name == name)
                strokes.push_back(std::move(s));
    EXPECT_EQ(strokes.size(), 1u) << name;
    if (strokes.size() != 1u)
        return {};
    auto results = runFeelStrokes(*scene, strokes, setting(renderer));
    EXPECT_TRUE(results) << (results ? "" : results.error().what);
    if (!results)
        return {};
    const FeelFigures &f = results->front().figures;
    std::printf("%s, %s on %s: pop-through %.0f ms, longest alternating run %zu, %zu "
                "sign-reversal spikes, pull-down %.0f ms, max %.2f N, %zu trips\n",
                renderer, name.c_str(), scene->name.c_str(), f.popThroughMs, f.longestAlternation,
                f.reversalSpikes, f.pullDownMs, f.maxForce, f.trips);
    return f;
}

/// An occluder pushed the finger out (over 1 N) without a limit cycle: no alternating run longer
/// than the goal's, no false trip and, with \a noReversal, no sign-reversal spike.
void expectPushedOutSmoothly(const FeelFigures &f, bool noReversal)
{
    EXPECT_GT(f.maxForce, 1.0);
    EXPECT_LE(f.longestAlternation, FeelGoals{}.maxAlternation);
    EXPECT_EQ(f.falseTrips, 0u);
    if (noReversal) {
        EXPECT_EQ(f.reversalSpikes, 0u);
    }
}

/// The goals of docs/benchmarks.md (FeelGoals' defaults).
void expectGoalsMet(const StrokesRun &r)
{
    const FeelGoals goals;
    EXPECT_EQ(r.total.falseTrips, 0u);
    EXPECT_LE(r.total.popThroughMs, goals.maxPopThroughMs);
    EXPECT_LE(r.total.phantomMs, goals.maxPhantomMs);
    EXPECT_LE(r.total.spikesPerSecond, goals.maxSpikesPerSecond);
    EXPECT_LE(r.worstSpikes, goals.maxStrokeSpikesPerSecond);
    EXPECT_LE(r.total.maxForce, goals.deviceMaxForce + 1e-9);
}

class FeelScenarioTest : public ::testing::TestWithParam<SyntheticScene> {};

// Slides pressed 1 and 3 mm in at 5 and 10 cm/s, presses held still and strokes across the
// silhouettes: the finger renderer (touch's and play's default) meets every goal, with either
// re-engagement and with friction on the proxy (μs 0.5, μd 0.4); `modified` trips safety with no
// cut, sticks and slips (force spikes) and, on silhouettes, lets the finger through or pulls it
// back.
// On the depth as the older bench mapped it: holes filled by push-pull (keepHoles = false). With
// holes kept as the receiver sees them, and with the stroke families placed where the content is
// hardest, the finger misses goals: `depthtouch bench feel` shows where.
TEST_P(FeelScenarioTest, fingerMeetsTheFeelGoalsWhereModifiedFails)
{
    SyntheticSceneOptions options;
    options.keepHoles = false;
    auto scene = makeSyntheticScene(GetParam(), options);
    ASSERT_TRUE(scene) << scene.error().what;
    const std::vector<Stroke> strokes = makeStrokes(*scene);
    ASSERT_GE(strokes.size(), 9u);
    for (const char *name : {"finger", "finger-ramp", "finger-friction"}) {
        const StrokesRun finger = runStrokes(*scene, strokes, setting(name));
        expectGoalsMet(finger);
        // AND no worse than measured on these seeded scenes (worst stroke: table and head 0
        // spikes/s, forearm 1.0/s), by a margin of one spike per second: the goals above leave room
        // for regressions such as losing the local candidate beside a silhouette (forearm: 3/s)
        const double measured = GetParam() == SyntheticScene::Forearm ? 1.0 : 0.0;
        EXPECT_LE(finger.worstSpikes, measured + 1.0) << name;
    }
    const StrokesRun release = runStrokes(*scene, strokes, setting("modified-release"));
    EXPECT_GT(release.total.falseTrips, 0u);
    EXPECT_GT(release.total.spikesPerSecond, 2.0);
    EXPECT_GT(release.total.popThroughMs, 10.0);
    const StrokesRun ramp = runStrokes(*scene, strokes, setting("modified-ramp"));
    EXPECT_GT(ramp.total.falseTrips, 0u);
    EXPECT_GT(ramp.total.spikesPerSecond, 2.0);
    if (GetParam() == SyntheticScene::Forearm) { // pulled back through the forearm
        EXPECT_GT(ramp.total.phantomMs, 10.0);
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, FeelScenarioTest,
                         ::testing::Values(SyntheticScene::Table, SyntheticScene::Head,
                                           SyntheticScene::Forearm),
                         [](const auto &scene) {
                             return std::string(syntheticSceneName(scene.param)).substr(10);
                         });

// A height field pushes, it never pulls: over the bench's six stroke families on the synthetic
// head (swipes and circles across its silhouette, taps, presses, traces and holds), the finger's
// force never points down (Fz ≥ 0 on every update). Before, a glide toward a new optimum could end
// part-way down a side, under the HIP, and pull the finger down it: on this scene a circle and a
// swipe gave Fz of −1.0 and −1.7 N (and a 7-Scenes swipe −2.8 N).
TEST(FeelScenarioPushTest, theFingerNeverPullsDownOnTheBenchsStrokes)
{
    auto scene = makeSyntheticScene(SyntheticScene::Head);
    ASSERT_TRUE(scene) << scene.error().what;
    FamilyPlan plan;
    plan.places = 1;
    plan.moveSeconds = 0.6;
    const std::vector<Stroke> strokes = makeFamilyStrokes(*scene, plan);
    ASSERT_GE(strokes.size(), 10u);
    auto results = runFeelStrokes(*scene, strokes, setting("finger"), "|");
    ASSERT_TRUE(results) << results.error().what;
    double lowest = 0.0;
    std::string where;
    std::size_t updates = 0;
    for (const FeelStrokeResult &r : *results) {
        for (const FeelSample &row : r.log) {
            ++updates;
            if (row.force.z < lowest) {
                lowest = row.force.z;
                where = r.stroke;
            }
        }
    }
    std::printf("%zu strokes, %zu updates: lowest Fz %.3f N %s\n", results->size(), updates, lowest,
                where.c_str());
    EXPECT_GT(updates, 5000u);
    EXPECT_GE(lowest, 0.0) << where;
}

// A 6 mm press at 5 cm/s beside the synthetic head's contour (8-bit, holes kept, as `bench feel`
// places it): the stencil's descent stepped onto a patch of the contour whose kept taps (the side
// steeper than the outlier rule keeps, a hole beside it) span no plane; flat at their median, 0.1
// mm over the finger and nearer than the side it pressed into, it took the force to 0.1 N with the
// finger 6 mm inside the head: 42 ms of pop-through. The descent does not move onto a plane its
// taps do not span; the press meets the pop-through goal. (The bounded push, which turns at a
// bounded rate, now holds this press too: without the span rule it also meets the goal.)
TEST(FeelScenarioPushTest, aDeepPressBesideTheHeadsContourKeepsItsForce)
{
    const FeelFigures f = familyStroke(SyntheticScene::Head, "press 6.0 mm 5 cm/s edge");
    EXPECT_GT(f.updates, 0u);
    EXPECT_LE(f.popThroughMs, FeelGoals{}.maxPopThroughMs);
    EXPECT_EQ(f.falseTrips, 0u);
}

// A finger held 3 mm in beside the synthetic occluder (8-bit, holes kept, as `bench feel` places
// it) while the occluder sweeps over it: pushed out at a bounded rate, the candidate proxy took
// turns between the occluder's top straight above the HIP and a point on its flank, and the force
// changed direction every update (before: an alternating run of 9 updates, 16 sign-reversal
// spikes). Now the push follows the mean of the last two candidates and turns at a bounded rate:
// no run longer than the goal's, no sign reversal.
TEST(FeelScenarioPushTest, aHeldFingerPushedOutByAnOccluderDoesNotAlternate)
{
    expectPushedOutSmoothly(familyStroke(SyntheticScene::Occluder, "hold 3 mm under occluder"),
                            true);
    // The push's own bounded turn, without the offset filter's bound on the force's move.
    expectPushedOutSmoothly(familyStroke(SyntheticScene::Occluder, "hold 3 mm under occluder",
                                         SensorModel::StructuredLight, "finger-unfiltered"),
                            true);
}

// A 0.5 mm press at 5 cm/s beside the synthetic occluder seen through the active-stereo model
// (8-bit, holes kept, as `bench feel` places it). The occluder sweeps over the finger and pushes it
// out; the glide toward the proxy's new optimum started from the pushed proxy, which is off the
// surface (along the push), and ended alternately on the occluder's top and back on the plane it
// started on: the force's direction turned to and fro, an alternating run of 11 updates (13 on
// the 16-bit clip). The glide now starts from the last proxy on the surface, and while pushed it
// does not go back the way the last update's glide went.
TEST(FeelScenarioPushTest, aShallowPressUnderAPassingOccluderDoesNotAlternate)
{
    expectPushedOutSmoothly(
        familyStroke(SyntheticScene::Occluder, "press 0.5 mm 5 cm/s edge",
                     SensorModel::ActiveStereo, "finger-unfiltered"),
        false); // 2 sign-reversal spikes, with or without the glide from the surface
}

// A finger held 3 mm in under the synthetic occluder seen through the time-of-flight model: pushed
// out, the search from either side of a ridge of flying pixels ended on the other side, and the
// proxy glided 0.38 mm there and back every update (an alternating run of 17 updates, 2
// sign-reversal spikes, once the glide started from the surface). While pushed, a glide back the
// way the last one went waits an update: the proxy goes on toward the optimum it was heading for.
// Since the plane is kept on what was measured at its centre, the 8-bit clip's stroke no longer
// meets such a ridge; the 16-bit clip's does (a run of 7 without the rule, 3 with it).
TEST(FeelScenarioPushTest, aPushedFingerDoesNotGlideToAndFro)
{
    expectPushedOutSmoothly(familyStroke(SyntheticScene::Occluder, "hold 3 mm under occluder",
                                         SensorModel::TimeOfFlight, "finger-unfiltered"),
                            true);
    expectPushedOutSmoothly(familyStroke(SyntheticScene::Occluder, "hold 3 mm under occluder",
                                         SensorModel::TimeOfFlight, "finger-unfiltered", 16),
                            false); // 3 sign-reversal spikes, with or without the rule
}

// A 0.5 mm press at 5 cm/s beside the synthetic occluder's edge with a 1 mm fingertip (the
// bench's `finger-r1mm`). Beside the edge the glide toward a new optimum can end part-way down the
// occluder's side, under the HIP: the spring would pull the finger down it. A height field's
// surface pushes up, so the proxy is then put on the plane under the HIP (pushUp()): no update
// with the force pointing down. Without that: 58 ms of it (Fz under −0.2 N).
TEST(FeelScenarioPushTest, aThinFingerPressingBesideAnEdgeIsNeverPulledDownItsSide)
{
    const FeelFigures f = familyStroke(SyntheticScene::Occluder, "press 0.5 mm 5 cm/s edge",
                                       SensorModel::StructuredLight, "finger-r1mm");
    EXPECT_GT(f.maxForce, 1.0); // it did press
    EXPECT_EQ(f.pullDownMs, 0.0);
    EXPECT_EQ(f.falseTrips, 0u);
}

} // namespace
} // namespace depthtouch::haptics::bench
