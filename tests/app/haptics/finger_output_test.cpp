/// \file
/// \brief The fingertip renderer's output stage (finger_output.h) on its own: the offset filter
/// given a goal whose surface part alternates at the servo rate, as the 3×3 stencil's plane does
/// when its taps fall on a keyboard's keys and in the gaps between them in turn. On depth that has
/// not fitted clean, the force is the mean surface's and steady; on a clean surface the goal
/// passes through unfiltered (no lag on clean geometry).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include <glm/vec3.hpp>
#include <gtest/gtest.h>

#include "depthtouch/haptics/finger_output.h"
#include "depthtouch/haptics/finger_parameters.h"
#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics {
namespace {

constexpr double kRate = 1000.0; ///< Hz, the servo rate.

/// Runs the output stage's filter for \a updates updates, the first a new contact: the HIP starts
/// at z = −5 mm and rises by \a rise (m) an update (its move is the goal's FingerGoal::hipMove),
/// the goal's offset above the HIP in update k is \a offsetOf(k) (m), on a surface that fits clean
/// to \a smooth (FingerPlane::smooth, 0..1). \return the filtered offsets (held proxy − HIP, z, m).
template <class OffsetOf>
std::vector<double> filterRun(int updates, double rise, double smooth, OffsetOf offsetOf)
{
    const RendererConfig config = RendererConfig::forMethod(Method::Finger);
    FingerOutput output(config, fingerParameters(config));
    glm::dvec3 hip{0.0, 0.0, -0.005};
    std::vector<double> held;
    for (int k = 0; k < updates; ++k) {
        FingerGoal goal;
        goal.contact = true;
        goal.touching = k > 0;
        goal.smooth = smooth;
        goal.hipMove = k > 0 ? glm::dvec3{0.0, 0.0, rise} : glm::dvec3{0.0};
        goal.proxy = hip + glm::dvec3{0.0, 0.0, offsetOf(k)};
        held.push_back(output.filter(hip, goal, k / kRate).z - hip.z);
        hip.z += rise;
    }
    return held;
}

/// The filtered offsets (m) of a still HIP whose goal stands \a low and \a high (m) above it in
/// turn, update after update, on a surface that fits clean to \a smooth.
std::vector<double> alternatingGoal(double low, double high, double smooth, int updates)
{
    return filterRun(updates, 0.0, smooth, [&](int k) { return k % 2 == 0 ? low : high; });
}

/// \return the largest change of \a v from one entry to the next from entry \a from on.
double largestChange(const std::vector<double> &v, std::size_t from)
{
    double most = 0.0;
    for (std::size_t i = std::max<std::size_t>(from, 1); i < v.size(); ++i)
        most = std::max(most, std::fabs(v[i] - v[i - 1]));
    return most;
}

// A goal 0.3 and 0.5 mm over a still HIP in turn (0.16 N at k = 800 N/m, the keys swipe's
// alternation in `bench feel`) on depth that never fits clean. The alpha-beta filter alone
// passed 0.23 of an alternation at the servo rate (its gain at the Nyquist frequency): the force
// turned by 0.036 N every update for as long as the goal did, an alternating run `bench feel`
// counts wherever the goal's own swing was a little larger. Its measurement is now the mean of
// the last two offsets there: an alternation at the servo rate is not passed at all, and the
// force is the mean surface's.
TEST(FingerOutputTest, aGoalAlternatingAtTheServoRateOnNoisyDepthGivesTheMeanSurfacesSteadyForce)
{
    const double low = 0.3e-3;
    const double high = 0.5e-3;
    const std::vector<double> held = alternatingGoal(low, high, 0.0, 300);
    const double swing = largestChange(held, 200);
    std::printf("goal alternating %.2f / %.2f mm on noisy depth: the filtered offset %.4f mm, "
                "changing by at most %.5f mm an update after 200 updates\n",
                low * 1e3, high * 1e3, held.back() * 1e3, swing * 1e3);
    EXPECT_LT(swing, 0.05 * (high - low)); // the filter alone: 0.45 of it
    EXPECT_NEAR(held.back(), 0.5 * (low + high), 0.02 * (high - low));
}

// The same goal on a surface whose taps have fitted clean (smooth = 1) for longer than the depth
// memory: nothing there is noise, and the goal passes through as it is, the alternation too (on
// clean geometry the force follows the surface without the filter's lag).
TEST(FingerOutputTest, aGoalOnACleanSurfacePassesThroughUnfiltered)
{
    const double low = 0.3e-3;
    const double high = 0.5e-3;
    const std::vector<double> held = alternatingGoal(low, high, 1.0, 300);
    const std::size_t from = static_cast<std::size_t>(2.0 * kFingerDepthMemory * kRate);
    for (std::size_t k = from; k < held.size(); ++k)
        EXPECT_NEAR(held[k], k % 2 == 0 ? low : high, 1e-9) << "update " << k;
}

// A still HIP under a goal 0.4 mm over it whose height is noise, ±0.1 mm drawn anew each update
// (a fixed sequence): the plane of a stencil whose taps cross noisy pixels at every update. The
// two-tap mean takes out what alternates; the alpha-beta filter takes most of the rest: the
// force's change from one update to the next is about a fifth of the goal's (RMS, 0.20). With
// α = 1 (the filter's own share off, the mean alone) it is about half.
TEST(FingerOutputTest, aNoisyGoalIsSmoothedBeyondTheMeanOfTwo)
{
    std::uint32_t state = 12345u; // a linear congruential generator (Numerical Recipes' constants)
    const auto noise = [&state] {
        state = 1664525u * state + 1013904223u;
        return (static_cast<double>(state >> 8) / 16777216.0 - 0.5) * 0.2e-3;
    };
    std::vector<double> goal;
    const std::vector<double> held = filterRun(1000, 0.0, 0.0, [&](int) {
        goal.push_back(0.4e-3 + noise());
        return goal.back();
    });
    const auto changeRms = [](const std::vector<double> &v) {
        double sum = 0.0;
        for (std::size_t i = 51; i < v.size(); ++i)
            sum += (v[i] - v[i - 1]) * (v[i] - v[i - 1]);
        return std::sqrt(sum / static_cast<double>(v.size() - 51));
    };
    const double ratio = changeRms(held) / changeRms(goal);
    std::printf(
        "a goal 0.4 mm ± 0.1 mm of noise: the filtered offset's change an update is %.3f of "
        "the goal's (RMS)\n",
        ratio);
    EXPECT_LT(ratio, 0.3);
}

// A bounded push that grows by pushDepth an update (a surface sweeping under a finger, found
// deep) while the hand yields 0.2 mm an update along it: the goal's offset grows, 0.16, 0.31,
// 0.47 mm ... The filter passed the hand's move out as the spring's relaxing, as if the goal had
// stayed where it was: the force fell from the push's first step to 0.09 N before it grew (a new
// contact on the keys, or under the crowd's floor as the hand rose, began with such a fall:
// alternating runs of 4-6 updates in `bench feel`). The offset did not shrink, so nothing
// passes: the force grows from the first update on.
TEST(FingerOutputTest, aPushThatGrowsWhileTheHandYieldsGrowsFromTheFirstUpdate)
{
    const FingerParameters p = fingerParameters(RendererConfig::forMethod(Method::Finger));
    const double yield = 0.2e-3;
    const std::vector<double> depth =
        filterRun(10, yield, 0.0, [&](int k) { return p.pushDepth * (k + 1); });
    std::printf("a push growing by %.3f mm an update, the hand yielding %.1f mm an update: the "
                "filtered depth %.3f, %.3f, %.3f mm ...\n",
                p.pushDepth * 1e3, yield * 1e3, depth[0] * 1e3, depth[1] * 1e3, depth[2] * 1e3);
    for (std::size_t k = 1; k < depth.size(); ++k)
        EXPECT_GT(depth[k], depth[k - 1]) << "update " << k;
}

// The hand lifting off a still goal 0.5 mm away by 0.2 mm an update: the offset shrinks by the
// hand's move, and that passes at once, as a spring answers (the energy a late force puts into a
// hand that leaves; docs/benchmarks.md, "The offset filter lags the hand's own motion").
TEST(FingerOutputTest, aHandLiftingOffAStillGoalRelaxesTheSpringAtOnce)
{
    const double lift = 0.2e-3;
    // The goal stays 0.5 mm over where the HIP started: k lifts nearer to the HIP in update k.
    const std::vector<double> depth =
        filterRun(3, lift, 0.0, [&](int k) { return 0.5e-3 - lift * k; });
    // Update 1: the mean of the last two moves (0.1 mm) passes; the mean of the two offsets is
    // filtered. Update 2: the move (0.2 mm) passes in full.
    EXPECT_LT(depth[1], depth[0] - 0.5 * lift);
    EXPECT_LT(depth[2], depth[1] - 0.5 * lift);
}

} // namespace
} // namespace depthtouch::haptics
