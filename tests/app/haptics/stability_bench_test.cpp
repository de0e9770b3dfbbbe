/// \file
/// \brief `bench stability`'s physics (stability_bench.h) against sources of their own: the poles
/// of a mass-damper with a zero-order-hold spring computed here from the characteristic
/// polynomial (Gillespie & Cutkosky 1996), the passivity bound 2b/T of Colgate & Schenkel (1997),
/// the sign of the passivity observer's energy, and the CSV's columns against its header.

#include "depthtouch/haptics/stability_bench.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <gtest/gtest.h>

#include "support/temp_dir.h"

namespace depthtouch::haptics::bench {
namespace {

/// The largest pole modulus of x(n+1) under F(n) = −k·x(n) held over T on m·ẍ = F − b·ẋ: the roots
/// of (z − 1)(z − e) + (k/b)(c1·z + c0), e = exp(−bT/m), c1 = T − (1 − e)/a, c0 = (1 − e)/a − T·e
/// (the zero-order-hold transform of 1/(m s² + b s)), worked out here, not taken from the bench.
double poleRadius(double m, double b, double k, double period)
{
    const double a = b / m;
    const double e = std::exp(-a * period);
    const double c1 = period - (1.0 - e) / a;
    const double c0 = (1.0 - e) / a - period * e;
    const double p1 = -(1.0 + e) + k / b * c1;
    const double p0 = e + k / b * c0;
    const std::complex<double> root = std::sqrt(std::complex<double>(p1 * p1 - 4.0 * p0, 0.0));
    return std::max(std::abs((-p1 + root) / 2.0), std::abs((-p1 - root) / 2.0));
}

/// A mass-damper (no hand spring) 1 mm off a bilateral spring sampled at \a rate: \return the
/// ratio of the largest |x| over the last second to that over the first of a \a seconds run.
double springGrowth(double m, double b, double k, double rate, double seconds)
{
    HandModel hand;
    hand.mass = m;
    hand.damping = b;
    hand.stiffness = 0.0;
    HandState s;
    s.x.z = 1e-3;
    const auto ticks = static_cast<std::size_t>(seconds * rate);
    const auto second = static_cast<std::size_t>(rate);
    double first = 0.0;
    double last = 0.0;
    for (std::size_t n = 0; n < ticks; ++n) {
        if (n < second)
            first = std::max(first, std::fabs(s.x.z));
        if (n + second >= ticks)
            last = std::max(last, std::fabs(s.x.z));
        stepHand(hand, glm::dvec3(0.0), glm::dvec3(0.0, 0.0, -k * s.x.z), 1.0 / rate, 16, s);
    }
    return last / first;
}

TEST(StabilityBenchTest, TheExactBoundOfTheHandIsColgatesWithinAFewPerCent)
{
    // Colgate & Schenkel: k_max = 2b/T when bT/m is small (here 0.01 and 0.02); the exact bound is
    // where the pole pair computed above reaches the unit circle.
    for (const double rate : {1000.0, 500.0})
        for (const double b : {1.0, 3.0}) {
            const double exact = sampledSpringLimit(0.1, b, rate);
            EXPECT_NEAR(exact / colgateBound(b, rate), 1.0, 0.05) << rate << " Hz, b " << b;
            EXPECT_NEAR(poleRadius(0.1, b, exact, 1.0 / rate), 1.0, 1e-9);
            EXPECT_LT(poleRadius(0.1, b, 0.9 * exact, 1.0 / rate), 1.0);
            EXPECT_GT(poleRadius(0.1, b, 1.1 * exact, 1.0 / rate), 1.0);
        }
    EXPECT_DOUBLE_EQ(colgateBound(1.0, 1000.0), 2000.0);
}

TEST(StabilityBenchTest, ASampledSpringOnAMassIsStableBelowTheColgateBoundAndNotAbove)
{
    const double m = 0.1;
    for (const double rate : {1000.0, 500.0}) {
        const double b = 1.0;
        const double bound = colgateBound(b, rate);
        EXPECT_LT(springGrowth(m, b, 0.5 * bound, rate, 5.0), 0.05) << rate;
        EXPECT_GT(springGrowth(m, b, 2.0 * bound, rate, 5.0), 20.0) << rate;
        // Near the exact bound too, and at the rate the poles say: over 4 s between the first and
        // the last second, ρ^(4·rate) (the peak of a second is within a cycle of its envelope).
        const double exact = sampledSpringLimit(m, b, rate);
        for (const double f : {0.8, 1.25}) {
            const double rho = poleRadius(m, b, f * exact, 1.0 / rate);
            const double want = std::pow(rho, 4.0 * rate);
            const double got = springGrowth(m, b, f * exact, rate, 5.0);
            EXPECT_NEAR(std::log(got), std::log(want), 0.25) << rate << " Hz, " << f << " k*";
            EXPECT_EQ(got < 1.0, f < 1.0);
        }
    }
}

/// \return the energy a wall run generated, J: the observer's E at the end minus the −k·p²/2 an
/// ideal (continuous) spring would hold there, since that spring gives back what it took.
double generated(const StabilityRow &r)
{
    return r.energyEnd + 0.5 * r.stiffness * r.penetrationMean * r.penetrationMean;
}

TEST(StabilityBenchTest, TheWallSettlesBelowTheBoundAndOscillatesAboveWithTheEnergysSign)
{
    StabilityOptions o;
    HandModel hand;
    const StabilitySurface flat{"flat", 0.0};
    const double bound = colgateBound(hand.damping, 1000.0);
    const StabilityRow below = runStabilityCase("wall", flat, 1000.0, 0.5 * bound, hand, o);
    EXPECT_EQ(below.outcome, "settled");
    EXPECT_TRUE(below.stable());
    EXPECT_LT(below.oscillation, o.tolerance);
    EXPECT_NEAR(below.forceMean, below.forceExpected, 1e-3 * below.forceExpected);
    EXPECT_GE(below.settleTime, 0.0);
    // Once settled nothing more goes in or out.
    EXPECT_NEAR(below.lateEnergy, 0.0, 1e-6);

    const StabilityRow above = runStabilityCase("wall", flat, 1000.0, 2.0 * bound, hand, o);
    EXPECT_EQ(above.outcome, "oscillates");
    EXPECT_FALSE(above.stable());
    EXPECT_GT(above.oscillation, 100.0 * o.tolerance);
    // The wall keeps putting energy into the hand: it feeds the limit cycle against b.
    EXPECT_GT(above.lateEnergy, 1e-3);
    EXPECT_GT(above.energyPeak, 0.0);
    EXPECT_LT(above.settleTime, 0.0);
}

TEST(StabilityBenchTest, ASampledWallGeneratesEnergyAndMoreAtTheSlowerServoRate)
{
    // Colgate & Schenkel: a sampled spring is not passive; it acts as a negative damping of about
    // k·T/2, so over the same press it generates energy (E above the ideal spring's −k·p²/2),
    // more with the longer period. Both runs are stable (k = 500 N/m is a quarter and a half of
    // 2b/T), so the hand's damping takes it out again.
    StabilityOptions o;
    HandModel hand;
    const StabilitySurface flat{"flat", 0.0};
    const StabilityRow fast = runStabilityCase("wall", flat, 1000.0, 500.0, hand, o);
    const StabilityRow slow = runStabilityCase("wall", flat, 500.0, 500.0, hand, o);
    ASSERT_TRUE(fast.stable());
    ASSERT_TRUE(slow.stable());
    EXPECT_GT(generated(fast), 0.0);
    EXPECT_GT(generated(slow), 1.5 * generated(fast));
    // The peak is the largest E the run saw, so it bounds the end.
    EXPECT_GE(fast.energyPeak, fast.energyEnd);
    EXPECT_GE(slow.energyPeak, slow.energyEnd);
}

TEST(StabilityBenchTest, TheRenderersHoldTheHandAtAModestStiffnessOnBothSurfaces)
{
    StabilityOptions o;
    HandModel hand;
    hand.damping = 3.0;
    for (const char *method : {"finger", "modified"})
        for (const StabilitySurface &surface :
             {StabilitySurface{"flat", 0.0}, StabilitySurface{"sloped", 20.0}}) {
            const StabilityRow r = runStabilityCase(method, surface, 1000.0, 300.0, hand, o);
            EXPECT_EQ(r.outcome, "settled") << method << ' ' << surface.name;
            EXPECT_NEAR(r.forceMean, r.forceExpected, 0.02 * r.forceExpected)
                << method << ' ' << surface.name;
            EXPECT_EQ(r.workspaceScale, 1.0);
            EXPECT_EQ(r.releases, 0);
        }
}

std::vector<std::string> split(const std::string &line)
{
    std::vector<std::string> out;
    std::stringstream ss(line);
    std::string field;
    while (std::getline(ss, field, ','))
        out.push_back(field);
    if (!line.empty() && line.back() == ',')
        out.emplace_back();
    return out;
}

TEST(StabilityBenchTest, TheCsvHoldsWhatItsHeaderSaysInItsUnits)
{
    StabilityOptions o;
    o.methods = {"wall", "modified"};
    o.servoRates = {500.0};
    o.dampings = {1.0};
    o.kSteps = 3;
    o.kMin = 200.0;
    o.kMax = 9000.0;
    const std::vector<StabilityRow> rows = runStabilitySweep(o);
    ASSERT_EQ(rows.size(), 2u * 2u * 3u);
    const std::vector<StabilityLimit> limits = stabilityLimits(rows);
    ASSERT_EQ(limits.size(), 4u);
    depthtouch::testing::TempDir tmp("dt-stability-test-");
    std::string error;
    std::string note;
    ASSERT_TRUE(writeStabilityOutputs(rows, limits, tmp.dir().string(), error, note)) << error;

    std::ifstream csv(tmp.path("stability.csv"));
    std::string line;
    ASSERT_TRUE(std::getline(csv, line));
    EXPECT_EQ(line, stabilityCsvHeader());
    const std::vector<std::string> header = split(line);
    // Every figure's name ends in its unit; the rest are names, a count or a ratio.
    for (const std::string &h : header) {
        const bool named = h == "method" || h == "surface" || h == "outcome" || h == "releases" ||
                           h == "workspace_scale";
        const bool unit = h.ends_with("_hz") || h.ends_with("_n_s_per_m") ||
                          h.ends_with("_n_per_m") || h.ends_with("_m") || h.ends_with("_n") ||
                          h.ends_with("_j") || h.ends_with("_s");
        EXPECT_TRUE(named || unit) << h;
    }
    auto col = [&](const char *name) {
        return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) -
                                        header.begin());
    };
    std::size_t n = 0;
    while (std::getline(csv, line)) {
        const std::vector<std::string> f = split(line);
        ASSERT_EQ(f.size(), header.size()) << line;
        const StabilityRow &r = rows[n++];
        EXPECT_EQ(f[col("method")], r.method);
        const double rate = std::stod(f[col("servo_rate_hz")]);
        const double b = std::stod(f[col("hand_damping_n_s_per_m")]);
        const double k = std::stod(f[col("stiffness_n_per_m")]);
        EXPECT_EQ(rate, 500.0);
        EXPECT_EQ(b, 1.0);
        EXPECT_GE(k, 200.0 * (1 - 1e-9));
        EXPECT_LE(k, 9000.0 * (1 + 1e-9));
        EXPECT_NEAR(std::stod(f[col("colgate_bound_n_per_m")]), 2.0 * b * rate, 1e-6);
        EXPECT_NEAR(std::stod(f[col("workspace_scale")]), std::max(1.0, k / 3000.0), 1e-6);
        // Metres: a press of about 1 N into k N/m sits about 1/k in.
        const double pen = std::stod(f[col("penetration_mean_m")]);
        const double osc = std::stod(f[col("oscillation_pp_m")]);
        EXPECT_GE(osc, 0.0);
        const std::string outcome = f[col("outcome")];
        EXPECT_EQ(outcome, r.outcome);
        if (outcome == "settled") {
            EXPECT_LT(osc, o.tolerance);
            EXPECT_NEAR(pen, std::stod(f[col("force_expected_n")]) / k, 0.05 / k);
            EXPECT_FALSE(f[col("settle_time_s")].empty());
        } else {
            EXPECT_TRUE(f[col("settle_time_s")].empty()) << line;
        }
    }
    EXPECT_EQ(n, rows.size());
    std::ifstream limitsCsv(tmp.path("stability_limits.csv"));
    std::size_t limitLines = 0;
    while (std::getline(limitsCsv, line))
        ++limitLines;
    EXPECT_EQ(limitLines, 1u + limits.size());
}

} // namespace
} // namespace depthtouch::haptics::bench
