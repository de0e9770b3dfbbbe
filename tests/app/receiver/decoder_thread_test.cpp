// DecoderThread: the decode thread feeding a polling consumer through the SPSC queue (mock
// backends).
#include <chrono>
#include <memory>
#include <thread>

#include <gtest/gtest.h>

#include "depthtouch/drivers/mock/mock_media_source.h"
#include "depthtouch/drivers/mock/mock_video_decoder.h"
#include "depthtouch/receiver/decoder_thread.h"

namespace depthtouch::receiver {
namespace {

using std::chrono::milliseconds;

std::unique_ptr<Receiver> openMock(platform::Clock &clock, const std::string &url)
{
    DecoderFactory factory = [&clock](const hal::StreamInfo &) {
        return Result<std::unique_ptr<hal::VideoDecoder>>(
            std::unique_ptr<hal::VideoDecoder>(std::make_unique<drivers::MockVideoDecoder>(clock)));
    };
    ReceiverConfig cfg;
    cfg.consumerFrames = static_cast<int>(DecoderThread::kQueueFrames) + 2;
    auto r =
        Receiver::open(std::make_unique<drivers::MockMediaSource>(), url.c_str(), factory, cfg);
    EXPECT_TRUE(r);
    return r ? std::move(*r) : nullptr;
}

/// Polls until \a done or a real-time guard expires (a hang fails instead of blocking ctest).
template <class F> bool pollUntil(F done)
{
    const auto guard = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (!done()) {
        if (std::chrono::steady_clock::now() > guard)
            return false;
        std::this_thread::yield();
    }
    return true;
}

TEST(DecoderThreadTest, consumerPollsEveryFrameInOrder)
{
    platform::ManualClock clock;
    auto r = openMock(clock, "mock://clip?frames=60&fps=30");
    ASSERT_NE(r, nullptr);
    DecoderThread t(*r);
    ASSERT_TRUE(t.start());
    std::vector<hal::Pts> pts;
    ASSERT_TRUE(pollUntil([&] {
        PairedFrame f;
        while (t.poll(f)) {
            pts.push_back(f.pts);
            EXPECT_TRUE(f.depth);
        }
        return t.finished();
    }));
    ASSERT_EQ(pts.size(), 60u);
    for (std::size_t i = 1; i < pts.size(); ++i)
        EXPECT_GT(pts[i], pts[i - 1]);
    EXPECT_EQ(t.stats().framesOutput, 60u);
    EXPECT_FALSE(t.failed());
    t.stop();
}

TEST(DecoderThreadTest, slowConsumerBlocksOnlyTheDecoderThread)
{
    platform::ManualClock clock;
    auto r = openMock(clock, "mock://clip?frames=40");
    ASSERT_NE(r, nullptr);
    DecoderThread t(*r);
    ASSERT_TRUE(t.start());
    // GIVEN a consumer that does not poll: the queue fills and the decoder thread waits
    ASSERT_TRUE(pollUntil([&] { return t.stats().framesOutput >= DecoderThread::kQueueFrames; }));
    std::this_thread::sleep_for(milliseconds(20));
    EXPECT_LE(t.stats().framesOutput, DecoderThread::kQueueFrames + 1);
    // WHEN it polls, every frame still arrives, none twice
    std::size_t n = 0;
    hal::Pts last = hal::kNoPts;
    ASSERT_TRUE(pollUntil([&] {
        PairedFrame f;
        while (t.poll(f)) {
            EXPECT_TRUE(last == hal::kNoPts || f.pts > last);
            last = f.pts;
            ++n;
        }
        return t.finished();
    }));
    EXPECT_EQ(n, 40u);
}

TEST(DecoderThreadTest, seekDiscardsQueuedFramesAndRestartsAtTheTarget)
{
    platform::ManualClock clock;
    auto r = openMock(clock, "mock://clip?frames=100&fps=25&gop=5");
    ASSERT_NE(r, nullptr);
    DecoderThread t(*r);
    ASSERT_TRUE(t.start());
    ASSERT_TRUE(pollUntil([&] { return t.stats().framesOutput >= 3; }));
    t.seek(milliseconds(2000));
    PairedFrame first;
    ASSERT_TRUE(pollUntil([&] { return t.poll(first); }));
    EXPECT_EQ(first.pts, milliseconds(2000));
    std::size_t n = 1;
    ASSERT_TRUE(pollUntil([&] {
        PairedFrame f;
        while (t.poll(f))
            ++n;
        return t.finished();
    }));
    EXPECT_EQ(n, 50u);
}

TEST(DecoderThreadTest, stopMidStreamJoinsAndReturnsEveryFrame)
{
    platform::ManualClock clock;
    auto r = openMock(clock, "mock://clip?frames=100000");
    ASSERT_NE(r, nullptr);
    {
        DecoderThread t(*r);
        ASSERT_TRUE(t.start());
        EXPECT_FALSE(t.start()); // already running
        ASSERT_TRUE(pollUntil([&] { return t.stats().framesOutput >= 2; }));
        t.stop();
        t.stop(); // idempotent
    }
    // every frame went back to the receiver's stores: it can go on by itself
    PairedFrame f;
    auto n = r->next(f);
    ASSERT_TRUE(n);
    EXPECT_TRUE(*n);
}

} // namespace
} // namespace depthtouch::receiver
