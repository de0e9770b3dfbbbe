// PtsPairer: the pairing rules on timestamps alone (pure, no decoding).
#include <chrono>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/receiver/pts_pairer.h"

namespace depthtouch::receiver {
namespace {

using std::chrono::milliseconds;
using Pairer = PtsPairer<int>;

constexpr milliseconds kPeriod{40}; // 25 fps

PairerConfig config(bool color = true, bool depth = true, milliseconds colorPeriod = kPeriod,
                    milliseconds depthPeriod = kPeriod, int window = 8)
{
    return PairerConfig::forStreams(color, depth, colorPeriod, depthPeriod, window);
}

Pairer::Item item(std::int64_t ms, int id, bool corrupt = false)
{
    Pairer::Item i;
    i.pts = milliseconds(ms);
    i.corrupt = corrupt;
    i.payload = id;
    return i;
}

std::vector<Pairer::Output> pullAll(Pairer &p)
{
    std::vector<Pairer::Output> out;
    Pairer::Output o;
    while (p.pull(o))
        out.push_back(o);
    return out;
}

/// Ends both streams of \a p, appends what it still gives to \a out and checks it finished.
std::vector<Pairer::Output> drain(Pairer &p, std::vector<Pairer::Output> out)
{
    p.endOfStream(PairStream::Color);
    p.endOfStream(PairStream::Depth);
    for (auto &o : pullAll(p))
        out.push_back(o);
    EXPECT_TRUE(p.finished());
    return out;
}

/// Pushes color at \a colorMs and depth at \a depthMs interleaved by time, pulling as it goes.
std::vector<Pairer::Output> run(Pairer &p, const std::vector<std::int64_t> &colorMs,
                                const std::vector<std::int64_t> &depthMs)
{
    std::vector<Pairer::Output> out;
    std::size_t c = 0;
    std::size_t d = 0;
    while (c < colorMs.size() || d < depthMs.size()) {
        const bool takeColor =
            d >= depthMs.size() || (c < colorMs.size() && colorMs[c] <= depthMs[d]);
        if (takeColor) {
            EXPECT_TRUE(p.canPush(PairStream::Color));
            p.push(PairStream::Color, item(colorMs[c], static_cast<int>(c)));
            ++c;
        } else {
            EXPECT_TRUE(p.canPush(PairStream::Depth));
            p.push(PairStream::Depth, item(depthMs[d], 1000 + static_cast<int>(d)));
            ++d;
        }
        for (auto &o : pullAll(p))
            out.push_back(o);
    }
    return drain(p, std::move(out));
}

std::vector<std::int64_t> times(int count, std::int64_t step, std::int64_t start = 0)
{
    std::vector<std::int64_t> v;
    for (int i = 0; i < count; ++i)
        v.push_back(start + i * step);
    return v;
}

TEST(PtsPairerTest, equalRatesPairEachColorFrameWithItsDepthFrameAndTheNext)
{
    // GIVEN color and depth at 25 fps with identical PTS
    Pairer p(config());
    // WHEN paired
    const auto out = run(p, times(10, 40), times(10, 40));
    // THEN every color frame i gets depth i and depth i+1 (none after the last)
    ASSERT_EQ(out.size(), 10u);
    for (std::size_t i = 0; i < out.size(); ++i) {
        EXPECT_EQ(out[i].index, i);
        EXPECT_EQ(out[i].color.payload, static_cast<int>(i));
        ASSERT_TRUE(out[i].hasDepth);
        EXPECT_EQ(out[i].depth.payload, 1000 + static_cast<int>(i));
        EXPECT_EQ(out[i].hasNext, i + 1 < out.size());
        if (out[i].hasNext) {
            EXPECT_EQ(out[i].depthNext.payload, 1001 + static_cast<int>(i));
        }
        EXPECT_FALSE(out[i].depthDuplicated || out[i].depthMissing);
    }
    EXPECT_EQ(p.stats().depthUnpaired, 0u);
}

TEST(PtsPairerTest, outputWaitsUntilTheNextDepthFrameIsBuffered)
{
    Pairer p(config());
    p.push(PairStream::Color, item(0, 0));
    p.push(PairStream::Depth, item(0, 100));
    Pairer::Output o;
    // THEN frame 0 is not decided until depth frame 1 exists
    EXPECT_FALSE(p.pull(o));
    p.push(PairStream::Depth, item(40, 101));
    ASSERT_TRUE(p.pull(o));
    EXPECT_EQ(o.depth.payload, 100);
    ASSERT_TRUE(o.hasNext);
    EXPECT_EQ(o.depthNext.payload, 101);
    EXPECT_EQ(o.depthNext.pts, milliseconds(40));
}

TEST(PtsPairerTest, jitterWithinHalfAFramePairsTheNearestDepthFrame)
{
    Pairer p(config());
    EXPECT_EQ(p.tolerance(), milliseconds(20));
    // depth PTS off by up to 15 ms
    const auto out = run(p, {0, 40, 80, 120}, {5, 30, 95, 135});
    ASSERT_EQ(out.size(), 4u);
    EXPECT_EQ(out[0].depth.payload, 1000);
    EXPECT_EQ(out[1].depth.payload, 1001);
    EXPECT_EQ(out[2].depth.payload, 1002);
    EXPECT_EQ(out[3].depth.payload, 1003);
    for (const auto &o : out)
        EXPECT_FALSE(o.depthDuplicated);
}

TEST(PtsPairerTest, halfRateDepthIsReusedWithTheFollowingFrameAsNext)
{
    // GIVEN color at 25 fps and depth at 12.5 fps
    Pairer p(config(true, true, kPeriod, milliseconds(80)));
    const auto out = run(p, times(8, 40), times(4, 80));
    ASSERT_EQ(out.size(), 8u);
    for (std::size_t i = 0; i < out.size(); ++i) {
        ASSERT_TRUE(out[i].hasDepth) << i;
        EXPECT_EQ(out[i].depth.payload, 1000 + static_cast<int>(i / 2)) << i;
        EXPECT_EQ(out[i].depthDuplicated, i % 2 == 1) << i;
        if (i + 2 < out.size()) { // odd frames interpolate towards the next depth frame
            ASSERT_TRUE(out[i].hasNext);
            EXPECT_EQ(out[i].depthNext.payload, 1001 + static_cast<int>(i / 2));
        }
    }
    EXPECT_EQ(p.stats().depthDuplicated, 4u);
}

TEST(PtsPairerTest, doubleRateDepthSkipsTheFramesBetweenColorFrames)
{
    Pairer p(config(true, true, kPeriod, milliseconds(20)));
    const auto out = run(p, times(5, 40), times(10, 20));
    ASSERT_EQ(out.size(), 5u);
    for (std::size_t i = 0; i < out.size(); ++i) {
        EXPECT_EQ(out[i].depth.payload, 1000 + 2 * static_cast<int>(i));
        EXPECT_EQ(out[i].depth.pts, out[i].pts);
    }
    // the in-between frames: 1, 3, 5, 7, 9
    EXPECT_EQ(p.stats().depthUnpaired, 5u);
}

TEST(PtsPairerTest, depthStartingLateLeavesTheFirstFramesWithoutDepth)
{
    Pairer p(config());
    const auto out = run(p, times(6, 40), times(3, 40, 120));
    ASSERT_EQ(out.size(), 6u);
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(out[static_cast<std::size_t>(i)].depthMissing);
        EXPECT_FALSE(out[static_cast<std::size_t>(i)].hasDepth);
    }
    for (int i = 3; i < 6; ++i)
        EXPECT_EQ(out[static_cast<std::size_t>(i)].depth.payload, 1000 + i - 3);
    EXPECT_EQ(p.stats().depthMissing, 3u);
}

TEST(PtsPairerTest, lostDepthFramesAreCountedAsGapAndBridgedByTheLastFrame)
{
    Pairer p(config());
    // depth frames 3 and 4 lost
    const auto out = run(p, times(8, 40), {0, 40, 80, 200, 240, 280});
    ASSERT_EQ(out.size(), 8u);
    EXPECT_TRUE(out[3].depthDuplicated);
    EXPECT_TRUE(out[4].depthDuplicated);
    EXPECT_EQ(out[3].depth.payload, 1002);
    EXPECT_EQ(out[3].depthNext.payload, 1003); // the frame at 200 ms
    EXPECT_EQ(p.stats().ptsGaps, 1u);
    EXPECT_EQ(p.stats().depthDuplicated, 2u);
}

TEST(PtsPairerTest, duplicateAndBackwardPtsAreRefusedAndCounted)
{
    Pairer p(config());
    EXPECT_EQ(p.push(PairStream::Color, item(0, 0)), PushOutcome::Accepted);
    EXPECT_EQ(p.push(PairStream::Color, item(40, 1)), PushOutcome::Accepted);
    EXPECT_EQ(p.push(PairStream::Color, item(40, 2)), PushOutcome::Duplicate);
    EXPECT_EQ(p.push(PairStream::Color, item(20, 3)), PushOutcome::NonMonotonic);
    EXPECT_EQ(p.push(PairStream::Color, item(80, 4)), PushOutcome::Accepted);
    EXPECT_EQ(p.stats().ptsDuplicates, 1u);
    EXPECT_EQ(p.stats().ptsNonMonotonic, 1u);
    p.endOfStream(PairStream::Color);
    p.endOfStream(PairStream::Depth);
    const auto out = pullAll(p);
    ASSERT_EQ(out.size(), 3u);
    EXPECT_EQ(out[2].color.payload, 4);
}

TEST(PtsPairerTest, missingPtsFollowsThePreviousFrame)
{
    Pairer p(config(true, false));
    p.push(PairStream::Color, item(0, 0));
    Pairer::Item none;
    none.payload = 1;
    EXPECT_EQ(p.push(PairStream::Color, std::move(none)), PushOutcome::Accepted);
    const auto out = pullAll(p);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[1].pts, milliseconds(40));
    EXPECT_EQ(p.stats().ptsMissing, 1u);
}

TEST(PtsPairerTest, stalledDepthForcesDecisionsWithinTheWindow)
{
    // GIVEN a depth stream that stops after two frames while color goes on (not ended)
    Pairer p(config(true, true, kPeriod, kPeriod, 4));
    p.push(PairStream::Depth, item(0, 1000));
    p.push(PairStream::Depth, item(40, 1001));
    std::size_t outputs = 0;
    for (int i = 0; i < 30; ++i) {
        ASSERT_TRUE(p.canPush(PairStream::Color)) << i; // never full: bounded buffering
        p.push(PairStream::Color, item(40 * i, i));
        outputs += pullAll(p).size();
    }
    // THEN all but the window's worth came out, reusing the last depth frame
    EXPECT_EQ(outputs, 30u - 4u);
    EXPECT_GT(p.stats().pairingForced, 0u);
    EXPECT_GT(p.stats().depthDuplicated, 0u);
}

TEST(PtsPairerTest, depthRunningAheadOfAStalledColorStreamIsDroppedBeyondTheWindow)
{
    Pairer p(config(true, true, kPeriod, kPeriod, 4));
    for (int i = 0; i < 20; ++i) {
        ASSERT_TRUE(p.canPush(PairStream::Depth)) << i;
        p.push(PairStream::Depth, item(40 * i, i));
        EXPECT_TRUE(pullAll(p).empty());
    }
    EXPECT_EQ(p.stats().depthUnpaired, 16u);
}

TEST(PtsPairerTest, shorterColorStreamLeavesTheRestOfTheDepthUnpaired)
{
    Pairer p(config());
    const auto out = run(p, times(4, 40), times(10, 40));
    EXPECT_EQ(out.size(), 4u);
    EXPECT_EQ(p.stats().depthUnpaired, 6u);
    EXPECT_TRUE(out[3].hasNext); // depth frame 4 exists, so frame 3 interpolates towards it
}

TEST(PtsPairerTest, shorterDepthStreamLeavesTheLastColorFramesDuplicated)
{
    Pairer p(config());
    const auto out = run(p, times(6, 40), times(3, 40));
    ASSERT_EQ(out.size(), 6u);
    EXPECT_FALSE(out[2].hasNext);
    for (std::size_t i = 3; i < 6; ++i) {
        EXPECT_TRUE(out[i].depthDuplicated);
        EXPECT_EQ(out[i].depth.payload, 1002);
        EXPECT_FALSE(out[i].hasNext);
    }
}

TEST(PtsPairerTest, depthOnlyAndColorOnlyInputs)
{
    Pairer depthOnly(config(false, true));
    const auto d = run(depthOnly, {}, times(5, 40));
    ASSERT_EQ(d.size(), 5u);
    for (std::size_t i = 0; i < d.size(); ++i) {
        EXPECT_FALSE(d[i].hasColor);
        EXPECT_EQ(d[i].depth.payload, 1000 + static_cast<int>(i));
        EXPECT_EQ(d[i].hasNext, i + 1 < d.size());
        EXPECT_EQ(d[i].pts, milliseconds(40 * static_cast<int>(i)));
    }
    Pairer colorOnly(config(true, false));
    const auto c = run(colorOnly, times(5, 40), {});
    ASSERT_EQ(c.size(), 5u);
    for (const auto &o : c) {
        EXPECT_TRUE(o.depthMissing);
        EXPECT_FALSE(o.hasDepth);
    }
}

TEST(PtsPairerTest, corruptItemsMarkTheOutputConcealed)
{
    Pairer p(config());
    p.push(PairStream::Color, item(0, 0));
    p.push(PairStream::Depth, item(0, 100, true));
    p.push(PairStream::Color, item(40, 1));
    p.push(PairStream::Depth, item(40, 101));
    p.endOfStream(PairStream::Color);
    p.endOfStream(PairStream::Depth);
    const auto out = pullAll(p);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_TRUE(out[0].concealed);
    EXPECT_FALSE(out[1].concealed);
}

TEST(PtsPairerTest, resetStartsAFreshTimeline)
{
    Pairer p(config());
    p.push(PairStream::Color, item(400, 0));
    p.reset();
    // an earlier PTS is fine after a reset (seek backwards)
    EXPECT_EQ(p.push(PairStream::Color, item(0, 1)), PushOutcome::Accepted);
    EXPECT_EQ(p.stats().ptsNonMonotonic, 0u);
}

// Timestamp discontinuities (issue 60): a splice, an encoder restart, a loop. Both streams jump at
// the same frame; each refuses its first frame after the jump (a lone stray changes nothing) and
// re-bases at the next, so the outputs go on one period apart, paired, and the first output after
// the jump is flagged.

/// \return \a segments (each: frame count, first PTS in ms) of 40 ms frames, one after another.
std::vector<std::int64_t> segments(const std::vector<std::pair<int, std::int64_t>> &segs)
{
    std::vector<std::int64_t> v;
    for (const auto &[count, start] : segs)
        for (const auto t : times(count, 40, start))
            v.push_back(t);
    return v;
}

/// Pushes \a ms on both streams in file order (color then depth of each frame, as a demuxer
/// reads them), pulling as it goes, then ends both.
std::vector<Pairer::Output> runLockstep(Pairer &p, const std::vector<std::int64_t> &ms)
{
    std::vector<Pairer::Output> out;
    for (std::size_t i = 0; i < ms.size(); ++i) {
        p.push(PairStream::Color, item(ms[i], static_cast<int>(i)));
        p.push(PairStream::Depth, item(ms[i], 1000 + static_cast<int>(i)));
        for (auto &o : pullAll(p))
            out.push_back(o);
    }
    return drain(p, std::move(out));
}

/// Runs \a ms on both streams and checks the re-based timeline: \a jumps discontinuities, each
/// losing one frame per stream, every output paired with its own depth frame, 40 ms apart.
void expectRebased(const std::vector<std::int64_t> &ms, std::uint64_t jumps)
{
    Pairer p(config());
    const auto out = runLockstep(p, ms);
    ASSERT_EQ(out.size(), ms.size() - jumps);
    std::uint64_t flagged = 0;
    for (std::size_t i = 0; i < out.size(); ++i) {
        EXPECT_EQ(out[i].pts, out[0].pts + milliseconds(40 * static_cast<std::int64_t>(i))) << i;
        EXPECT_EQ(out[i].depth.pts, out[i].pts) << i;
        EXPECT_EQ(out[i].depth.payload, out[i].color.payload + 1000) << i;
        EXPECT_FALSE(out[i].depthDuplicated || out[i].depthMissing) << i;
        flagged += out[i].discontinuity ? 1u : 0u;
    }
    EXPECT_EQ(flagged, jumps);
    EXPECT_EQ(p.stats().ptsDiscontinuities, 2u * static_cast<std::uint64_t>(jumps)); // both streams
    EXPECT_EQ(p.stats().depthUnpaired, 0u);
}

TEST(PtsPairerDiscontinuityTest, aForwardJumpOf1000sIsRebasedNotWaitedFor)
{
    expectRebased(segments({{30, 0}, {30, 1'000'000 + 1200}}), 1);
}

TEST(PtsPairerDiscontinuityTest, aBackwardJumpIsRebasedNotDropped)
{
    expectRebased(segments({{30, 100'000}, {30, 60'000}}), 1);
}

TEST(PtsPairerDiscontinuityTest, aResetToZeroIsRebased)
{
    expectRebased(segments({{30, 5'000}, {30, 0}}), 1);
}

TEST(PtsPairerDiscontinuityTest, aClipRepeatedThreeTimesPlaysThreeTimes)
{
    expectRebased(segments({{30, 0}, {30, 0}, {30, 0}}), 2);
}

TEST(PtsPairerDiscontinuityTest, a33BitMpegTsWrapIsRebased)
{
    // 2^33 ticks of 90 kHz = 95443.717 s: a wrap the demuxer left is a jump back of that much.
    const std::int64_t wrapMs = (std::int64_t{1} << 33) / 90;
    expectRebased(segments({{30, wrapMs - 1000}, {30, 200}}), 1);
}

TEST(PtsPairerDiscontinuityTest, aLoneStrayTimestampIsRefusedAndChangesNothing)
{
    Pairer p(config());
    auto ms = times(20, 40);
    ms[8] = 500'000; // forward stray
    ms[14] = 40;     // backward stray
    const auto out = run(p, ms, times(20, 40));
    ASSERT_EQ(out.size(), 18u);
    for (const auto &o : out)
        EXPECT_FALSE(o.discontinuity);
    EXPECT_EQ(p.stats().ptsDiscontinuities, 0u);
    EXPECT_EQ(p.stats().ptsJumps, 1u);
    EXPECT_EQ(p.stats().ptsNonMonotonic, 1u);
    EXPECT_EQ(out.back().pts, milliseconds(19 * 40));
}

TEST(PtsPairerDiscontinuityTest, aForwardStepWithinMaxStepIsAGapNotARebase)
{
    Pairer p(config());
    const auto ms = segments({{10, 0}, {10, 5'000}}); // 4.6 s of nothing: kept as it is
    const auto out = run(p, ms, ms);
    ASSERT_EQ(out.size(), 20u);
    EXPECT_EQ(out[10].pts, milliseconds(5'000));
    EXPECT_FALSE(out[10].discontinuity);
    EXPECT_EQ(p.stats().ptsDiscontinuities, 0u);
}

TEST(PtsPairerDiscontinuityTest, resetForgetsTheRebase)
{
    Pairer p(config());
    (void)runLockstep(p, segments({{10, 0}, {10, 0}}));
    p.reset();
    const auto out = run(p, times(3, 40, 80), times(3, 40, 80)); // a seek to 80 ms
    ASSERT_EQ(out.size(), 3u);
    EXPECT_EQ(out[0].pts, milliseconds(80));
}

} // namespace
} // namespace depthtouch::receiver
