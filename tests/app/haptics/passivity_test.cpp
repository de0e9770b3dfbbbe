/// \file
/// \brief The passivity observer (passivity.h) against work computed by hand, and the energy
/// figures of the feel figures (feel.h) on a sampled spring and on one that lags.

#include "depthtouch/haptics/passivity.h"

#include <cmath>
#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>
#include <gtest/gtest.h>

#include "depthtouch/haptics/feel.h"

namespace depthtouch::haptics {
namespace {

TEST(PassivityObserverTest, AConstantForceDoesItsForceTimesTheDisplacement)
{
    // 2 N along +x, the hand moving 1 mm along x and 3 mm along y in 10 steps: W = F·Δx = 2 mJ.
    PassivityObserver o;
    for (int i = 0; i <= 10; ++i)
        o.update({1e-4 * i, 3e-4 * i, 0.0}, {2.0, 0.0, 0.0});
    EXPECT_NEAR(o.energy(), 2.0 * 1e-3, 1e-12);
    EXPECT_NEAR(o.peak(), 2.0 * 1e-3, 1e-12);
}

TEST(PassivityObserverTest, TheForceOfAnUpdateActsOverTheMoveAfterIt)
{
    // Zero-order hold: the first update's force (0) acts over the first move, the second's (5 N
    // up) over the second. Moving up 1 mm twice: 0 + 5 N · 1 mm.
    PassivityObserver o;
    o.update({0.0, 0.0, 0.0}, {0.0, 0.0, 0.0});
    o.update({0.0, 0.0, 1e-3}, {0.0, 0.0, 5.0});
    o.update({0.0, 0.0, 2e-3}, {0.0, 0.0, 0.0});
    EXPECT_NEAR(o.energy(), 5e-3, 1e-12);
}

TEST(PassivityObserverTest, ASampledSpringGivesBackItsStaircaseAndNoMore)
{
    // A penalty spring k·d sampled while the hand presses D deep and leaves again in steps of δ:
    // the held force lags the depth by one step each way, so the round trip gives the hand k·D·δ
    // (the area between the staircases: the energy a sampled spring generates, Colgate & Schenkel
    // 1997), and a finer sampling gives less.
    const double k = 800.0;
    const double depth = 3e-3;
    for (const int steps : {30, 300}) {
        const double delta = depth / steps;
        PassivityObserver o;
        for (int i = 0; i <= steps; ++i)
            o.update({0.0, 0.0, -delta * i}, {0.0, 0.0, k * delta * i});
        for (int i = steps - 1; i >= 0; --i)
            o.update({0.0, 0.0, -delta * i}, {0.0, 0.0, k * delta * i});
        EXPECT_NEAR(o.energy(), k * depth * delta, 1e-9) << steps << " steps";
        EXPECT_GT(o.energy(), 0.0);
        // Pressing in took energy from the hand: the peak is the lead of the last step out.
        EXPECT_LE(o.peak(), o.energy() + 1e-12);
    }
}

TEST(PassivityObserverTest, AResetForgetsAndABrokenPathSkipsTheMoveAcrossIt)
{
    PassivityObserver o;
    o.update({0.0, 0.0, 0.0}, {1.0, 0.0, 0.0});
    o.update({1e-3, 0.0, 0.0}, {1.0, 0.0, 0.0});
    EXPECT_NEAR(o.energy(), 1e-3, 1e-12);
    // The device was lost: the hand moved 1 m with no force on it; nothing is counted for it.
    o.breakPath();
    o.update({1.0, 0.0, 0.0}, {1.0, 0.0, 0.0});
    EXPECT_NEAR(o.energy(), 1e-3, 1e-12);
    o.update({1.0 + 1e-3, 0.0, 0.0}, {0.0, 0.0, 0.0});
    EXPECT_NEAR(o.energy(), 2e-3, 1e-12);
    o.reset();
    EXPECT_EQ(o.energy(), 0.0);
    EXPECT_EQ(o.peak(), 0.0);
}

TEST(PassivityObserverTest, NonFiniteInputIsSkippedAndTheEnergyStaysFinite)
{
    PassivityObserver o;
    o.update({0.0, 0.0, 0.0}, {1.0, 0.0, 0.0});
    o.update({std::nan(""), 0.0, 0.0}, {1.0, 0.0, 0.0});
    o.update({1e-3, 0.0, 0.0}, {INFINITY, 0.0, 0.0});
    EXPECT_TRUE(std::isfinite(o.energy()));
    o.update({2e-3, 0.0, 0.0}, {0.0, 0.0, 0.0});
    EXPECT_NEAR(o.energy(), 2e-3, 1e-12); // the first force over the whole 2 mm
}

/// A press straight down into a flat surface at z = 0 and out again, 1 mm per 10 updates to 3 mm
/// deep: the ideal penalty k·depth on each row; the renderer's force is the ideal one \a lag
/// updates late.
std::vector<FeelSample> pressAndLeave(int lag)
{
    const double k = 800.0;
    std::vector<double> z;
    for (int i = 0; i <= 30; ++i)
        z.push_back(-1e-4 * i);
    for (int i = 29; i >= -5; --i)
        z.push_back(-1e-4 * i);
    std::vector<FeelSample> rows(z.size());
    for (std::size_t i = 0; i < z.size(); ++i) {
        FeelSample &r = rows[i];
        r.t = 1e-3 * static_cast<double>(i);
        r.hip = {0.0, 0.0, z[i]};
        r.surfaceZ = 0.0;
        r.idealPenalty = {0.0, 0.0, k * std::max(0.0, -z[i])};
        r.idealForce = r.idealPenalty.z;
        const std::size_t from =
            i >= static_cast<std::size_t>(lag) ? i - static_cast<std::size_t>(lag) : 0;
        r.force = {0.0, 0.0, k * std::max(0.0, -z[from])};
        if (static_cast<int>(i) < lag)
            r.force = {};
    }
    return rows;
}

TEST(FeelEnergyTest, TheIdealPenaltyItselfGeneratesNothingBeyondItself)
{
    const FeelFigures f = computeFeel(pressAndLeave(0));
    EXPECT_NEAR(f.energyExcessMj, 0.0, 1e-12);
    // The sampled spring's own staircase: k·D·δ = 800 · 3 mm · 0.1 mm = 0.24 mJ.
    EXPECT_NEAR(f.energyMj, 0.24, 1e-9);
    EXPECT_NEAR(f.idealEnergyMj, 0.24, 1e-9);
}

TEST(FeelEnergyTest, AForceThatLagsTheSurfacePushesTheLeavingHandAndIsCountedAsExcess)
{
    // L updates late, the force takes k·δ·L·δ less from the hand on each step in and gives it as
    // much more on each step out: 2L·k·D·δ over the round trip, less the steps the late force
    // never reaches around the turn at the bottom, L(L+1)·k·δ². The ideal penalty's own staircase
    // (0.24 mJ) is not the renderer's.
    const double k = 800.0;
    const double depth = 3e-3;
    const double delta = 1e-4;
    for (const int lag : {1, 2}) {
        const FeelFigures f = computeFeel(pressAndLeave(lag));
        const double excess = 2.0 * lag * k * depth * delta - lag * (lag + 1) * k * delta * delta;
        EXPECT_NEAR(f.energyExcessMj, 1e3 * excess, 1e-9) << lag;
        EXPECT_NEAR(f.energyMj - f.idealEnergyMj, f.energyExcessMj, 1e-12);
        EXPECT_GE(f.energyPeakMj, f.energyMj - 1e-12);
    }
}

TEST(FeelEnergyTest, WithoutTheIdealPenaltyThereIsNoExcessToJudge)
{
    std::vector<FeelSample> rows = pressAndLeave(1);
    for (FeelSample &r : rows)
        r.idealPenalty = glm::dvec3{std::nan("")};
    const FeelFigures f = computeFeel(rows);
    EXPECT_TRUE(std::isnan(f.energyExcessMj));
    EXPECT_GT(f.energyMj, 0.0);
}

TEST(FeelEnergyTest, AccumulatingSumsTheEnergyAndKeepsTheWorstStrokesExcess)
{
    const FeelFigures lag2 = computeFeel(pressAndLeave(2));
    const FeelFigures lag1 = computeFeel(pressAndLeave(1));
    FeelFigures total;
    accumulate(total, lag2);
    accumulate(total, lag1);
    EXPECT_NEAR(total.energyMj, lag2.energyMj + lag1.energyMj, 1e-12);
    EXPECT_NEAR(total.idealEnergyMj, lag2.idealEnergyMj + lag1.idealEnergyMj, 1e-12);
    EXPECT_NEAR(total.energyExcessMj, lag2.energyExcessMj, 1e-12);
    EXPECT_GT(lag2.energyExcessMj, lag1.energyExcessMj);
    FeelFigures none;
    none.energyExcessMj = std::nan("");
    accumulate(total, none);
    EXPECT_NEAR(total.energyExcessMj, lag2.energyExcessMj, 1e-12);
}

/// A HIP 8 mm under a surface at z = 0 rising 0.1 mm an update to 2 mm under it, pushed up by
/// 5 N; with \a arrived the surface came over it in the first update (10 mm in 1 ms).
std::vector<FeelSample> risingUnder(bool arrived)
{
    std::vector<FeelSample> rows(61);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        FeelSample &r = rows[i];
        r.t = 1e-3 * static_cast<double>(i);
        r.hip = {0.0, 0.0, -8e-3 + 1e-4 * static_cast<double>(i)};
        r.force = {0.0, 0.0, 5.0};
        r.surfaceZ = 0.0;
        r.surfaceRise = i == 0 && arrived ? 10e-3 : 0.0;
        r.idealPenalty = glm::dvec3{0.0};
    }
    return rows;
}

TEST(FeelEnergyTest, NoEnergyIsJudgedWhileAnArrivingSurfaceCoversTheFinger)
{
    // Under a still surface the 5 N does 5 N · 6 mm = 30 mJ on the hand; under a surface that
    // swept over the finger (the renderer may push out at a bounded rate there) nothing is judged.
    const FeelFigures still = computeFeel(risingUnder(false));
    EXPECT_NEAR(still.energyMj, 30.0, 1e-9);
    EXPECT_NEAR(still.energyExcessMj, 30.0, 1e-9);
    const FeelFigures covered = computeFeel(risingUnder(true));
    EXPECT_GT(covered.coveredMs, 50.0);
    EXPECT_EQ(covered.energyMj, 0.0);
    EXPECT_EQ(covered.idealEnergyMj, 0.0);
}

TEST(FeelEnergyTest, AHoleOverTheFingerAnArrivingSurfaceCoveredKeepsItCovered)
{
    // The object that came over the finger turns to a hole over it from 20 ms (its own stereo
    // shadow as it leaves) while the renderer still pushes the rising HIP out at 5 N; from 45 ms
    // the backdrop is measured again 9 mm down, under the HIP, and the force is off. The push-out
    // under the hole belongs to the arrival: not judged (before: 5 N · 2.5 mm = 12.5 mJ of excess).
    std::vector<FeelSample> rows = risingUnder(true);
    for (std::size_t i = 20; i < rows.size(); ++i) {
        rows[i].surfaceZ = i < 45 ? std::nan("") : -9e-3;
        if (i >= 45)
            rows[i].force = {};
    }
    const FeelFigures f = computeFeel(rows);
    EXPECT_NEAR(f.coveredMs, 45.0, 1e-9); // 0..44 ms
    EXPECT_EQ(f.energyMj, 0.0);
    EXPECT_EQ(f.energyExcessMj, 0.0);
    // Measured again over the HIP at the arrived height instead (the hole was a dropout), it is
    // still covered: the arrival is not over.
    for (std::size_t i = 45; i < rows.size(); ++i)
        rows[i].surfaceZ = 0.0;
    EXPECT_NEAR(computeFeel(rows).coveredMs, 61.0, 1e-9);
}

TEST(FeelEnergyTest, TheIdealPenaltyIsClampedToTheDeviceMaximumAsADeviceRendersIt)
{
    // 20 N asked for, 8.5 N rendered, over 1 mm up: 8.5 mJ.
    std::vector<FeelSample> rows = risingUnder(false);
    rows.resize(11);
    for (FeelSample &r : rows)
        r.idealPenalty = {0.0, 0.0, 20.0};
    FeelThresholds th;
    th.deviceMaxForce = 8.5;
    const FeelFigures f = computeFeel(rows, th);
    EXPECT_NEAR(f.idealEnergyMj, 8.5, 1e-9);
    EXPECT_NEAR(f.energyMj, 5.0, 1e-9);
    EXPECT_NEAR(f.energyExcessMj, -3.5, 1e-9);
}

TEST(FeelEnergyTest, TheExcessWhereTheIdealsNearestPointIsOnASideIsSummedApart)
{
    // A hand 6 mm under a top that rises 1 mm and carries it (60 updates of 1/60 mm), then lifts
    // it 2 mm (20 updates of 0.1 mm). The renderer pushes 4 N up throughout (a proxy on the top);
    // the ideal's nearest point is on a side 4.8 mm away for the first 70 updates (3.84 N along
    // −y, no work on a vertical move), then on the top (4 N up). Work by hand: the renderer's
    // 4 N · 3 mm = 12 mJ; the ideal's 4 N · 1 mm = 4 mJ, over the last 10 moves; the excess
    // 8 mJ is all on moves held under the sideways ideal: 4 N · (1 mm + 1 mm).
    std::vector<FeelSample> rows(81);
    double z = -6e-3;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        FeelSample &r = rows[i];
        r.t = 1e-3 * static_cast<double>(i);
        z += i == 0 ? 0.0 : (i <= 60 ? 1e-3 / 60 : 1e-4);
        r.hip = {0.0, 0.0, z};
        r.surfaceZ = i <= 60 ? z + 6e-3 : 1e-3;
        r.surfaceRise = i == 0 ? 0.0 : (i <= 60 ? 1e-3 / 60 : 0.0);
        r.force = {0.0, 0.0, 4.0};
        r.idealPenalty = i < 70 ? glm::dvec3{0.0, -3.84, 0.0} : glm::dvec3{0.0, 0.0, 4.0};
    }
    const FeelFigures f = computeFeel(rows);
    EXPECT_NEAR(f.energyMj, 12.0, 1e-9);
    EXPECT_NEAR(f.idealEnergyMj, 4.0, 1e-9);
    EXPECT_NEAR(f.energyExcessMj, 8.0, 1e-9);
    EXPECT_NEAR(f.energyExcessSidewaysMj, 8.0, 1e-9);

    // The same with the ideal on the top all along: the same work, none of it sideways.
    for (FeelSample &r : rows)
        r.idealPenalty = {0.0, 0.0, 4.0};
    const FeelFigures top = computeFeel(rows);
    EXPECT_NEAR(top.energyExcessMj, 0.0, 1e-9);
    EXPECT_EQ(top.energyExcessSidewaysMj, 0.0);

    // A renderer on the side too (its force along −y): not the yardstick's jump, not summed apart.
    for (std::size_t i = 0; i < rows.size(); ++i) {
        rows[i].idealPenalty = i < 70 ? glm::dvec3{0.0, -3.84, 0.0} : glm::dvec3{0.0, 0.0, 4.0};
        rows[i].force = rows[i].idealPenalty;
    }
    EXPECT_EQ(computeFeel(rows).energyExcessSidewaysMj, 0.0);

    // The worst stroke's part is kept with its excess.
    FeelFigures total;
    accumulate(total, top);
    accumulate(total, f);
    accumulate(total, top);
    EXPECT_NEAR(total.energyExcessMj, 8.0, 1e-9);
    EXPECT_NEAR(total.energyExcessSidewaysMj, 8.0, 1e-9);
}

TEST(FeelEnergyTest, TheIdealGodObjectsProxyIsTheNearestSurfacePoint)
{
    // A step: z = 0 for x < 0, z = 10 mm for x >= 0. A HIP at x = 1 mm, z = 5 mm is 5 mm under
    // the top but 1 mm beside the step's side: the nearest point is on the side, within a ring
    // step (0.2 mm) and a direction step (15°) of (0, 0, 5 mm).
    const auto step = [](double x, double) { return x < 0.0 ? 0.0 : 10e-3; };
    const glm::dvec3 hip{1e-3, 0.0, 5e-3};
    glm::dvec3 nearest{};
    const double d = nearestSurface(step, hip, 5e-3, &nearest);
    EXPECT_LE(d, 1.2e-3 + 1e-9);
    EXPECT_GE(d, 1e-3 - 1e-9);
    EXPECT_NEAR(glm::length(nearest - hip), d, 1e-12);
    EXPECT_LT(nearest.x, 1e-9);          // on the side of the step
    EXPECT_NEAR(nearest.z, 5e-3, 1e-12); // level with the HIP: the side is vertical
    EXPECT_DOUBLE_EQ(depthInside(step, hip, 5e-3), d);
}

TEST(FeelEnergyTest, ThePlanePenaltyPushesAlongTheNormalOfATiltedPlane)
{
    // z = 0.5·x: the normal is (−0.5, 0, 1)/|·|; 2 mm under it at x = 0, d along the normal is
    // 2 mm · n_z, and the force k·d·n.
    const auto plane = [](double x, double) { return 0.5 * x; };
    const glm::dvec3 hip{0.0, 0.0, -2e-3};
    const glm::dvec3 f = planePenalty(plane, hip, plane(hip.x, hip.y), 1000.0);
    const double nz = 1.0 / std::sqrt(1.25);
    EXPECT_NEAR(f.x, 1000.0 * 2e-3 * nz * (-0.5 * nz), 1e-9);
    EXPECT_NEAR(f.y, 0.0, 1e-12);
    EXPECT_NEAR(f.z, 1000.0 * 2e-3 * nz * nz, 1e-9);
    EXPECT_EQ(planePenalty(plane, glm::dvec3{0.0, 0.0, 1e-3}, 0.0, 1000.0), glm::dvec3{0.0});
}

} // namespace
} // namespace depthtouch::haptics
