// LatencyHistogram: the percentiles, maximum and mean that play --stats, the telemetry and bench rt
// report, checked against a nearest-rank percentile of the sorted values worked out here (the
// definition in the header), within the documented bin width.
#include "depthtouch/haptic_task/latency_histogram.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace depthtouch::haptic_task {
namespace {

/// Nearest-rank percentile (the smallest value with at least p % of the values at or below it).
double nearestRank(std::vector<std::int64_t> v, double p)
{
    std::sort(v.begin(), v.end());
    const auto rank =
        static_cast<std::size_t>(std::ceil(p / 100.0 * static_cast<double>(v.size())));
    return static_cast<double>(v[std::clamp<std::size_t>(rank, 1, v.size()) - 1]);
}

/// Durations 1..n µs in a shuffled order, in ns.
std::vector<std::int64_t> shuffledMicroseconds(int n, unsigned seed)
{
    std::vector<std::int64_t> v(static_cast<std::size_t>(n));
    std::iota(v.begin(), v.end(), 1);
    for (auto &x : v)
        x *= 1000;
    std::shuffle(v.begin(), v.end(), std::mt19937(seed));
    return v;
}

TEST(LatencyHistogramTest, percentilesAreTheNearestRankWithinHalfABin)
{
    // GIVEN 1000 durations of 1..1000 µs, added out of order
    const std::vector<std::int64_t> values = shuffledMicroseconds(1000, 7);
    LatencyHistogram h;
    for (std::int64_t v : values)
        h.add(v);

    // THEN each percentile is the sorted values' nearest rank, read at its 0.5 µs bin's centre
    const LatencySummary s = h.summary();
    EXPECT_EQ(s.count, 1000u);
    EXPECT_NEAR(s.p50Us, nearestRank(values, 50.0) * 1e-3, 0.25);
    EXPECT_NEAR(s.p90Us, nearestRank(values, 90.0) * 1e-3, 0.25);
    EXPECT_NEAR(s.p99Us, nearestRank(values, 99.0) * 1e-3, 0.25);
    EXPECT_NEAR(s.p999Us, nearestRank(values, 99.9) * 1e-3, 0.25);
    EXPECT_NEAR(s.p99Us, 990.0, 0.25);
    EXPECT_DOUBLE_EQ(s.maxUs, 1000.0);
    EXPECT_DOUBLE_EQ(s.meanUs, 500.5);
    EXPECT_NEAR(h.percentileNs(0.0), 1000.0, 250.0) << "p0 is the smallest value";
    EXPECT_DOUBLE_EQ(h.percentileNs(100.0), 1'000'000.0) << "p100 is the largest";
}

TEST(LatencyHistogramTest, clearForgetsEveryCount)
{
    // GIVEN a histogram of 500 long durations (1.5 ms), then cleared
    LatencyHistogram h;
    for (int i = 0; i < 500; ++i)
        h.add(1'500'000);
    h.clear();
    EXPECT_EQ(h.count(), 0u);
    EXPECT_EQ(h.percentileNs(50.0), 0.0);
    EXPECT_EQ(h.maxNs(), 0);

    // WHEN three short durations are added
    for (std::int64_t ns : {10'000, 20'000, 30'000})
        h.add(ns);

    // THEN only they count: no bin keeps the old 1.5 ms
    EXPECT_EQ(h.count(), 3u);
    EXPECT_NEAR(h.percentileNs(50.0), 20'000.0, 250.0);
    EXPECT_NEAR(h.percentileNs(99.0), 30'000.0, 250.0);
    EXPECT_DOUBLE_EQ(h.meanNs(), 20'000.0);
    EXPECT_EQ(h.binCount(static_cast<std::size_t>(1'500'000 / LatencyHistogram::kFineBinNs)), 0u);
}

TEST(LatencyHistogramTest, mergedHalvesReadAsTheWhole)
{
    const std::vector<std::int64_t> values = shuffledMicroseconds(400, 3);
    LatencyHistogram whole, a, b;
    for (std::size_t i = 0; i < values.size(); ++i) {
        whole.add(values[i]);
        (i % 2 == 0 ? a : b).add(values[i]);
    }
    a.merge(b);
    EXPECT_EQ(a.count(), whole.count());
    EXPECT_EQ(a.maxNs(), whole.maxNs());
    EXPECT_DOUBLE_EQ(a.meanNs(), whole.meanNs());
    for (double p : {1.0, 50.0, 90.0, 99.0})
        EXPECT_DOUBLE_EQ(a.percentileNs(p), whole.percentileNs(p)) << "p" << p;
}

TEST(LatencyHistogramTest, coarseAndOverflowBins)
{
    // GIVEN durations in the 50 µs bins (2..100 ms), one past 100 ms and one negative
    LatencyHistogram h;
    h.add(-5);          // counts as 0
    h.add(3'010'000);   // 3.01 ms
    h.add(42'000'000);  // 42 ms
    h.add(250'000'000); // 250 ms: the overflow bin
    // THEN each reads within half its bin, the overflow bin at its lower edge (100 ms), the
    // maximum exactly
    EXPECT_NEAR(h.percentileNs(25.0), 250.0, 250.0) << "the negative value counts as 0";
    EXPECT_NEAR(h.percentileNs(50.0), 3'010'000.0, 25'000.0);
    EXPECT_NEAR(h.percentileNs(75.0), 42'000'000.0, 25'000.0);
    EXPECT_DOUBLE_EQ(h.percentileNs(100.0), 100'000'000.0);
    EXPECT_EQ(h.maxNs(), 250'000'000);
    EXPECT_DOUBLE_EQ(h.meanNs(), (0.0 + 3'010'000.0 + 42'000'000.0 + 250'000'000.0) / 4.0);
}

} // namespace
} // namespace depthtouch::haptic_task
