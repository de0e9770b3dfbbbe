// The player's opener (app/playback/src/async_opener.h) on the mock media source: one try by
// default, and with untilOpened a live address tried again until a sender comes (the player waiting
// for the next sender of a stream that fell silent), and no more tries once abandoned. Zapping
// (issue 60, class 6) on a source whose open blocks until interrupted: at most two opens alive
// whatever the number of zaps, each abandoned one interrupted, the last one opened.
#include "async_opener.h"

#include <algorithm>
#include <atomic>
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
#include "depthtouch/platform/clock.h"

namespace depthtouch::playback {
namespace {

using namespace std::chrono_literals;

/// Mock sources whose open fails (no sender yet: Timeout) for the first \a failures tries.
struct Sources : std::enable_shared_from_this<Sources> {
    explicit Sources(int failing) : failures(failing) {}
    /// The factory holds the counters: a job left to finish on its own never outlives them.
    AsyncOpener::SourceFactory factory()
    {
        return [self = shared_from_this()]() -> Result<std::unique_ptr<hal::MediaSource>> {
            auto s = std::make_unique<drivers::MockMediaSource>();
            if (self->tries.fetch_add(1) < self->failures)
                s->failNextOpen(Errc::Timeout);
            return std::unique_ptr<hal::MediaSource>(std::move(s));
        };
    }
    const int failures;
    std::atomic<int> tries{0};
};

receiver::DecoderFactory mockDecoders()
{
    static platform::ManualClock clock;
    return [](const hal::StreamInfo &) -> Result<std::unique_ptr<hal::VideoDecoder>> {
        return std::unique_ptr<hal::VideoDecoder>(
            std::make_unique<drivers::MockVideoDecoder>(clock));
    };
}

/// Polls \a opener until its job ends (at most 20 s: the retries wait 0.5 s each).
std::optional<AsyncOpener::Outcome> waitFor(AsyncOpener &opener)
{
    const auto end = std::chrono::steady_clock::now() + 20s;
    while (std::chrono::steady_clock::now() < end) {
        if (auto out = opener.poll())
            return out;
        std::this_thread::sleep_for(10ms);
    }
    return std::nullopt;
}

TEST(AsyncOpenerTest, anOpenThatFailsIsReportedAfterOneTry)
{
    // GIVEN an address with no sender yet
    auto sources = std::make_shared<Sources>(2);
    AsyncOpener opener;
    std::string why;
    // WHEN it is opened as `play` opens it
    ASSERT_TRUE(opener.start(sources->factory(), "mock://clip?frames=5", mockDecoders(), {}, why));
    const auto out = waitFor(opener);
    // THEN the failure is reported after the one try, with the address in the reason
    ASSERT_TRUE(out);
    EXPECT_FALSE(out->receiver);
    EXPECT_NE(out->error.find("mock://clip?frames=5"), std::string::npos) << out->error;
    EXPECT_EQ(sources->tries.load(), 1);
}

TEST(AsyncOpenerTest, aWaitForTheNextSenderTriesUntilOneComes)
{
    // GIVEN an address whose sender comes at the third try
    auto sources = std::make_shared<Sources>(2);
    static platform::ManualClock clock; // the retries' waits pass at once
    AsyncOpener opener(clock);
    std::string why;
    // WHEN it is opened to wait for its next sender
    ASSERT_TRUE(
        opener.start(sources->factory(), "mock://clip?frames=5", mockDecoders(), {}, why, true));
    const auto out = waitFor(opener);
    // THEN the failed tries are not reported: the receiver of the third one is
    ASSERT_TRUE(out);
    EXPECT_TRUE(out->receiver) << out->error;
    EXPECT_EQ(sources->tries.load(), 3);
}

TEST(AsyncOpenerTest, anAbandonedWaitStopsTrying)
{
    // GIVEN a wait on an address that never gets a sender, its retries timed by a simulated clock
    // (each wait passes at once; static: it outlives a job left running by a failed expectation)
    auto sources = std::make_shared<Sources>(1'000'000'000);
    static platform::ManualClock clock;
    AsyncOpener opener(clock);
    std::string why;
    ASSERT_TRUE(opener.start(sources->factory(), "mock://clip", mockDecoders(), {}, why, true));
    const auto tried = [&sources](int n) {
        for (int i = 0; i < 100'000 && sources->tries.load() < n; ++i)
            std::this_thread::sleep_for(100us);
        return sources->tries.load() >= n;
    };
    ASSERT_TRUE(tried(3));
    // WHEN the player stops (or opens something else)
    opener.abandon();
    EXPECT_FALSE(opener.busy());
    // THEN the job ends (its thread joined by a later poll) and tries no more
    for (int i = 0; i < 100'000 && opener.jobsAlive() > 0; ++i) {
        EXPECT_FALSE(opener.poll());
        std::this_thread::sleep_for(100us);
    }
    ASSERT_EQ(opener.jobsAlive(), 0u);
    const int after = sources->tries.load();
    EXPECT_FALSE(opener.poll());
    EXPECT_EQ(sources->tries.load(), after);
}

/// What the blocking sources of one test did (shared by the factory and every source).
struct Blocking : std::enable_shared_from_this<Blocking> {
    std::mutex mutex;
    std::condition_variable wake;
    bool released = false; ///< Guarded by mutex: opens from now on go through.
    int alive = 0;         ///< Guarded by mutex: sources made and not yet destroyed.
    int maxAlive = 0;      ///< Guarded by mutex.
    int inOpen = 0;        ///< Guarded by mutex: opens entered and not yet returned.
    int maxInOpen = 0;     ///< Guarded by mutex.
    int opens = 0;         ///< Guarded by mutex: opens entered.
    int interrupted = 0;   ///< Guarded by mutex: opens that ended by an interrupt().
    int opened = 0;        ///< Guarded by mutex: opens that went through (released).

    void release()
    {
        const std::lock_guard<std::mutex> lock(mutex);
        released = true;
        wake.notify_all();
    }
    AsyncOpener::SourceFactory factory();
};

/// A mock source whose open() blocks until interrupt() (then Errc::Timeout, as the ffmpeg source
/// says after a stop) or until the test releases it (then the mock clip opens).
class BlockingSource final : public hal::MediaSource {
public:
    explicit BlockingSource(std::shared_ptr<Blocking> b) : b_(std::move(b))
    {
        const std::lock_guard<std::mutex> lock(b_->mutex);
        b_->maxAlive = std::max(b_->maxAlive, ++b_->alive);
    }
    ~BlockingSource() override
    {
        const std::lock_guard<std::mutex> lock(b_->mutex);
        --b_->alive;
    }
    [[nodiscard]] State state() const noexcept override { return inner_.state(); }
    [[nodiscard]] Result<void> open(const char *url) override
    {
        std::unique_lock<std::mutex> lock(b_->mutex);
        ++b_->opens;
        b_->maxInOpen = std::max(b_->maxInOpen, ++b_->inOpen);
        b_->wake.wait(lock, [this] { return interrupted_ || b_->released; });
        --b_->inOpen;
        if (interrupted_) {
            ++b_->interrupted;
            return unexpected(Errc::Timeout, "Interrupted by a stop request");
        }
        ++b_->opened;
        lock.unlock();
        return inner_.open(url);
    }
    void close() noexcept override { inner_.close(); }
    [[nodiscard]] const hal::MediaInfo &info() const noexcept override { return inner_.info(); }
    [[nodiscard]] Result<hal::Packet> readPacket() override { return inner_.readPacket(); }
    [[nodiscard]] Result<void> seek(hal::Pts position) override { return inner_.seek(position); }
    void interrupt() noexcept override
    {
        const std::lock_guard<std::mutex> lock(b_->mutex);
        interrupted_ = true;
        b_->wake.notify_all();
    }

private:
    std::shared_ptr<Blocking> b_;
    drivers::MockMediaSource inner_;
    bool interrupted_ = false; ///< Guarded by b_->mutex.
};

AsyncOpener::SourceFactory Blocking::factory()
{
    return [self = shared_from_this()]() -> Result<std::unique_ptr<hal::MediaSource>> {
        return std::unique_ptr<hal::MediaSource>(std::make_unique<BlockingSource>(self));
    };
}

/// Polls \a opener (no outcome expected) until \a done() (at most 100 000 polls, 0.1 ms apart).
/// \return whether it came.
template <typename Done> bool pollUntil(AsyncOpener &opener, Done done)
{
    for (int i = 0; i < 100'000; ++i) {
        if (done())
            return true;
        EXPECT_FALSE(opener.poll());
        std::this_thread::sleep_for(100us);
    }
    return done();
}

TEST(AsyncOpenerTest, zappingHoldsAtMostTwoOpensAndInterruptsEachAbandonedOne)
{
    // GIVEN inputs whose open blocks until it is interrupted (a silent stream, a device)
    auto blocking = std::make_shared<Blocking>();
    const auto opens = [&blocking] {
        const std::lock_guard<std::mutex> lock(blocking->mutex);
        return blocking->opens;
    };
    {
        AsyncOpener opener;
        std::string why;
        std::size_t mostJobs = 0;
        // WHEN the viewer zaps 1 000 times while each input opens, then 1 000 times without
        // waiting (the player polls between)
        for (int i = 0; i < 2000; ++i) {
            const int before = opens();
            ASSERT_TRUE(opener.start(blocking->factory(),
                                     "mock://clip?fps=10&frames=" + std::to_string(i + 1),
                                     mockDecoders(), {}, why))
                << why;
            mostJobs = std::max(mostJobs, opener.jobsAlive());
            if (i < 1000) {
                ASSERT_TRUE(pollUntil(opener, [&] { return opens() > before; })) << "zap " << i;
            }
            EXPECT_FALSE(opener.poll()) << "zap " << i;
            mostJobs = std::max(mostJobs, opener.jobsAlive());
        }
        // THEN at most two opens were ever alive: the one in flight and the one being abandoned
        EXPECT_LE(mostJobs, AsyncOpener::kMaxJobs);
        {
            const std::lock_guard<std::mutex> lock(blocking->mutex);
            EXPECT_LE(blocking->maxInOpen, 2);
            EXPECT_LE(blocking->maxAlive, 2);
            EXPECT_GE(blocking->opens, 1000);
        }
        // AND once the input answers, the last zap's input opens (bounded polls)
        blocking->release();
        std::optional<AsyncOpener::Outcome> out;
        for (int i = 0; i < 100'000 && !out; ++i) {
            out = opener.poll();
            if (!out)
                std::this_thread::sleep_for(100us);
        }
        ASSERT_TRUE(out);
        ASSERT_TRUE(out->receiver) << out->error;
        EXPECT_EQ(out->receiver->source().info().duration, std::chrono::seconds(200))
            << "not the last zap's input (2 000 frames at 10 fps)";
        // AND the abandoned jobs have ended: their threads are joined
        EXPECT_TRUE(pollUntil(opener, [&] { return opener.jobsAlive() == 0; }));
    }
    // AND every open but that one ended because it was interrupted, none left blocked
    const std::lock_guard<std::mutex> lock(blocking->mutex);
    EXPECT_EQ(blocking->opened, 1);
    EXPECT_EQ(blocking->interrupted, blocking->opens - 1);
    EXPECT_EQ(blocking->alive, 0);
}

} // namespace
} // namespace depthtouch::playback
