/// \file
/// \brief The feel figures (feel.h) on hand-made rows, the Kinect-style sensor model
/// (depth_noise.h) and the feel bench's scenes and strokes (feel_scenes.h).

#include "depthtouch/haptics/feel.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "depthtouch/depth/occupancy.h"
#include "depthtouch/haptics/depth_noise.h"
#include "depthtouch/haptics/feel_scenes.h"

namespace depthtouch::haptics {
namespace {

/// \a n rows 1 ms apart, HIP 2 mm under a surface at z = 0, force 1 N up: a clean press.
std::vector<FeelSample> pressRows(std::size_t n)
{
    std::vector<FeelSample> rows(n);
    for (std::size_t i = 0; i < n; ++i) {
        rows[i].t = 1e-3 * static_cast<double>(i);
        rows[i].hip = {0.0, 0.0, -2e-3};
        rows[i].force = {0.0, 0.0, 1.0};
        rows[i].surfaceZ = 0.0;
    }
    return rows;
}

TEST(FeelTest, CleanPressHasNoFault)
{
    const FeelFigures f = computeFeel(pressRows(100));
    EXPECT_EQ(f.updates, 100u);
    EXPECT_NEAR(f.seconds, 0.1, 1e-12); // 99 steps + the median step for the last row
    EXPECT_EQ(f.trips, 0u);
    EXPECT_EQ(f.popThroughMs, 0.0);
    EXPECT_EQ(f.phantomMs, 0.0);
    EXPECT_EQ(f.spikes, 0u);
    EXPECT_DOUBLE_EQ(f.maxForce, 1.0);
}

TEST(FeelTest, TripsSplitIntoRealCutsAndFalse)
{
    auto rows = pressRows(100);
    for (auto &r : rows)
        r.sliding = true;
    rows[10].released = true;
    rows[20].released = true;
    rows[20].surfaceCut = true;
    rows[30].released = true;
    const FeelFigures f = computeFeel(rows);
    EXPECT_EQ(f.trips, 3u);
    EXPECT_EQ(f.realCutTrips, 1u);
    EXPECT_EQ(f.falseTrips, 2u);
    EXPECT_NEAR(f.falseTripsPerSecond, 2.0 / 0.1, 1e-9);
}

TEST(FeelTest, PopThroughCountsOnlyAfterFirstContact)
{
    auto rows = pressRows(100);
    for (std::size_t i = 0; i < 10; ++i)
        rows[i].force = {}; // inside but no force before any contact: not a pop-through
    for (std::size_t i = 50; i < 60; ++i)
        rows[i].force = {0.0, 0.0, 0.05}; // after contact, 2 mm in, 0.05 N: pop-through
    rows[70].hip.z = -0.5e-3;              // within the margin: not counted
    rows[70].force = {};
    const FeelFigures f = computeFeel(rows);
    EXPECT_NEAR(f.popThroughMs, 10.0, 1e-9);
}

TEST(FeelTest, PhantomForceAboveOrOffTheSurface)
{
    auto rows = pressRows(100);
    for (std::size_t i = 0; i < 5; ++i)
        rows[i].hip.z = 2e-3; // 2 mm above with 1 N: phantom
    rows[5].surfaceZ = std::nan(""); // no surface measured here: not judged
    rows[6].hip.z = 0.5e-3;          // within the margin
    rows[7].hip.z = 2e-3;
    rows[7].force = {0.0, 0.0, 0.15}; // under the phantom force threshold
    const FeelFigures f = computeFeel(rows);
    EXPECT_NEAR(f.phantomMs, 5.0, 1e-9);
}

// A fingertip leaving an edge: 2 mm above the surface under its centre, a surface within its
// reach at its own height still holds it (no phantom force); one whose reach is as low as its
// centre's does not (phantom). A release in progress: a 5 N force falling by the step limit (2 N
// an update) over a surface that vanished is no phantom until it stops falling that fast.
TEST(FeelTest, PhantomForceSparesAFingertipOnAnEdgeAndAReleaseInProgress)
{
    auto rows = pressRows(40);
    for (std::size_t i = 0; i < 5; ++i) {
        rows[i].hip.z = 2e-3;
        rows[i].reachSurfaceZ = 1.5e-3; // an edge within the radius, 0.5 mm under the HIP
    }
    for (std::size_t i = 5; i < 8; ++i) {
        rows[i].hip.z = 2e-3;
        rows[i].reachSurfaceZ = 0.0; // nothing higher within reach: phantom, 3 ms
    }
    rows[8].hip.z = -2e-3;
    rows[9].hip.z = -2e-3;
    rows[9].force = {0.0, 0.0, 5.0};
    const double falling[] = {3.0, 1.0, 0.5, 0.5}; // 2 N, 2 N, then 0.5 N an update: 2 ms
    for (std::size_t k = 0; k < 4; ++k) {
        rows[10 + k].hip.z = 2e-3;
        rows[10 + k].force = {0.0, 0.0, falling[k]};
    }
    const FeelFigures f = computeFeel(rows);
    EXPECT_NEAR(f.phantomMs, 3.0 + 2.0, 1e-9);
}

// A proxy alternating between two points every update: forces 1 N and 2.2 N in turn over 40
// updates (39 changes of 1.2 N, each against the one before), then steady.
TEST(FeelTest, AlternatingLogGivesItsRunLengthAndSignReversals)
{
    auto rows = pressRows(200);
    for (std::size_t i = 100; i < 140; ++i) {
        rows[i].force = {0.0, 0.0, i % 2 == 0 ? 1.0 : 2.2};
        rows[i].pressed = true;
    }
    FeelFigures f = computeFeel(rows);
    // Changes at rows 101..139 (39, alternating) and 140 (2.2 → 1, against 139's): 40 in a chain.
    EXPECT_EQ(f.longestAlternation, 40u);
    // Every change but the first reverses the one before and exceeds the 0.5 N spike step.
    EXPECT_EQ(f.reversalSpikes, 39u);
    EXPECT_NEAR(f.reversalSpikesPerSecond, 39.0 / 0.2, 1e-9);
    // Pressed spikes: the 1 N first row is not pressed; rows 101..139 are (39 spikes).
    EXPECT_EQ(f.pressedSpikes, 39u);
    EXPECT_NEAR(f.pressedSeconds, 0.040, 1e-9);

    // A single jump and return: a run of 2, one reversal.
    rows = pressRows(100);
    rows[50].force = {0.0, 0.0, 3.0};
    f = computeFeel(rows);
    EXPECT_EQ(f.longestAlternation, 2u);
    EXPECT_EQ(f.reversalSpikes, 1u);
    // A monotonic ramp is no alternation; small dither under the threshold is none either.
    rows = pressRows(100);
    for (std::size_t i = 0; i < 100; ++i)
        rows[i].force = {0.0, 0.0, 0.1 * static_cast<double>(i) + (i % 2 ? 0.02 : 0.0)};
    f = computeFeel(rows);
    EXPECT_EQ(f.reversalSpikes, 0u);
    EXPECT_LE(f.longestAlternation, 1u);
}

TEST(FeelTest, TheIdealPenaltysOwnAlternatingRunIsReportedBesideTheRenderers)
{
    // A swipe across ridges narrower than a servo period's travel: the ideal penalty leans +x, -x,
    // +x ... over rows 20..29 and is straight up before and after, while the renderer's force stays
    // 1 N straight up. The ideal's changes at rows 20..30 each point against the one before: a run
    // of 11; the renderer's only change is its first row's rise from zero, a run of 1.
    auto rows = pressRows(100);
    for (std::size_t i = 0; i < rows.size(); ++i)
        rows[i].idealPenalty = {i >= 20 && i < 30 ? (i % 2 == 0 ? 0.3 : -0.3) : 0.0, 0.0, 1.0};
    FeelFigures f = computeFeel(rows);
    EXPECT_EQ(f.longestAlternation, 1u);
    EXPECT_EQ(f.idealLongestAlternation, 11u);
    // Clamped as a device renders it: an ideal alternating 20, 30, 20 ... N up is 8.5 N throughout
    // at the device maximum (FeelThresholds::deviceMaxForce), no run.
    rows = pressRows(100);
    for (std::size_t i = 0; i < rows.size(); ++i)
        rows[i].idealPenalty = {0.0, 0.0, i % 2 == 0 ? 20.0 : 30.0};
    f = computeFeel(rows);
    EXPECT_EQ(f.idealLongestAlternation, 1u); // the first row's rise from zero only
    // Not given (NaN): no run; accumulate() keeps the worst run's.
    FeelFigures total;
    accumulate(total, computeFeel(pressRows(10)));
    EXPECT_EQ(total.idealLongestAlternation, 0u);
    auto ridged = pressRows(100);
    for (std::size_t i = 0; i < ridged.size(); ++i)
        ridged[i].idealPenalty = {i >= 20 && i < 30 ? (i % 2 == 0 ? 0.3 : -0.3) : 0.0, 0.0, 1.0};
    accumulate(total, computeFeel(ridged));
    accumulate(total, f);
    EXPECT_EQ(total.idealLongestAlternation, 11u);
}

// feel.h: a sign-reversal spike points against a change of more than alternationStep; a change of
// exactly alternationStep before it is not one (0.25 N: exact in binary, as is 1.25 N − 1 N).
TEST(FeelTest, ASignReversalNeedsAChangeBeforeItAboveTheAlternationStep)
{
    FeelThresholds th;
    th.alternationStep = 0.25;
    // GIVEN a steady 1 N that rises by exactly the alternation step at row 50, then drops to 0 N
    // at row 51 (a spike of 1.25 N, against the rise) and stays there
    auto rows = pressRows(100);
    rows[50].force = {0.0, 0.0, 1.25};
    for (std::size_t i = 51; i < rows.size(); ++i)
        rows[i].force = {};
    FeelFigures f = computeFeel(rows, th);
    // THEN the drop is a spike but no sign reversal, and no change makes an alternating run
    EXPECT_EQ(f.reversalSpikes, 0u);
    EXPECT_EQ(f.longestAlternation, 1u);
    // WHEN the rise is 0.5 N, over the step  THEN the drop reverses it: one reversal, a run of 2
    rows[50].force = {0.0, 0.0, 1.5};
    f = computeFeel(rows, th);
    EXPECT_EQ(f.reversalSpikes, 1u);
    EXPECT_EQ(f.longestAlternation, 2u);
}

// The ideal penalty lets go as the hand leaves: at row 60 it drops its whole 4 N in one update.
// After a climb (its force rising 0.06 N an update) that drop points against the rise: one
// sign-reversal spike of the ideal's, beside the renderer's own (none: it unloads 0.25 N an
// update). After a force held still, or one already falling (a surface receding), it is none.
TEST(FeelTest, TheIdealPenaltysSignReversalsAreCountedBesideTheRenderers)
{
    const auto liftOff = [](double slope) { // N an update before the lift-off
        auto rows = pressRows(100);
        for (std::size_t i = 0; i < rows.size(); ++i) {
            const double at = static_cast<double>(i);
            const double before = 4.0 + slope * (at - 59.0);
            rows[i].idealPenalty = {0.0, 0.0, i < 60 ? before : 0.0};
            rows[i].force = {0.0, 0.0, i < 60 ? before : std::max(0.0, 4.0 - 0.25 * (at - 59.0))};
        }
        return rows;
    };
    for (const double slope : {0.0, -0.06}) {
        const FeelFigures f = computeFeel(liftOff(slope));
        EXPECT_EQ(f.idealReversalSpikes, 0u) << slope;
        EXPECT_EQ(f.reversalSpikes, 0u) << slope;
    }
    const FeelFigures f = computeFeel(liftOff(0.06));
    EXPECT_EQ(f.idealReversalSpikes, 1u);
    EXPECT_NEAR(f.idealReversalSpikesPerSecond, 1.0 / f.seconds, 1e-12);
    EXPECT_EQ(f.reversalSpikes, 0u);
    // Not given (NaN, as for a log without the reference): none. accumulate() sums the runs.
    EXPECT_EQ(computeFeel(pressRows(10)).idealReversalSpikes, 0u);
    FeelFigures total;
    accumulate(total, f);
    accumulate(total, computeFeel(pressRows(10)));
    accumulate(total, f);
    EXPECT_EQ(total.idealReversalSpikes, 2u);
}

TEST(FeelTest, TimeAtTheDeviceMaximumWithoutATrip)
{
    auto rows = pressRows(100);
    for (std::size_t i = 20; i < 32; ++i) // 12 updates stuck at 8.5 N
        rows[i].force = {0.0, 0.0, 8.5};
    for (std::size_t i = 60; i < 70; ++i) // 10 at the maximum, but a trip at 65
        rows[i].force = {0.0, 8.5, 0.0};
    rows[65].released = true;
    FeelFigures f = computeFeel(rows);
    EXPECT_NEAR(f.atMaxMs, 12.0, 1e-9);
    FeelThresholds th;
    th.deviceMaxForce = 10.0; // the same log on a stronger device never reaches its maximum
    f = computeFeel(rows, th);
    EXPECT_EQ(f.atMaxMs, 0.0);
    FeelFigures total;
    accumulate(total, computeFeel(rows));
    accumulate(total, computeFeel(pressRows(10)));
    EXPECT_NEAR(total.atMaxMs, 12.0, 1e-9);
}

// A finger held 2 mm into a still backdrop at z = 0; an occluder 10 mm tall covers it from 100 to
// 200 ms (the surface over the HIP at z = 10 mm, the finger free: 0 N), then leaves; the force
// comes back at 235 ms: 35 ms to regain contact. No pop-through is counted under the occluder.
TEST(FeelTest, RegainTimeAfterAnOccluderLeaves)
{
    auto rows = pressRows(400);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        rows[i].heldSurfaceZ = 0.0;
        rows[i].held = true;
        if (i >= 100 && i < 200)
            rows[i].surfaceZ = 10e-3;
        if (i >= 100 && i < 235)
            rows[i].force = {};
    }
    FeelFigures f = computeFeel(rows);
    EXPECT_EQ(f.regainEvents, 1u);
    EXPECT_EQ(f.regainMissed, 0u);
    EXPECT_NEAR(f.regainMs, 35.0, 1e-9);
    EXPECT_NEAR(f.popThroughMs, 35.0, 1e-9); // 200..234: back on the held surface, no force
    // Never regained: the time to the end of the hold, counted as missed.
    for (std::size_t i = 235; i < 300; ++i)
        rows[i].force = {};
    for (std::size_t i = 300; i < rows.size(); ++i)
        rows[i].heldSurfaceZ = std::nan(""); // the hold ends at 300 ms
    f = computeFeel(rows);
    EXPECT_EQ(f.regainEvents, 1u);
    EXPECT_EQ(f.regainMissed, 1u);
    EXPECT_NEAR(f.regainMs, 100.0, 1e-9);
    // A hole under the finger (no surface) is an occluder too; no event without one.
    rows = pressRows(100);
    for (auto &r : rows)
        r.heldSurfaceZ = 0.0;
    f = computeFeel(rows);
    EXPECT_EQ(f.regainEvents, 0u);
    EXPECT_EQ(f.regainMs, 0.0);
}

// A person walks in front of a finger pressed 2 mm into a backdrop at z = 0: the surface over the
// HIP's x–y rises 25 mm in 10 ms (2.5 m/s, far faster than the 0.15 m/s a bounded push-out
// follows), the finger is let go (a trip, 0 N) and stays 27 mm inside the person; the person
// leaves at 150 ms. Covered: no pop-through, the trip is an arrival trip, not a false one. Back
// on the backdrop at 150 ms with no force, pop-through counts again (from 150 to 199 ms).
TEST(FeelTest, ASurfaceArrivingOverTheFingerCoversIt)
{
    auto rows = pressRows(200);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const double k = static_cast<double>(i);
        rows[i].surfaceZ = i < 40 || i >= 150 ? 0.0 : std::min(25e-3, 2.5e-3 * (k - 39.0));
        rows[i].surfaceRise = i == 0 ? std::nan("") : rows[i].surfaceZ - rows[i - 1].surfaceZ;
        if (i >= 42)
            rows[i].force = {};
    }
    rows[42].released = true;
    FeelFigures f = computeFeel(rows);
    EXPECT_EQ(f.trips, 1u);
    EXPECT_EQ(f.arrivalTrips, 1u);
    EXPECT_EQ(f.falseTrips, 0u);
    EXPECT_NEAR(f.popThroughMs, 50.0, 1e-9); // 150..199: the backdrop is back, no force
    EXPECT_NEAR(f.coveredMs, 110.0, 1e-9);   // 40..149

    // The same rise at 0.1 m/s (0.1 mm an update) is a surface a renderer must push out of: not
    // covered, so the same let-go is a false trip and its pop-through counts.
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const double k = static_cast<double>(i);
        rows[i].surfaceZ = i < 40 || i >= 150 ? 0.0 : std::min(25e-3, 0.1e-3 * (k - 39.0));
        rows[i].surfaceRise = i == 0 ? std::nan("") : rows[i].surfaceZ - rows[i - 1].surfaceZ;
    }
    f = computeFeel(rows);
    EXPECT_EQ(f.arrivalTrips, 0u);
    EXPECT_EQ(f.falseTrips, 1u);
    EXPECT_EQ(f.coveredMs, 0.0);
    EXPECT_NEAR(f.popThroughMs, 158.0, 1e-9); // 42..199: 2 mm and more inside, no force
}

// An object whose stereo shadow runs ahead of it: under a finger pressed 2 mm into a backdrop at
// z = 0 the surface is a hole (no depth) from 40 to 59 ms, then the object appears at 16 mm, 18 mm
// over the HIP, and stays. The renderer pushes the finger out at a bounded rate, reaches the
// device maximum and lets go at 100 ms: the object rose 16 mm over the finger in the update it
// came out of the hole (no renderer saw it come), so the trip is an arrival trip, not a false
// one, and 18 mm inside it is no pop-through. A pixel that drops out and comes back at its own
// height (a flickering hole border) rose by nothing: the same let-go there is a false trip and
// its pop-through counts; so does one back 0.5 mm higher (under the 1 mm margin).
TEST(FeelTest, ASurfaceComingOverTheFingerWhileAHoleHidItCoversIt)
{
    const auto run = [](double appearsAt, std::size_t holeEnd) {
        auto rows = pressRows(holeEnd + 140);
        for (std::size_t i = 0; i < rows.size(); ++i) {
            rows[i].surfaceZ = i < 40 ? 0.0 : i < holeEnd ? std::nan("") : appearsAt;
            if (i == holeEnd) // the bench's surfaceRise across the hole: since 39 ms
                rows[i].surfaceRise = appearsAt - rows[39].surfaceZ;
            else if (i > 0)
                rows[i].surfaceRise = rows[i].surfaceZ - rows[i - 1].surfaceZ;
            if (i >= holeEnd + 40)
                rows[i].force = {};
        }
        rows[holeEnd + 40].released = true;
        return computeFeel(rows);
    };
    FeelFigures f = run(16e-3, 60);
    EXPECT_EQ(f.trips, 1u);
    EXPECT_EQ(f.arrivalTrips, 1u);
    EXPECT_EQ(f.falseTrips, 0u);
    EXPECT_EQ(f.popThroughMs, 0.0);
    EXPECT_NEAR(f.coveredMs, 140.0, 1e-9); // 60..199
    // However long the hole hid it: 200 ms of hole, then 16 mm over the finger.
    f = run(16e-3, 240);
    EXPECT_EQ(f.arrivalTrips, 1u);
    EXPECT_NEAR(f.coveredMs, 140.0, 1e-9);
    for (const double back : {0.0, 0.5e-3}) {
        f = run(back, 60);
        EXPECT_EQ(f.arrivalTrips, 0u) << back;
        EXPECT_EQ(f.falseTrips, 1u) << back;
        EXPECT_EQ(f.coveredMs, 0.0) << back;
        EXPECT_NEAR(f.popThroughMs, 100.0, 1e-9) << back; // 100..199: inside with no force
    }
}

// A held finger (2 mm into a surface at z = 0, held from 0 to 99 ms) that an object covers from
// 50 ms on (20 mm over the surface, the finger let go behind it) and that lifts out through the
// object after the hold: 2 mm an update from 100 ms, out of it at 111 ms. The object is over the
// finger until it is out: no pop-through after the hold either. With no object, the same lift
// with no force counts as pop-through while the HIP is over 1 mm inside (100 ms only).
TEST(FeelTest, AnOccluderOverAHeldFingerCoversItUntilItIsOut)
{
    const auto run = [](bool object) {
        auto rows = pressRows(130);
        for (std::size_t i = 0; i < rows.size(); ++i) {
            const double k = static_cast<double>(i);
            rows[i].heldSurfaceZ = i < 100 ? 0.0 : std::nan("");
            rows[i].surfaceZ = object && i >= 50 ? 20e-3 : 0.0;
            if (i >= 100)
                rows[i].hip.z = -2e-3 + 2e-3 * (k - 99.0);
            if (object && i >= 50)
                rows[i].force = {};
        }
        return computeFeel(rows);
    };
    FeelFigures f = run(true);
    EXPECT_EQ(f.popThroughMs, 0.0);
    f = run(false);
    EXPECT_NEAR(f.popThroughMs, 0.0, 1e-9); // a 1 N press, lifted: force until it is out
    auto rows = pressRows(130);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        rows[i].heldSurfaceZ = i < 100 ? 0.0 : std::nan("");
        if (i >= 100)
            rows[i].force = {};
    }
    f = computeFeel(rows);
    EXPECT_NEAR(f.popThroughMs, 30.0, 1e-9); // 100..129: 2 mm inside with no force
}

// A height field only pushes: 12 updates of a force pointing down by more than the phantom
// threshold (0.2 N), wherever the HIP is, are 12 ms of pull-down force; 0.1 N down is not counted.
TEST(FeelTest, ADownwardForceIsPullDown)
{
    auto rows = pressRows(100);
    for (std::size_t i = 20; i < 32; ++i)
        rows[i].force = {0.3, 0.0, -0.5};
    for (std::size_t i = 50; i < 60; ++i)
        rows[i].force = {0.0, 0.0, -0.1};
    const FeelFigures f = computeFeel(rows);
    EXPECT_NEAR(f.pullDownMs, 12.0, 1e-9);
    FeelFigures total;
    accumulate(total, f);
    accumulate(total, f);
    EXPECT_NEAR(total.pullDownMs, 24.0, 1e-9);
}

// The ideal penalty's spikes on the same updates: a 1 mm step under the finger at 800 N/m is a
// 0.8 N step of the ideal force, so a renderer that steps with it is no worse than the ideal.
TEST(FeelTest, IdealPenaltySpikesOnTheSamePath)
{
    auto rows = pressRows(100);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        rows[i].pressed = i > 0;
        rows[i].idealForce = i < 50 ? 1.6 : 2.4;
        rows[i].force = {0.0, 0.0, i < 50 ? 1.6 : 2.4};
    }
    FeelFigures f = computeFeel(rows);
    EXPECT_EQ(f.idealSpikes, 1u);
    EXPECT_EQ(f.pressedSpikes, 1u);
    EXPECT_DOUBLE_EQ(f.spikeRatio(), 1.0);
    for (std::size_t i = 0; i < rows.size(); ++i)
        rows[i].idealForce = 2.0;
    f = computeFeel(rows);
    EXPECT_EQ(f.idealSpikes, 0u);
    EXPECT_TRUE(std::isnan(f.spikeRatio()));
}

TEST(FeelTest, SpikesOnlyWhileSliding)
{
    auto rows = pressRows(100);
    for (std::size_t i = 40; i < 60; ++i)
        rows[i].sliding = true;
    rows[45].force = {0.0, 0.6, 1.0}; // |ΔF| = 0.6 in and 0.6 out: two spikes while sliding
    rows[80].force = {0.0, 0.0, 3.0}; // a step, but not sliding
    rows[0].sliding = true;            // the first row steps from zero: 1 N is a spike
    const FeelFigures f = computeFeel(rows);
    EXPECT_EQ(f.spikes, 3u);
    EXPECT_NEAR(f.slidingSeconds, 0.021, 1e-9);
    EXPECT_DOUBLE_EQ(f.maxForce, 3.0);
}

TEST(FeelTest, LargestForceStepPerUpdate)
{
    // The demo's goal reads the largest |ΔF| between consecutive updates: the first row's rise
    // from zero is not a step of the run, a step anywhere else is, sliding or not.
    auto rows = pressRows(100); // 1 N throughout
    FeelFigures f = computeFeel(rows);
    EXPECT_DOUBLE_EQ(f.maxStepN, 0.0);
    rows[30].force = {0.3, 0.4, 1.0};  // |ΔF| = 0.5 in, 0.5 out
    rows[70].force = {-0.6, 0.0, 1.8}; // |ΔF| = 1.0 in, 1.0 out
    f = computeFeel(rows);
    EXPECT_NEAR(f.maxStepN, 1.0, 1e-12);
    FeelFigures total;
    accumulate(total, computeFeel(pressRows(10)));
    accumulate(total, f);
    EXPECT_NEAR(total.maxStepN, 1.0, 1e-12); // the worst run's
}

TEST(FeelTest, RippleWhileHeld)
{
    auto rows = pressRows(100);
    for (std::size_t i = 0; i < 100; ++i) {
        rows[i].held = i >= 50;
        rows[i].force = {0.0, 0.0, i >= 50 ? (i % 2 ? 1.1 : 0.9) : 5.0};
    }
    const FeelFigures f = computeFeel(rows);
    EXPECT_NEAR(f.rippleRms, 0.1, 1e-9);
    EXPECT_NEAR(f.rippleRelative, 0.1, 1e-9);
}

TEST(FeelTest, UpdatePercentilesAndAccumulate)
{
    auto rows = pressRows(1000);
    for (std::size_t i = 0; i < rows.size(); ++i)
        rows[i].updateSeconds = i == 999 ? 50e-6 : 1e-6;
    const FeelFigures f = computeFeel(rows);
    EXPECT_DOUBLE_EQ(f.updateP50, 1e-6);
    EXPECT_DOUBLE_EQ(f.updateP999, 1e-6); // nearest rank 999 of 1000
    FeelFigures total;
    accumulate(total, f);
    accumulate(total, f);
    EXPECT_EQ(total.updates, 2000u);
    EXPECT_NEAR(total.seconds, 2.0, 1e-9);
    EXPECT_DOUBLE_EQ(total.updateP999, f.updateP999);
}

// --- Sensor model --------------------------------------------------------------------------------

depth::Plane<float> flat(double z, int w = 64, int h = 48)
{
    return depth::Plane<float>(w, h, static_cast<float>(z));
}

TEST(DepthNoiseTest, QuantisationStepGrowsWithZSquared)
{
    bench::KinectNoiseOptions o;
    for (double z : {1.0, 2.0, 3.0}) {
        // Two neighbouring representable depths differ by about 2.85e-3·z².
        const double a = bench::quantiseDisparity(z, o.disparityStep);
        const double b = bench::quantiseDisparity(a * (1.0 + 2.85e-3 * z), o.disparityStep);
        EXPECT_NEAR(b - a, 2.85e-3 * z * z, 0.1 * 2.85e-3 * z * z) << z;
    }
}

TEST(DepthNoiseTest, FlickerIsNonzeroAndScalesWithZSquared)
{
    bench::KinectNoiseOptions o;
    o.speckleProbability = 0.0;
    const auto spread = [&](double z) {
        const auto a = bench::applyKinectNoise(flat(z), o, 0);
        double s = 0.0;
        double s2 = 0.0;
        for (auto v : a.samples) {
            s += v;
            s2 += static_cast<double>(v) * v;
        }
        const double n = static_cast<double>(a.size());
        return std::sqrt(s2 / n - (s / n) * (s / n)) * 1e-3; // m
    };
    const double s1 = spread(1.0);
    const double s2 = spread(2.0);
    EXPECT_GT(s1, 0.5e-3);
    EXPECT_NEAR(s2 / s1, 4.0, 1.2);
    // Frame to frame the same pixel changes.
    const auto f0 = bench::applyKinectNoise(flat(2.0), o, 0);
    const auto f1 = bench::applyKinectNoise(flat(2.0), o, 1);
    EXPECT_NE(f0.samples, f1.samples);
}

TEST(DepthNoiseTest, DeterministicPerSeed)
{
    bench::KinectNoiseOptions o;
    auto z = flat(1.5);
    for (int y = 0; y < z.height; ++y)
        for (int x = 30; x < z.width; ++x)
            z.at(x, y) = 1.0f;
    const auto a = bench::applyKinectNoise(z, o, 3);
    const auto b = bench::applyKinectNoise(z, o, 3);
    EXPECT_EQ(a.samples, b.samples);
    o.seed = 2;
    const auto c = bench::applyKinectNoise(z, o, 3);
    EXPECT_NE(a.samples, c.samples);
}

TEST(DepthNoiseTest, HolesSitAtSilhouettes)
{
    bench::KinectNoiseOptions o;
    o.speckleProbability = 0.0;
    auto z = flat(2.0, 128, 64);
    for (int y = 0; y < z.height; ++y)
        for (int x = 64; x < z.width; ++x)
            z.at(x, y) = 1.0f; // near on the right: a shadow on the far side left of x = 64
    const auto n = bench::applyKinectNoise(z, o, 0);
    std::size_t nearEdge = 0;
    std::size_t elsewhere = 0;
    for (int y = 0; y < n.height; ++y)
        for (int x = 0; x < n.width; ++x)
            if (n.at(x, y) == 0)
                (std::abs(x - 63) <= 25 ? nearEdge : elsewhere)++;
    // Shadow 585·0.075·(1 − 0.5) ≈ 22 px on every row.
    EXPECT_GE(nearEdge, static_cast<std::size_t>(20 * n.height));
    EXPECT_EQ(elsewhere, 0u);
}

// --- Scenes and strokes
// ----------------------------------------------------------------------------

/// The largest rise of the reference along the line over 0.5 mm (a silhouette step), m.
double largestStep(bench::ReferenceSurface &ref, double t, glm::dvec2 a, glm::dvec2 b)
{
    const int n = static_cast<int>(glm::length(b - a) / 0.5e-3);
    double best = 0.0;
    double prev = ref.height(t, a.x, a.y);
    for (int i = 1; i <= n; ++i) {
        const glm::dvec2 p = a + (b - a) * (static_cast<double>(i) / n);
        const double h = ref.height(t, p.x, p.y);
        best = std::max(best, std::fabs(h - prev));
        prev = h;
    }
    return best;
}

/// \a scene without depth noise, \a seconds (s) long, at its default size.
Result<bench::FeelScene> noiselessScene(bench::SyntheticScene scene, double seconds)
{
    bench::SyntheticSceneOptions o;
    o.seconds = seconds;
    o.noisy = false;
    return bench::makeSyntheticScene(scene, o);
}

TEST(FeelScenesTest, HeadSceneIsGray8WithAStepOfThirteenToTwentyMillimetres)
{
    auto s = noiselessScene(bench::SyntheticScene::Head, 0.2);
    ASSERT_TRUE(s) << s.error().what;
    EXPECT_EQ(s->format, SampleFormat::Gray8);
    EXPECT_EQ(s->frameCount(), 6u);
    ASSERT_FALSE(s->crossings.empty());
    bench::ReferenceSurface ref(*s);
    for (const auto &c : s->crossings) {
        const double step = largestStep(ref, 0.1, c.from, c.to);
        EXPECT_GT(step, 13e-3) << c.what;
        EXPECT_LT(step, 20e-3) << c.what;
    }
}

TEST(FeelScenesTest, ForearmIsAboutNineMillimetresWide)
{
    auto s = noiselessScene(bench::SyntheticScene::Forearm, 0.1);
    ASSERT_TRUE(s) << s.error().what;
    ASSERT_FALSE(s->crossings.empty());
    bench::ReferenceSurface ref(*s);
    const auto &c = s->crossings.front();
    const double base = ref.height(0.0, c.from.x, c.from.y);
    double width = 0.0;
    double top = -1.0;
    const int n = 2000;
    for (int i = 0; i <= n; ++i) {
        const glm::dvec2 p = c.from + (c.to - c.from) * (static_cast<double>(i) / n);
        const double h = ref.height(0.0, p.x, p.y);
        top = std::max(top, h - base);
        if (h - base > 5e-3)
            width += glm::length(c.to - c.from) / n;
    }
    EXPECT_NEAR(width, 9e-3, 1.5e-3);
    EXPECT_GT(top, 10e-3);
    const double step = largestStep(ref, 0.0, c.from, c.to);
    EXPECT_GT(step, 8e-3);
    EXPECT_LT(step, 20e-3);
}

TEST(FeelScenesTest, StrokesFollowTheSurfaceAndMarkPhases)
{
    bench::SyntheticSceneOptions o;
    o.seconds = 2.0;
    o.width = 320;
    o.height = 240;
    auto s = bench::makeSyntheticScene(bench::SyntheticScene::Table, o);
    ASSERT_TRUE(s) << s.error().what;
    const auto strokes = bench::makeStrokes(*s);
    ASSERT_GE(strokes.size(), 8u);
    bench::ReferenceSurface ref(*s);
    for (const auto &st : strokes) {
        std::size_t sliding = 0;
        std::size_t held = 0;
        for (const auto &p : st.samples) {
            sliding += p.sliding;
            held += p.held;
            if (p.sliding || p.held) {
                EXPECT_NEAR(p.hip.z, ref.height(p.t, p.hip.x, p.hip.y) + (-st.depth), 1e-9)
                    << st.name;
            }
        }
        EXPECT_GE(held, 400u) << st.name;
        if (st.kind != bench::StrokeKind::Press) {
            EXPECT_GE(sliding, 300u) << st.name;
        }
        EXPECT_GT(
            st.samples.front().hip.z,
            ref.height(st.samples.front().t, st.samples.front().hip.x, st.samples.front().hip.y));
    }
}

// --- Stroke families
// ------------------------------------------------------------------------------

/// A scene of known geometry, 320×240 at 30 fps for 1.5 s, seen without noise: a wall at 1 m, a
/// still block at 0.8 m (columns 40..119, rows 60..179) and a square at 0.8 m (40 px, rows
/// 100..139) moving right from column 160 to 250 over the clip.
struct KnownScene {
    static constexpr int kW = 320;
    static constexpr int kH = 240;
    static constexpr int kFrames = 45;
    static int squareLeft(std::size_t frame)
    {
        return 160 +
               static_cast<int>(std::lround(90.0 * static_cast<double>(frame) / (kFrames - 1)));
    }
    static bool block(int c, int r) { return c >= 40 && c < 120 && r >= 60 && r < 180; }
    static bool square(std::size_t frame, int c, int r)
    {
        const int l = squareLeft(frame);
        return c >= l && c < l + 40 && r >= 100 && r < 140;
    }
    static bool near(std::size_t frame, int c, int r) { return block(c, r) || square(frame, c, r); }
    /// Pixel (column, row) under box (x, y), m.
    static std::pair<int, int> pixel(const glm::dvec3 &p)
    {
        const double s = 0.1 / (kW - 1);
        return {static_cast<int>(std::lround(p.x / s + 0.5 * (kW - 1))),
                static_cast<int>(std::lround(0.5 * (kH - 1) - p.y / s))};
    }
    static std::size_t frameAt(double t)
    {
        return std::min<std::size_t>(kFrames - 1,
                                     static_cast<std::size_t>(std::floor(t * 30.0 + 1e-9)));
    }
};

Result<bench::FeelScene> knownScene()
{
    std::vector<depth::Plane<std::uint16_t>> mm;
    for (std::size_t f = 0; f < KnownScene::kFrames; ++f) {
        depth::Plane<std::uint16_t> p(KnownScene::kW, KnownScene::kH, 1000);
        for (int r = 0; r < KnownScene::kH; ++r)
            for (int c = 0; c < KnownScene::kW; ++c)
                if (KnownScene::near(f, c, r))
                    p.at(c, r) = 800;
        mm.push_back(std::move(p));
    }
    return bench::sceneFromSensorDepth("known", mm, 30.0, SceneBox{}, 8);
}

// The placer finds the silhouettes and the moving square from the depth alone: every swipe crosses
// between a near object and the wall, every trace runs along an edge, every hold "beside moving" is
// never under the square but within 20 px of where it passes, and every hold "under occluder" is
// on the wall when pressed and under the square during its hold — checked against the scene's own
// geometry above.
TEST(FeelFamiliesTest, StrokesCrossSilhouettesAndHoldBesideTheMovingSquare)
{
    auto s = knownScene();
    ASSERT_TRUE(s) << s.error().what;
    bench::FamilyPlan plan;
    plan.moveSeconds = 0.5;
    plan.holdSeconds = 0.8;
    std::vector<std::string> notes;
    const auto strokes = bench::makeFamilyStrokes(*s, plan, &notes);
    for (const auto &n : notes)
        std::printf("note: %s\n", n.c_str());
    std::size_t swipes = 0;
    std::size_t traces = 0;
    std::size_t beside = 0;
    std::size_t under = 0;
    for (const auto &st : strokes) {
        ASSERT_FALSE(st.samples.empty()) << st.name;
        // A hand's path: the HIP never jumps, also where the surface under it leaves or comes back
        // out of a hole lower (a held finger follows at a press's 0.1 m/s; a moving one climbs at
        // most kClimb = 4 times its speed). Before, a hold under the square fell onto the wall in
        // one update when the square left.
        const double reach = (st.speed * 5.0 + 0.2) / plan.rate;
        for (std::size_t k = 1; k < st.samples.size(); ++k)
            ASSERT_LE(glm::length(st.samples[k].hip - st.samples[k - 1].hip), reach)
                << st.name << " jumps at t = " << st.samples[k].t
                << " from z = " << st.samples[k - 1].hip.z << " to " << st.samples[k].hip.z;
        if (st.family == bench::StrokeFamily::Swipe) {
            ++swipes;
            bool onNear = false;
            bool onWall = false;
            for (const auto &p : st.samples) {
                if (!p.sliding)
                    continue;
                const auto [c, r] = KnownScene::pixel(p.hip);
                (KnownScene::near(KnownScene::frameAt(p.t), c, r) ? onNear : onWall) = true;
            }
            EXPECT_TRUE(onNear && onWall) << st.name << " does not cross a silhouette";
        }
        if (st.family == bench::StrokeFamily::Trace) {
            ++traces;
            for (const auto &p : st.samples) {
                if (!p.sliding)
                    continue;
                // Within 8 px (2.5 mm) of a near/wall boundary at that time.
                const auto [c, r] = KnownScene::pixel(p.hip);
                const std::size_t f = KnownScene::frameAt(p.t);
                bool edge = false;
                for (int d = -8; d <= 8 && !edge; ++d)
                    edge = KnownScene::near(f, c + d, r) != KnownScene::near(f, c, r) ||
                           KnownScene::near(f, c, r + d) != KnownScene::near(f, c, r);
                EXPECT_TRUE(edge) << st.name << " leaves the edge at t = " << p.t;
            }
        }
        if (st.family != bench::StrokeFamily::Hold)
            continue;
        const auto [c, r] = KnownScene::pixel(st.samples.front().hip);
        if (st.where == "moving") {
            ++beside;
            bool close = false;
            for (std::size_t f = 0; f < KnownScene::kFrames; ++f) {
                EXPECT_FALSE(KnownScene::square(f, c, r)) << st.name << " is under the square";
                for (int dr = -20; dr <= 20 && !close; ++dr)
                    for (int dc = -20; dc <= 20 && !close; ++dc)
                        close = KnownScene::square(f, c + dc, r + dr);
            }
            EXPECT_TRUE(close) << st.name << " is not beside the moving square";
        }
        if (st.where == "occluder") {
            ++under;
            const auto &first = st.samples.front();
            EXPECT_FALSE(KnownScene::near(KnownScene::frameAt(first.t), c, r)) << st.name;
            bool covered = false;
            for (const auto &p : st.samples)
                covered = covered || (p.held && KnownScene::square(KnownScene::frameAt(p.t), c, r));
            EXPECT_TRUE(covered) << st.name << " is never under the square while held";
            EXPECT_TRUE(std::isfinite(st.samples[st.samples.size() / 2].heldZ)) << st.name;
        }
    }
    EXPECT_EQ(swipes, plan.swipeSpeeds.size() * static_cast<std::size_t>(plan.places));
    EXPECT_EQ(traces, plan.traceSpeeds.size());
    EXPECT_EQ(beside, plan.holdDepths.size());
    EXPECT_EQ(under, plan.holdDepths.size());
}

// A hand's path where the surface leaves: a room (a step of 100 mm across it, so strokes have
// silhouettes to be placed on) moves 30 mm back from the camera in one frame. Every still stroke
// follows it down at a press's speed (0.1 m/s), none falls the 30 mm in one update (before: a hold
// fell onto the receded surface in one update, a knock no hand makes).
TEST(FeelFamiliesTest, AStillFingerFollowsASurfaceThatRecedesAtAPressSpeed)
{
    std::vector<depth::Plane<std::uint16_t>> mm;
    for (int f = 0; f < 60; ++f) {
        depth::Plane<std::uint16_t> p(96, 72, 1000);
        const int back = f < 20 ? 0 : 30;
        for (int r = 0; r < 72; ++r)
            for (int c = 0; c < 96; ++c)
                p.at(c, r) = static_cast<std::uint16_t>((c < 48 ? 900 : 1000) + back);
        mm.push_back(std::move(p));
    }
    auto s = bench::sceneFromSensorDepth("receding", mm, 30.0, SceneBox{}, 16);
    ASSERT_TRUE(s) << s.error().what;
    bench::FamilyPlan plan;
    const auto strokes = bench::makeFamilyStrokes(*s, plan, nullptr);
    std::size_t still = 0;
    for (const auto &st : strokes) {
        if (st.speed > 0.0)
            continue;
        ++still;
        double fastest = 0.0;
        for (std::size_t k = 1; k < st.samples.size(); ++k)
            fastest =
                std::max(fastest, (st.samples[k - 1].hip.z - st.samples[k].hip.z) * plan.rate);
        // Down at the press speed, plus a tap's own (π·5 Hz·5 mm) or an approach's 0.05 m/s.
        EXPECT_LE(fastest, 0.1 + 0.08 + 1e-6) << st.name;
    }
    EXPECT_GT(still, 0u);
}

// Holes are kept: a sample the sensor did not measure is code 0 under holeBelow in the touched
// frame, and the reference has no surface there.
TEST(FeelFamiliesTest, HolesAreKeptInFramesAndReference)
{
    std::vector<depth::Plane<std::uint16_t>> mm(3, depth::Plane<std::uint16_t>(64, 48, 1000));
    for (auto &p : mm)
        for (int r = 20; r < 30; ++r)
            for (int c = 20; c < 30; ++c)
                p.at(c, r) = 0;
    mm[0].at(5, 5) = 900;
    auto s = bench::sceneFromSensorDepth("holes", mm, 30.0, SceneBox{}, 8);
    ASSERT_TRUE(s) << s.error().what;
    EXPECT_EQ(s->holeBelow, depth::occupancyFor(8, false).threshold);
    const DepthFrameView f = s->frame(0);
    EXPECT_FALSE(f.measured(25, 25));
    EXPECT_TRUE(f.measured(5, 5));
    EXPECT_GE(f.sample(5, 5), depth::occupancyFor(8, false).first);
    bench::ReferenceSurface ref(*s);
    const double sp = 0.1 / 63;
    const auto at = [&](int c, int r) { return ref.height(0.0, (c - 31.5) * sp, (23.5 - r) * sp); };
    EXPECT_TRUE(std::isnan(at(25, 25)));
    EXPECT_TRUE(std::isfinite(at(10, 10)));
}

} // namespace
} // namespace depthtouch::haptics
