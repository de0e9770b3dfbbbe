// FrameClock: the render thread's pacing without GL or threads, on plain time points: the clock
// started by the first frame and re-anchored after its draw (preroll), frames waited for, late
// frames drawn or dropped, pause freezing media time, the end of the last frame and the time spent
// playing.
#include "depthtouch/playback/frame_clock.h"

#include <chrono>

#include <gtest/gtest.h>

namespace depthtouch::playback {
namespace {

using platform::fromSeconds;
using platform::TimePoint;
using Step = Pace::Step;

constexpr double kPeriod = 1.0 / 30.0;

TimePoint at(double seconds)
{
    return TimePoint(fromSeconds(seconds));
}

TEST(FrameClockTest, theFirstFrameStartsTheClockAndThePrerollAnchorsItAgain)
{
    // GIVEN a clock not started and a first frame of PTS 2 s at t = 10 s
    FrameClock clock(0.0);
    EXPECT_FALSE(clock.started());
    const Pace first = clock.pace(at(10.0), 2.0, nullptr, kPeriod, false);
    // THEN it is shown at once, starting the clock: media time 2 s is now
    EXPECT_EQ(first.step, Step::Show);
    EXPECT_TRUE(first.starts);
    EXPECT_TRUE(clock.started());
    EXPECT_TRUE(clock.prerolling());
    EXPECT_EQ(clock.origin(), at(8.0));
    // WHEN its draw took 0.5 s: the origin moves so that the next frames are not late
    EXPECT_TRUE(clock.endPreroll(at(10.5), 2.0));
    EXPECT_FALSE(clock.prerolling());
    EXPECT_EQ(clock.origin(), at(8.5));
    EXPECT_FALSE(clock.endPreroll(at(11.0), 2.0)) << "once per start";
}

TEST(FrameClockTest, aFrameNotYetDueIsWaitedForAtMostFiveMillisecondsAtATime)
{
    FrameClock clock(0.0);
    (void)clock.pace(at(0.0), 0.0, nullptr, kPeriod, false);
    (void)clock.endPreroll(at(0.0), 0.0);
    // WHEN the frame of PTS 0.1 s is asked for at 0.098 s and at 0.05 s
    const Pace soon = clock.pace(at(0.098), 0.1, nullptr, kPeriod, false);
    const Pace later = clock.pace(at(0.05), 0.1, nullptr, kPeriod, false);
    // THEN the player sleeps until it is due, or 5 ms
    EXPECT_EQ(soon.step, Step::Wait);
    EXPECT_EQ(soon.until, at(0.1));
    EXPECT_EQ(later.step, Step::Wait);
    EXPECT_EQ(later.until, at(0.05) + std::chrono::milliseconds(5));
    // AND at its time it is shown, not late
    const Pace due = clock.pace(at(0.1), 0.1, nullptr, kPeriod, false);
    EXPECT_EQ(due.step, Step::Show);
    EXPECT_FALSE(due.starts);
    EXPECT_NEAR(due.lateSeconds, 0.0, 1e-9);
}

TEST(FrameClockTest, aLateFrameIsDroppedOnlyWhenItsSuccessorIsDueToo)
{
    // GIVEN no lateness allowed, a clock started at PTS 0 at t = 0
    FrameClock clock(0.0);
    (void)clock.pace(at(0.0), 0.0, nullptr, kPeriod, false);
    (void)clock.endPreroll(at(0.0), 0.0);
    const double next = 0.2;
    // WHEN the frame of PTS 0.1 s is taken at 0.15 s: late, but its successor is not due
    const Pace drawn = clock.pace(at(0.15), 0.1, &next, kPeriod, false);
    EXPECT_EQ(drawn.step, Step::Show);
    EXPECT_NEAR(drawn.lateSeconds, 0.05, 1e-9);
    // WHEN it is taken at 0.2 s, when its successor is due: it is skipped
    EXPECT_TRUE(clock.skipsFront(at(0.2), 0.1, &next));
    EXPECT_EQ(clock.pace(at(0.2), 0.1, &next, kPeriod, false).step, Step::Drop);
    // AND without a successor queued it is drawn however late
    EXPECT_FALSE(clock.skipsFront(at(5.0), 0.1, nullptr));
    EXPECT_EQ(clock.pace(at(5.0), 0.1, nullptr, kPeriod, false).step, Step::Show);
}

TEST(FrameClockTest, lateFramesWithinTheAllowedLatenessAreDrawnToCatchUp)
{
    // GIVEN 0.1 s of lateness allowed and a player on time until 1.0 s
    FrameClock clock(0.1);
    (void)clock.pace(at(0.0), 0.0, nullptr, kPeriod, false);
    (void)clock.endPreroll(at(0.0), 0.0);
    EXPECT_EQ(clock.pace(at(1.0), 1.0, nullptr, kPeriod, false).step, Step::Show);
    // WHEN a stall makes frame 1.05 s late by 0.08 s with its successor due
    const double next = 1.1;
    // THEN it is drawn (within the lateness, on time recently)
    EXPECT_FALSE(clock.skipsFront(at(1.13), 1.05, &next));
    // AND a frame more than 0.1 s late is skipped
    EXPECT_TRUE(clock.skipsFront(at(1.2), 1.05, &next));
    // AND when the player has not been on time for 3 × 0.1 s, even a slightly late one is
    const double later = 1.32;
    EXPECT_TRUE(clock.skipsFront(at(1.35), 1.3, &later));
}

TEST(FrameClockTest, pauseFreezesMediaTimeAndHoldsTheShownFrame)
{
    // GIVEN a clock started at PTS 0 at t = 0
    FrameClock clock(0.0);
    (void)clock.pace(at(0.0), 0.0, nullptr, kPeriod, false);
    (void)clock.endPreroll(at(0.0), 0.0);
    // WHEN paused at 1 s and still paused at 3 s
    EXPECT_TRUE(clock.holdForPause(at(1.0), true));
    EXPECT_EQ(clock.origin(), at(0.0));
    EXPECT_TRUE(clock.holdForPause(at(3.0), true));
    // THEN media time stays at 1 s: the origin followed the clock by 2 s
    EXPECT_EQ(clock.origin(), at(2.0));
    EXPECT_EQ(clock.pace(at(3.0), 1.1, nullptr, kPeriod, true).step, Step::Hold);
    // AND resumed, the frames go on from media time 1 s
    EXPECT_FALSE(clock.holdForPause(at(3.0), false));
    EXPECT_EQ(clock.pace(at(3.0), 1.1, nullptr, kPeriod, false).step, Step::Wait);
    EXPECT_EQ(clock.pace(at(3.1), 1.1, nullptr, kPeriod, false).step, Step::Show);
}

TEST(FrameClockTest, theOriginFollowsTheAudioClockBeyondTheTolerance)
{
    // GIVEN a clock started at PTS 0 at t = 0 and out of its preroll
    FrameClock clock(0.0);
    EXPECT_FALSE(clock.follow(at(0.5), 0.3, 0.002)); // not started: nothing to follow
    (void)clock.pace(at(0.0), 0.0, nullptr, kPeriod, false);
    EXPECT_FALSE(clock.follow(at(0.5), 0.3, 0.002)); // prerolling: the first frame anchors it
    (void)clock.endPreroll(at(0.0), 0.0);
    // WHEN the speaker plays media time 0.9 s at t = 1 s (the sound 0.1 s behind the picture)
    EXPECT_TRUE(clock.follow(at(1.0), 0.9, 0.002));
    // THEN media time 0.9 s is now: the frame of PTS 1.0 s waits 0.1 s more
    EXPECT_EQ(clock.origin(), at(0.1));
    EXPECT_EQ(clock.pace(at(1.05), 1.0, nullptr, kPeriod, false).step, Step::Wait);
    EXPECT_EQ(clock.pace(at(1.1), 1.0, nullptr, kPeriod, false).step, Step::Show);
    // AND a report within the tolerance (1 ms off) moves nothing
    EXPECT_FALSE(clock.follow(at(2.0), 1.901, 0.002));
    EXPECT_EQ(clock.origin(), at(0.1));
    // AND while paused the audio clock is not followed (the pause freezes media time)
    EXPECT_TRUE(clock.holdForPause(at(2.0), true));
    EXPECT_FALSE(clock.follow(at(2.5), 0.0, 0.002));
}

TEST(FrameClockTest, pauseBeforeTheFirstFrameMovesNothing)
{
    FrameClock clock(0.0);
    EXPECT_FALSE(clock.holdForPause(at(1.0), true));
    const Pace first = clock.pace(at(2.0), 0.5, nullptr, kPeriod, true);
    EXPECT_EQ(first.step, Step::Show) << "the first frame is shown even when paused";
    EXPECT_TRUE(first.starts);
}

TEST(FrameClockTest, aSeekRestartsTheClockAtTheNextFrame)
{
    FrameClock clock(0.0);
    (void)clock.pace(at(0.0), 0.0, nullptr, kPeriod, false);
    (void)clock.endPreroll(at(0.0), 0.0);
    clock.restart();
    EXPECT_FALSE(clock.started());
    const Pace first = clock.pace(at(4.0), 30.0, nullptr, kPeriod, false);
    EXPECT_TRUE(first.starts);
    EXPECT_EQ(clock.origin(), at(4.0) - fromSeconds(30.0));
}

TEST(FrameClockTest, theLastFrameIsDoneAfterItsPeriodOnScreen)
{
    FrameClock clock(0.0);
    EXPECT_TRUE(clock.lastFrameDone(at(0.0), 0.0, kPeriod)) << "no clock: nothing to wait for";
    (void)clock.pace(at(0.0), 0.0, nullptr, kPeriod, false);
    (void)clock.endPreroll(at(0.0), 0.0);
    EXPECT_FALSE(clock.lastFrameDone(at(1.0), 1.0, kPeriod));
    EXPECT_TRUE(clock.lastFrameDone(at(1.0 + kPeriod + 1e-6), 1.0, kPeriod));
}

TEST(FrameClockTest, playingTimeLeavesThePausesOut)
{
    FrameClock clock(0.0);
    clock.trackPlaying(at(1.0), false);
    EXPECT_NEAR(clock.playingSeconds(at(3.0)), 2.0, 1e-9);
    clock.trackPlaying(at(3.0), true);
    clock.trackPlaying(at(5.0), true);
    EXPECT_NEAR(clock.playingSeconds(at(10.0)), 2.0, 1e-9);
    clock.trackPlaying(at(10.0), false);
    EXPECT_NEAR(clock.playingSeconds(at(11.5)), 3.5, 1e-9);
}

} // namespace
} // namespace depthtouch::playback
