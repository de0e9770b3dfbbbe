// DecoderThread: the decode thread feeding a polling consumer through the SPSC queue (mock
// backends).
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
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

/// Opens \a url on \a source and mock decoders on \a clock, for a consumer that may hold the
/// decoder thread's queue and two more frames. \return null (a test failure) when it fails.
std::unique_ptr<Receiver> openOn(platform::Clock &clock, std::unique_ptr<hal::MediaSource> source,
                                 const std::string &url)
{
    DecoderFactory factory = [&clock](const hal::StreamInfo &) {
        return Result<std::unique_ptr<hal::VideoDecoder>>(
            std::unique_ptr<hal::VideoDecoder>(std::make_unique<drivers::MockVideoDecoder>(clock)));
    };
    ReceiverConfig cfg;
    cfg.consumerFrames = static_cast<int>(DecoderThread::kQueueFrames) + 2;
    auto r = Receiver::open(std::move(source), url.c_str(), factory, cfg);
    EXPECT_TRUE(r);
    return r ? std::move(*r) : nullptr;
}

/// Opens \a url on the mock source and decoders (openOn()).
std::unique_ptr<Receiver> openMock(platform::Clock &clock, const std::string &url)
{
    return openOn(clock, std::make_unique<drivers::MockMediaSource>(), url);
}

/// A seekable source that stalls (a server that stops sending mid-file): after \a stallAfter
/// packets its read waits, as a network read does until its 10 s time-out, unless interrupt() or
/// cancelRead() comes (then Errc::Timeout). After a cancelled read and a seek it reads again.
class StallingSource final : public hal::MediaSource {
public:
    explicit StallingSource(int stallAfter) : left_(stallAfter) {}
    [[nodiscard]] State state() const noexcept override { return inner_.state(); }
    [[nodiscard]] Result<void> open(const char *url) override { return inner_.open(url); }
    void close() noexcept override { inner_.close(); }
    [[nodiscard]] const hal::MediaInfo &info() const noexcept override { return inner_.info(); }
    [[nodiscard]] Result<hal::Packet> readPacket() override
    {
        if (left_ > 0) {
            --left_;
            return inner_.readPacket();
        }
        std::unique_lock<std::mutex> lock(mutex_);
        if (!wake_.wait_for(lock, std::chrono::seconds(10), [&] { return stopped_ || cancels_; }))
            return unexpected(Errc::Io, "stalled input: time-out");
        if (stopped_)
            return unexpected(Errc::Timeout, "Interrupted by a stop request");
        cancels_ = false;
        left_ = 1000000; // the server answers the seek's new request
        return unexpected(Errc::Timeout, "Read cancelled (a seek)");
    }
    [[nodiscard]] Result<void> seek(hal::Pts position) override { return inner_.seek(position); }
    void interrupt() noexcept override
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopped_ = true;
        wake_.notify_all();
    }
    void cancelRead() noexcept override
    {
        std::lock_guard<std::mutex> lock(mutex_);
        cancels_ = true;
        wake_.notify_all();
    }

private:
    drivers::MockMediaSource inner_;
    int left_; ///< Packets before the stall (decode thread only).
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stopped_ = false; ///< Guarded by mutex_.
    bool cancels_ = false; ///< Guarded by mutex_.
};

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
        ASSERT_NO_FATAL_FAILURE(startOn(std::make_unique<drivers::MockMediaSource>(), url));
    }

    /// Opens \a url on a StallingSource that stalls after \a stallAfter packets, starts a
    /// decoder thread on it and polls every frame until the thread read them all, then leaves its
    /// read 100 ms to wait on the stalled input (use with ASSERT_NO_FATAL_FAILURE).
    void startStalled(const std::string &url, int stallAfter)
    {
        ASSERT_NO_FATAL_FAILURE(startOn(std::make_unique<StallingSource>(stallAfter), url));
        DecoderThread &t = *thread_;
        ASSERT_TRUE(pollUntil([&] {
            PairedFrame f;
            while (t.poll(f)) {
            }
            return t.stats().packetsRead >= static_cast<std::uint64_t>(stallAfter);
        }));
        std::this_thread::sleep_for(milliseconds(100));
    }

    /// Opens \a url on \a source (openOn()) and starts a decoder thread on it.
    void startOn(std::unique_ptr<hal::MediaSource> source, const std::string &url)
    {
        receiver_ = openOn(clock_, std::move(source), url);
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

TEST_F(DecoderThreadTest, stopDoesNotWaitForAStalledInput)
{
    // GIVEN a decode thread whose input stalls after 20 packets (10 frames), all of them polled,
    // and whose read now waits on the stalled input
    ASSERT_NO_FATAL_FAILURE(startStalled("mock://clip?frames=100&fps=25", 20));
    DecoderThread &t = *thread_;
    // WHEN the player stops
    const auto begin = std::chrono::steady_clock::now();
    t.stop();
    // THEN the stop returns at once (generous: 2 s), not at the input's 10 s time-out
    EXPECT_LT(std::chrono::steady_clock::now() - begin, std::chrono::seconds(2));
}

TEST_F(DecoderThreadTest, seekDoesNotWaitForAStalledInput)
{
    // GIVEN a decode thread whose seekable input stalls after 20 packets (10 frames)
    ASSERT_NO_FATAL_FAILURE(startStalled("mock://clip?frames=100&fps=25&gop=5", 20));
    DecoderThread &t = *thread_;
    // WHEN the viewer seeks to 2 s
    const auto begin = std::chrono::steady_clock::now();
    t.seek(milliseconds(2000));
    // THEN the first frame of the new position comes at once (generous: 2 s), not after the
    // input's 10 s time-out, and the stream goes on from there
    PairedFrame first;
    ASSERT_TRUE(pollUntil([&] { return t.poll(first); }));
    EXPECT_LT(std::chrono::steady_clock::now() - begin, std::chrono::seconds(2));
    EXPECT_EQ(first.pts, milliseconds(2000));
    std::size_t n = 1;
    ASSERT_TRUE(drainUntilFinished(t, [&](const PairedFrame &) { ++n; }));
    EXPECT_EQ(n, 50u);
    EXPECT_FALSE(t.failed());
    t.stop();
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
