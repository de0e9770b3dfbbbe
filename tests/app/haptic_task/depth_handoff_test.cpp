// DepthHandoff: publication order, stalls, size checks and the slots the reader holds (single
// thread, deterministic). The concurrent torn-frame check is in depth_handoff_threads_test.cpp.
#include "depthtouch/haptic_task/depth_handoff.h"

#include <cstring>
#include <set>

#include <gtest/gtest.h>

#include "app/haptic_task/frames.h"

namespace depthtouch::haptic_task {
namespace {

using test::allSamples;
using test::Frame16;

std::unique_ptr<DepthHandoff> makeHandoff(int w = 8, int h = 6)
{
    auto r = DepthHandoff::create(w, h, scene::SampleFormat::Gray16);
    EXPECT_TRUE(r);
    return std::move(*r);
}

Frame16 constantFrame(std::uint16_t value, double pts)
{
    Frame16 f(8, 6, pts);
    std::fill(f.samples.begin(), f.samples.end(), value);
    return f;
}

/// Publishes (\a current, \a next) on \a handoff with publishPair() and acquires the pair into \a
/// out.
::testing::AssertionResult publishAndAcquire(DepthHandoff &handoff,
                                             const scene::DepthFrameView &current,
                                             const scene::DepthFrameView *next, DepthPair &out)
{
    handoff.publishPair(current, next);
    if (!handoff.acquire(out))
        return ::testing::AssertionFailure() << "acquire() found nothing after publishPair()";
    return ::testing::AssertionSuccess();
}

TEST(DepthHandoffTest, rejectsBadSizes)
{
    EXPECT_EQ(DepthHandoff::create(1, 10, scene::SampleFormat::Gray8).error().code,
              Errc::InvalidArgument);
    EXPECT_EQ(DepthHandoff::create(10, 0, scene::SampleFormat::Gray8).error().code,
              Errc::InvalidArgument);
    EXPECT_EQ(DepthHandoff::create(20000, 10, scene::SampleFormat::Gray8).error().code,
              Errc::InvalidArgument);
    auto ok = DepthHandoff::create(64, 48, scene::SampleFormat::Gray16);
    ASSERT_TRUE(ok);
    EXPECT_EQ((*ok)->frameBytes(), 64u * 48u * 2u);
}

TEST(DepthHandoffTest, nothingBeforeTheFirstPush)
{
    auto handoff = makeHandoff();
    DepthPair pair;
    pair.sequence = 42;
    EXPECT_FALSE(handoff->acquire(pair));
    EXPECT_EQ(pair.sequence, 42u) << "out is untouched when nothing was published";
}

TEST(DepthHandoffTest, pushPublishesPreviousAndNewFrameAsAPair)
{
    auto handoff = makeHandoff();
    DepthPair pair;
    // GIVEN the first frame  THEN the pair is (frame 0, none)
    ASSERT_TRUE(handoff->push(constantFrame(100, 0.0).view()));
    ASSERT_TRUE(handoff->acquire(pair));
    EXPECT_FALSE(pair.hasNext);
    EXPECT_TRUE(allSamples(pair.current, 100));
    EXPECT_EQ(pair.current.pts, 0.0);
    // WHEN frame 1 is pushed  THEN the pair is (frame 0, frame 1)
    ASSERT_TRUE(handoff->push(constantFrame(101, 0.04).view()));
    ASSERT_TRUE(handoff->acquire(pair));
    ASSERT_TRUE(pair.hasNext);
    EXPECT_TRUE(allSamples(pair.current, 100));
    EXPECT_TRUE(allSamples(pair.next, 101));
    EXPECT_DOUBLE_EQ(pair.next.pts, 0.04);
    EXPECT_EQ(pair.sequence, 2u);
    // AND at the end of the stream the last frame holds
    handoff->finish();
    ASSERT_TRUE(handoff->acquire(pair));
    EXPECT_FALSE(pair.hasNext);
    EXPECT_TRUE(allSamples(pair.current, 101));
}

TEST(DepthHandoffTest, stalledDecoderKeepsTheHeldPair)
{
    auto handoff = makeHandoff();
    DepthPair pair;
    ASSERT_TRUE(handoff->push(constantFrame(7, 0.0).view()));
    ASSERT_TRUE(handoff->push(constantFrame(8, 0.1).view()));
    ASSERT_TRUE(handoff->acquire(pair));
    // WHEN nothing more is published  THEN acquire() says so and the views stay valid
    for (int i = 0; i < 5; ++i)
        EXPECT_FALSE(handoff->acquire(pair));
    EXPECT_TRUE(allSamples(pair.current, 7));
    EXPECT_TRUE(allSamples(pair.next, 8));
}

TEST(DepthHandoffTest, readerGetsTheNewestPairAndSkipsTheOthers)
{
    auto handoff = makeHandoff();
    for (int i = 0; i < 10; ++i)
        ASSERT_TRUE(handoff->push(constantFrame(static_cast<std::uint16_t>(i), i * 0.1).view()));
    DepthPair pair;
    ASSERT_TRUE(handoff->acquire(pair));
    EXPECT_TRUE(allSamples(pair.current, 8));
    EXPECT_TRUE(allSamples(pair.next, 9));
    EXPECT_EQ(pair.sequence, 1u);
    EXPECT_EQ(handoff->published(), 10u);
}

TEST(DepthHandoffTest, writerNeverOverwritesTheHeldPair)
{
    // GIVEN the reader holds the pair (1000, 1001)
    auto handoff = makeHandoff();
    ASSERT_TRUE(handoff->push(constantFrame(1000, 0.0).view()));
    ASSERT_TRUE(handoff->push(constantFrame(1001, 0.1).view()));
    DepthPair held;
    ASSERT_TRUE(handoff->acquire(held));
    // WHEN the decoder pushes many frames without the reader taking any
    std::set<const std::uint8_t *> written;
    for (int i = 0; i < 50; ++i) {
        DepthSlot s = handoff->beginFrame();
        written.insert(s.data);
        EXPECT_NE(s.data, held.current.data);
        EXPECT_NE(s.data, held.next.data);
        std::memset(s.data, 0xAB, s.bytes);
        s.pts = 1.0 + i;
        handoff->publish(s, nullptr);
    }
    // THEN the held frames are intact, and the writer cycled through the other slots only
    EXPECT_TRUE(allSamples(held.current, 1000));
    EXPECT_TRUE(allSamples(held.next, 1001));
    EXPECT_LE(written.size(), static_cast<std::size_t>(DepthHandoff::kSlots - 2));
    DepthPair pair;
    ASSERT_TRUE(handoff->acquire(pair));
    EXPECT_DOUBLE_EQ(pair.current.pts, 50.0);
    EXPECT_FALSE(pair.hasNext);
}

TEST(DepthHandoffTest, twoNewFramesCanBePublishedAsOnePair)
{
    auto handoff = makeHandoff();
    DepthSlot a = handoff->beginFrame();
    DepthSlot b = handoff->beginFrame();
    EXPECT_NE(a.data, b.data);
    std::memset(a.data, 0, a.bytes);
    std::memset(b.data, 0xFF, b.bytes);
    a.pts = 3.0;
    b.pts = 3.5;
    handoff->publish(a, &b);
    DepthPair pair;
    ASSERT_TRUE(handoff->acquire(pair));
    EXPECT_TRUE(allSamples(pair.current, 0));
    EXPECT_TRUE(allSamples(pair.next, 0xFFFF));
    EXPECT_DOUBLE_EQ(pair.current.pts, 3.0);
    EXPECT_DOUBLE_EQ(pair.next.pts, 3.5);
}

TEST(DepthHandoffTest, pushRejectsAFrameOfAnotherShape)
{
    auto handoff = makeHandoff();
    Frame16 wrong(9, 6, 0.0);
    EXPECT_EQ(handoff->push(wrong.view()).error().code, Errc::InvalidArgument);
    scene::DepthFrameView gray8 = constantFrame(1, 0.0).view();
    gray8.format = scene::SampleFormat::Gray8;
    EXPECT_EQ(handoff->push(gray8).error().code, Errc::InvalidArgument);
    scene::DepthFrameView empty{};
    EXPECT_EQ(handoff->push(empty).error().code, Errc::InvalidArgument);
    DepthPair pair;
    EXPECT_FALSE(handoff->acquire(pair)) << "nothing was published";
}

TEST(DepthHandoffTest, publishPairCopiesEachNewFrameOnce)
{
    // GIVEN frames 0, 1, 2 shown in turn, each published as (frame i, frame i+1)
    auto handoff = makeHandoff();
    const Frame16 f0 = constantFrame(100, 0.0), f1 = constantFrame(200, 0.1),
                  f2 = constantFrame(300, 0.2);
    const auto v0 = f0.view(), v1 = f1.view(), v2 = f2.view();
    DepthPair first, second;
    ASSERT_TRUE(publishAndAcquire(*handoff, v0, &v1, first));
    ASSERT_TRUE(publishAndAcquire(*handoff, v1, &v2, second));
    // THEN the second pair's current frame is the slot that held the first pair's next frame
    // (frame 1 was copied once), with its pixels and PTS unchanged
    EXPECT_EQ(second.current.data, first.next.data);
    EXPECT_TRUE(allSamples(second.current, 200));
    EXPECT_DOUBLE_EQ(second.current.pts, 0.1);
    ASSERT_TRUE(second.hasNext);
    EXPECT_TRUE(allSamples(second.next, 300));
    EXPECT_DOUBLE_EQ(second.next.pts, 0.2);
    EXPECT_NE(second.next.data, first.current.data) << "the reader held frame 0 until now";
}

TEST(DepthHandoffTest, holeThresholdTravelsWithItsDepthFrame)
{
    // GIVEN frames with holes below 1536 (docs/architecture.md §3 "Holes") and one without
    auto handoff = makeHandoff();
    const Frame16 f0 = constantFrame(100, 0.0), f1 = constantFrame(200, 0.1),
                  f2 = constantFrame(300, 0.2);
    auto v0 = f0.view(), v1 = f1.view(), v2 = f2.view();
    v0.holeBelow = 1536;
    v1.holeBelow = 1536;
    DepthPair first, second;
    ASSERT_TRUE(publishAndAcquire(*handoff, v0, &v1, first));
    // THEN each frame's threshold reaches the haptic thread with it, also when its slot is held
    EXPECT_EQ(first.current.holeBelow, 1536u);
    EXPECT_EQ(first.next.holeBelow, 1536u);
    ASSERT_TRUE(publishAndAcquire(*handoff, v1, &v2, second));
    EXPECT_EQ(second.current.holeBelow, 1536u);
    EXPECT_EQ(second.next.holeBelow, 0u);
    // AND push() carries it too
    ASSERT_TRUE(handoff->push(v0));
    DepthPair pushed;
    ASSERT_TRUE(handoff->acquire(pushed));
    EXPECT_EQ(pushed.current.holeBelow, 1536u);
}

TEST(DepthHandoffTest, publishPairCopiesBothAfterASkipOrARestart)
{
    // GIVEN (frame 0, frame 1) published
    auto handoff = makeHandoff();
    const Frame16 f0 = constantFrame(100, 0.0), f1 = constantFrame(200, 0.1),
                  f2 = constantFrame(300, 0.2), f3 = constantFrame(400, 0.3);
    const auto v0 = f0.view(), v1 = f1.view(), v2 = f2.view(), v3 = f3.view();
    DepthPair pair, after;
    ASSERT_TRUE(publishAndAcquire(*handoff, v0, &v1, pair));
    // WHEN frame 1 is dropped: (frame 2, frame 3) is published
    ASSERT_TRUE(publishAndAcquire(*handoff, v2, &v3, after));
    // THEN both are copied in
    EXPECT_NE(after.current.data, pair.next.data);
    EXPECT_TRUE(allSamples(after.current, 300));
    EXPECT_TRUE(allSamples(after.next, 400));
    // WHEN after a restart() (a seek) frame 3 comes again as current, without a next frame
    handoff->restart();
    DepthPair last;
    ASSERT_TRUE(publishAndAcquire(*handoff, v3, nullptr, last));
    // THEN it is copied again (the old slot is not trusted) and the pair ends there
    EXPECT_NE(last.current.data, after.next.data);
    EXPECT_TRUE(allSamples(last.current, 400));
    EXPECT_FALSE(last.hasNext);
}

TEST(DepthHandoffTest, materialTravelsWithItsDepthFrame)
{
    // GIVEN a handoff that carries materials, frames 0 and 1 with material codes 10 and 20 and
    // frame 2 without any (a material frame missing in the stream)
    auto made = DepthHandoff::create(8, 6, scene::SampleFormat::Gray16, true);
    ASSERT_TRUE(made);
    DepthHandoff &handoff = **made;
    EXPECT_TRUE(handoff.carriesMaterial());
    const Frame16 f0 = constantFrame(100, 0.0), f1 = constantFrame(200, 0.1),
                  f2 = constantFrame(300, 0.2);
    const std::vector<std::uint8_t> m0(8 * 6 * 3, 10), m1(8 * 6 * 3, 20);
    auto v0 = f0.view(), v1 = f1.view(), v2 = f2.view();
    v0.material = {m0.data(), 8 * 3};
    v1.material = {m1.data(), 8 * 3};
    DepthPair first, second;
    ASSERT_TRUE(publishAndAcquire(handoff, v0, &v1, first));
    // THEN each slot holds a copy of its frame's material
    ASSERT_TRUE(first.current.material.present());
    ASSERT_TRUE(first.next.material.present());
    EXPECT_NE(first.current.material.data, m0.data());
    EXPECT_EQ(first.current.material.at(7, 5)[2], 10);
    EXPECT_EQ(first.next.material.at(0, 0)[0], 20);
    EXPECT_TRUE(first.current.validate());
    // AND the held slot keeps its material; a frame without one is handed over without one
    ASSERT_TRUE(publishAndAcquire(handoff, v1, &v2, second));
    ASSERT_TRUE(second.current.material.present());
    EXPECT_EQ(second.current.material.at(3, 3)[1], 20);
    EXPECT_FALSE(second.next.material.present());
    // AND a handoff made without materials ignores them
    auto plain = makeHandoff();
    DepthPair p;
    ASSERT_TRUE(publishAndAcquire(*plain, v0, &v1, p));
    EXPECT_FALSE(plain->carriesMaterial());
    EXPECT_FALSE(p.current.material.present());
}

TEST(DepthHandoffTest, mediaOriginRoundTrips)
{
    auto handoff = makeHandoff();
    const platform::TimePoint origin(std::chrono::milliseconds(1234));
    handoff->setMediaOrigin(origin);
    EXPECT_EQ(handoff->mediaOrigin(), origin);
}

} // namespace
} // namespace depthtouch::haptic_task
