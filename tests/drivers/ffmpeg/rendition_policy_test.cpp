// The throughput estimate and the rung it picks (rendition_policy.h): the figures are worked out
// here from the readings fed in, not taken from the code.

#include <vector>

#include <gtest/gtest.h>

#include "rendition_policy.h"

namespace depthtouch::drivers::ffmpeg {
namespace {

/// Feeds \a seconds of wall time from \a start of reads of \a bytes each, \a waited seconds
/// each, one every \a every seconds. \return the time after them.
double feed(ThroughputEstimate &e, double start, double seconds, std::size_t bytes, double waited,
            double every)
{
    double t = start;
    for (; t < start + seconds; t += every)
        e.add(bytes, waited, t);
    return t;
}

TEST(ThroughputEstimateTest, aLinkReadFlatOutMeasuresItsRate)
{
    ThroughputEstimate e;
    // 40000 bytes/s: reads of 4000 bytes, each 0.1 s of waiting, back to back.
    feed(e, 0.0, 1.0, 4000, 0.1, 0.1);
    EXPECT_EQ(e.bitsPerSecond(), 0.0) << "unknown before the short window has passed";
    feed(e, 1.0, 3.0, 4000, 0.1, 0.1);
    EXPECT_NEAR(e.bitsPerSecond(), 320'000.0, 320.0);
}

TEST(ThroughputEstimateTest, aReaderThatHardlyWaitsIsUnbounded)
{
    ThroughputEstimate e;
    // A paced player on a fast link: 4 kB every 33 ms, waiting 0.1 ms for each (0.3 %).
    feed(e, 0.0, 4.0, 4000, 1e-4, 1.0 / 30.0);
    EXPECT_EQ(e.bitsPerSecond(), ThroughputEstimate::kUnbounded);
}

TEST(ThroughputEstimateTest, aFastPastDoesNotHideASlowPresent)
{
    ThroughputEstimate e;
    // 8 s at 10 MB/s (waiting 20 % of the time), then the link falls to 25 kB/s.
    double t = feed(e, 0.0, 8.0, 200'000, 0.02, 0.1);
    EXPECT_NEAR(e.bitsPerSecond(), 8.0 * 200'000 / 0.02, 1e3);
    t = feed(e, t, 1.25, 2500, 0.1, 0.1);
    // After a second of slow reads their rate counts, though both windows still hold fast bytes
    // (the bytes over the waiting of the last 2 s would say about 9.6 Mbit/s).
    EXPECT_NEAR(e.bitsPerSecond(), 200'000.0, 2'000.0);
}

const std::vector<Rung> kLadder{{1'100'000}, {500'000}, {250'000}}; // tallest first

TEST(RenditionPolicyTest, aThroughputBelowThePlayingRungGoesDownToTheTallestWithinItsShare)
{
    // 700 kbit/s < 1100: down to the tallest at most 0.8 x 700 = 560: the 500 kbit/s rung.
    EXPECT_EQ(RenditionPolicy::choose(kLadder, 0, 700'000, 0.0), 1u);
    // 300 kbit/s: 0.8 x 300 = 240 fits none: the shortest.
    EXPECT_EQ(RenditionPolicy::choose(kLadder, 0, 300'000, 100.0), 2u);
    EXPECT_EQ(RenditionPolicy::choose(kLadder, 1, 300'000, 0.0), 2u);
    // Enough for the playing rung: no change, however long since the last switch.
    EXPECT_EQ(RenditionPolicy::choose(kLadder, 0, 1'200'000, 100.0), 0u);
}

TEST(RenditionPolicyTest, upOnlyAfterTheHoldAndToTheTallestWithinTheSmallerShare)
{
    const double hold = RenditionPolicy::kUpHoldSeconds;
    EXPECT_EQ(RenditionPolicy::choose(kLadder, 2, 10'000'000, hold - 0.1), 2u);
    EXPECT_EQ(RenditionPolicy::choose(kLadder, 2, 10'000'000, hold), 0u);
    // 1 Mbit/s: 0.7 x 1000 = 700 holds the 500 rung, not the 1100.
    EXPECT_EQ(RenditionPolicy::choose(kLadder, 2, 1'000'000, hold), 1u);
    EXPECT_EQ(RenditionPolicy::choose(kLadder, 2, ThroughputEstimate::kUnbounded, hold), 0u);
}

TEST(RenditionPolicyTest, aRungChosenOnTheWayDownIsNotLeftUpwardAtTheSameThroughput)
{
    for (double bps = 100'000; bps < 3'000'000; bps *= 1.07) {
        const std::size_t down = RenditionPolicy::choose(kLadder, 0, bps, 0.0);
        EXPECT_EQ(RenditionPolicy::choose(kLadder, down, bps, 1000.0), down) << bps;
    }
}

TEST(RenditionPolicyTest, anUnknownThroughputOrALadderWithoutRatesNeverChanges)
{
    EXPECT_EQ(RenditionPolicy::choose(kLadder, 0, 0.0, 100.0), 0u);
    const std::vector<Rung> noRates{{0}, {0}};
    EXPECT_EQ(RenditionPolicy::choose(noRates, 0, 1.0, 100.0), 0u);
    EXPECT_EQ(RenditionPolicy::choose(kLadder, 7, 1.0, 100.0), 7u) << "an index outside: kept";
}

// A rung the playing decoders cannot decode (another codec: rendition_match.h) is never chosen,
// down or up; the usable ones are chosen among as if it were not there (issue 60, class 7).
TEST(RenditionPolicyTest, anUnusableRungIsNeverChosen)
{
    std::vector<Rung> ladder = kLadder;
    ladder[2].usable = false; // the shortest
    EXPECT_EQ(RenditionPolicy::choose(ladder, 0, 300'000, 100.0), 1u) << "the shortest usable";
    EXPECT_EQ(RenditionPolicy::choose(ladder, 1, 300'000, 100.0), 1u);
    ladder[1].usable = false;
    EXPECT_EQ(RenditionPolicy::choose(ladder, 0, 300'000, 100.0), 0u) << "none: stays";
    ladder = kLadder;
    ladder[0].usable = false; // the tallest
    EXPECT_EQ(RenditionPolicy::choose(ladder, 2, 10'000'000, 100.0), 1u);
}

} // namespace
} // namespace depthtouch::drivers::ffmpeg
