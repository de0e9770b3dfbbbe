/// \file
/// \brief The fingertip renderer's output stage (finger_output.h) on its own: the offset filter
/// given a goal whose surface part alternates at the servo rate, as the 3×3 stencil's plane does
/// when its taps fall on a keyboard's keys and in the gaps between them in turn. On depth that has
/// not fitted clean, the force is the mean surface's and steady; on a clean surface the goal
/// passes through unfiltered (no lag on clean geometry).

#include <algorithm>
#include <cmath>
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

/// The filtered offsets (held proxy − HIP, z, m) of a still HIP whose goal stands \a low and
/// \a high (m) above it in turn, update after update, on a surface that fits clean to \a smooth
/// (FingerPlane::smooth, 0..1); the first update is a new contact.
std::vector<double> alternatingGoal(double low, double high, double smooth, int updates)
{
    const RendererConfig config = RendererConfig::forMethod(Method::Finger);
    FingerOutput output(config, fingerParameters(config));
    const glm::dvec3 hip{0.0, 0.0, -0.005};
    std::vector<double> held;
    for (int k = 0; k < updates; ++k) {
        FingerGoal goal;
        goal.contact = true;
        goal.touching = k > 0;
        goal.smooth = smooth;
        goal.proxy = hip + glm::dvec3{0.0, 0.0, k % 2 == 0 ? low : high};
        held.push_back(output.filter(hip, goal, k / kRate).z - hip.z);
    }
    return held;
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

} // namespace
} // namespace depthtouch::haptics
