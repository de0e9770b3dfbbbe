// DecoderThread: the decode thread feeding a polling consumer through the SPSC queue (mock
// backends).
#include <chrono>
#include <memory>
#include <optional>
#include <string>
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

/// Polls \a t, handing every frame to \a onFrame, until the thread has finished the stream (false
/// if the real-time guard of pollUntil() expires first).
template <class F> bool drainUntilFinished(DecoderThread &t, F onFrame)
{
    return pollUntil([&] {
        PairedFrame f;
        while (t.poll(f))
            onFrame(f);
        return t.finished();
    });
}

class DecoderThreadTest : public ::testing::Test {
protected:
    /// Opens \a url on the mock backends and starts a decoder thread on it (use with
    /// ASSERT_NO_FATAL_FAILURE).
    void start(const std::string &url)
    {
        receiver_ = openMock(clock_, url);
        ASSERT_NE(receiver_, nullptr);
        thread_.emplace(*receiver_);
        ASSERT_TRUE(thread_->start());
    }

    platform::ManualClock clock_;
    std::unique_ptr<Receiver> receiver_;
    std::optional<DecoderThread> thread_; ///< After receiver_: stopped and destroyed first.
};

TEST_F(DecoderThreadTest, consumerPollsEveryFrameInOrder)
{
    ASSERT_NO_FATAL_FAILURE(start("mock://clip?frames=60&fps=30"));
    DecoderThread &t = *thread_;
    std::vector<hal::Pts> pts;
    ASSERT_TRUE(drainUntilFinished(t, [&](const PairedFrame &f) {
        pts.push_back(f.pts);
        EXPECT_TRUE(f.depth);
    }));
    ASSERT_EQ(pts.size(), 60u);
    for (std::size_t i = 1; i < pts.size(); ++i)
        EXPECT_GT(pts[i], pts[i - 1]);
    EXPECT_EQ(t.stats().framesOutput, 60u);
    EXPECT_FALSE(t.failed());
    t.stop();
}

TEST_F(DecoderThreadTest, slowConsumerBlocksOnlyTheDecoderThread)
{
    ASSERT_NO_FATAL_FAILURE(start("mock://clip?frames=40"));
    DecoderThread &t = *thread_;
    // GIVEN a consumer that does not poll: the queue fills and the decoder thread waits
    ASSERT_TRUE(pollUntil([&] { return t.stats().framesOutput >= DecoderThread::kQueueFrames; }));
    std::this_thread::sleep_for(milliseconds(20));
    EXPECT_LE(t.stats().framesOutput, DecoderThread::kQueueFrames + 1);
    // WHEN it polls, every frame still arrives, none twice
    std::size_t n = 0;
    hal::Pts last = hal::kNoPts;
    ASSERT_TRUE(drainUntilFinished(t, [&](const PairedFrame &f) {
        EXPECT_TRUE(last == hal::kNoPts || f.pts > last);
        last = f.pts;
        ++n;
    }));
    EXPECT_EQ(n, 40u);
}

TEST_F(DecoderThreadTest, seekDiscardsQueuedFramesAndRestartsAtTheTarget)
{
    ASSERT_NO_FATAL_FAILURE(start("mock://clip?frames=100&fps=25&gop=5"));
    DecoderThread &t = *thread_;
    ASSERT_TRUE(pollUntil([&] { return t.stats().framesOutput >= 3; }));
    t.seek(milliseconds(2000));
    PairedFrame first;
    ASSERT_TRUE(pollUntil([&] { return t.poll(first); }));
    EXPECT_EQ(first.pts, milliseconds(2000));
    std::size_t n = 1;
    ASSERT_TRUE(drainUntilFinished(t, [&](const PairedFrame &) { ++n; }));
    EXPECT_EQ(n, 50u);
}

TEST_F(DecoderThreadTest, stopMidStreamJoinsAndReturnsEveryFrame)
{
    auto r = openMock(clock_, "mock://clip?frames=100000");
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
