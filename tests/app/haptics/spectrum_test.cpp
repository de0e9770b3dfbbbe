// averagedPsd and psdPeakDb (the force spectrum of bench feel and demo's force-psd.csv) against
// what a sine must give: its power A²/2 (Parseval: the one-sided density summed over the bins), a
// peak at its frequency, and the same spectrum in units of fs at any sample rate.
#include "depthtouch/haptics/spectrum.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

namespace depthtouch::haptics {
namespace {

/// \a n samples of a sine of amplitude \a a, \a cycles cycles every \a period samples, on an
/// offset.
std::vector<double> sine(std::size_t n, double a, double cycles, std::size_t period)
{
    std::vector<double> x(n);
    for (std::size_t i = 0; i < n; ++i)
        x[i] = 0.7 + a * std::sin(2.0 * std::numbers::pi * cycles * static_cast<double>(i) /
                                  static_cast<double>(period));
    return x;
}

double power(const Psd &p)
{
    double sum = 0.0;
    for (double d : p.density)
        sum += d * p.binHz;
    return sum;
}

TEST(SpectrumTest, aSineGivesItsPowerAtItsFrequency)
{
    // GIVEN 4 segments of 200 samples at 1 kHz, a 2 N sine at 50 Hz (ten cycles a segment)
    const std::vector<double> x = sine(800, 2.0, 10.0, 200);
    const Psd p = averagedPsd(x.data(), x.size(), 4, 1000.0, 500.0);

    // THEN the bins are 5 Hz apart up to 500 Hz, the power is A²/2 = 2 N² (the offset removed),
    // and the largest bin is the one at 50 Hz
    EXPECT_DOUBLE_EQ(p.binHz, 5.0);
    ASSERT_EQ(p.density.size(), 101u);
    EXPECT_NEAR(power(p), 2.0, 0.02);
    std::size_t peak = 0;
    for (std::size_t k = 0; k < p.density.size(); ++k)
        if (p.density[k] > p.density[peak])
            peak = k;
    EXPECT_EQ(peak, 10u);
    EXPECT_NEAR(p.density[0], 0.0, 1e-9) << "each segment's mean is removed";
    EXPECT_DOUBLE_EQ(psdPeakDb(p, 50.0, 6.0), 10.0 * std::log10(p.density[10]));
    EXPECT_LT(psdPeakDb(p, 300.0, 6.0), psdPeakDb(p, 50.0, 6.0) - 60.0);
}

TEST(SpectrumTest, anySampleRateGivesTheSameSpectrumInUnitsOfFs)
{
    // GIVEN the same samples read at 1 kHz and at 0.5 Hz (a slow log: one sample every 2 s)
    const std::vector<double> x = sine(800, 1.0, 10.0, 200);
    const Psd fast = averagedPsd(x.data(), x.size(), 4, 1000.0, 500.0);
    const Psd slow = averagedPsd(x.data(), x.size(), 4, 0.5, 0.25);

    // THEN the bins scale with fs, the density by 1/fs, and the power is the same
    EXPECT_DOUBLE_EQ(slow.binHz, 0.0025);
    ASSERT_EQ(slow.density.size(), fast.density.size());
    for (std::size_t k = 0; k < fast.density.size(); ++k)
        EXPECT_NEAR(slow.density[k] * 0.5, fast.density[k] * 1000.0,
                    1e-9 * fast.density[10] * 1000.0)
            << "bin " << k;
    EXPECT_NEAR(power(slow), power(fast), 1e-9);
}

TEST(SpectrumTest, maxHzLimitsTheBins)
{
    const std::vector<double> x = sine(800, 1.0, 10.0, 200);
    const Psd p = averagedPsd(x.data(), x.size(), 4, 1000.0, 100.0);
    EXPECT_EQ(p.density.size(), 21u) << "0..100 Hz in 5 Hz bins";
}

TEST(SpectrumTest, inputsThatGiveNoSpectrum)
{
    const std::vector<double> x = sine(800, 1.0, 10.0, 200);
    EXPECT_TRUE(averagedPsd(x.data(), x.size(), 0, 1000.0, 500.0).density.empty());
    EXPECT_TRUE(averagedPsd(x.data(), x.size(), 4, 0.0, 500.0).density.empty());
    EXPECT_TRUE(averagedPsd(x.data(), x.size(), 4, -1000.0, 500.0).density.empty());
    EXPECT_TRUE(averagedPsd(x.data(), x.size(), 4, 1000.0, 0.0).density.empty());
    EXPECT_TRUE(averagedPsd(x.data(), 7, 4, 1000.0, 500.0).density.empty()) << "n < 2 x segments";
    EXPECT_FALSE(averagedPsd(x.data(), 8, 4, 1000.0, 500.0).density.empty()) << "n = 2 x segments";

    // a constant signal has no power: -inf dB; a range beyond the bins: NaN
    const std::vector<double> flat(400, 3.0);
    const Psd p = averagedPsd(flat.data(), flat.size(), 2, 1000.0, 500.0);
    EXPECT_EQ(psdPeakDb(p, 50.0, 10.0), -std::numeric_limits<double>::infinity());
    EXPECT_TRUE(std::isnan(psdPeakDb(p, 900.0, 10.0)));
    EXPECT_TRUE(std::isnan(psdPeakDb(Psd{}, 50.0, 10.0)));
}

} // namespace
} // namespace depthtouch::haptics
