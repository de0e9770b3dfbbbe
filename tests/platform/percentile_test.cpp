/// \file
/// \brief percentile(): the nearest-rank definition (the smallest sample with at least a fraction p
/// of the samples at or below it), checked on samples whose ranks the test counts itself.

#include "depthtouch/platform/percentile.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace {

using depthtouch::platform::percentile;

TEST(PercentileTest, nearestRankOnOneToHundred)
{
    std::vector<double> v;
    for (int i = 100; i >= 1; --i) // in reverse: the function must sort
        v.push_back(i);
    EXPECT_EQ(percentile(v, 0.0), 1.0); // the minimum, not the second sample
    EXPECT_EQ(percentile(v, 0.01), 1.0);
    EXPECT_EQ(percentile(v, 0.5), 50.0);
    EXPECT_EQ(percentile(v, 0.99), 99.0);
    EXPECT_EQ(percentile(v, 1.0), 100.0);
    EXPECT_EQ(percentile(v, 7.0), 100.0); // p beyond 1 is the maximum
    EXPECT_EQ(percentile(v, -1.0), 1.0);
}

TEST(PercentileTest, matchesAFullSortOnRandomSamples)
{
    std::mt19937 rng(29);
    std::uniform_real_distribution<double> value(-5.0, 5.0);
    for (int n : {1, 2, 3, 10, 101}) {
        std::vector<double> v(static_cast<std::size_t>(n));
        for (double &x : v)
            x = value(rng);
        std::vector<double> sorted = v;
        std::sort(sorted.begin(), sorted.end());
        for (double p : {0.0, 0.25, 0.5, 0.9, 0.999, 1.0}) {
            // nearest rank: ceil(p n), at least 1, counted here without the function's clamps
            std::size_t rank = 1;
            while (static_cast<double>(rank) < p * n)
                ++rank;
            EXPECT_EQ(percentile(v, p), sorted[rank - 1]) << "n " << n << " p " << p;
        }
    }
}

TEST(PercentileTest, noSamplesIsZero)
{
    EXPECT_EQ(percentile({}, 0.5), 0.0);
}

} // namespace
