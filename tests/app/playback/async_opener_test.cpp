// The player's opener (app/playback/src/async_opener.h) on the mock media source: one try by
// default, and with untilOpened a live address tried again until a sender comes (the player waiting
// for the next sender of a stream that fell silent), and no more tries once abandoned.
#include "async_opener.h"

#include <atomic>
#include <chrono>
#include <memory>
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
    AsyncOpener opener;
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
    // GIVEN a wait on an address that never gets a sender
    auto sources = std::make_shared<Sources>(1'000'000);
    {
        AsyncOpener opener;
        std::string why;
        ASSERT_TRUE(opener.start(sources->factory(), "mock://clip", mockDecoders(), {}, why, true));
        std::this_thread::sleep_for(100ms);
        // WHEN the player stops (or opens something else)
        opener.abandon();
    }
    // THEN the job tries at most once more and then ends (the sources outlive it here)
    std::this_thread::sleep_for(1500ms);
    const int after = sources->tries.load();
    std::this_thread::sleep_for(1500ms);
    EXPECT_EQ(sources->tries.load(), after);
    EXPECT_LE(after, 2);
}

} // namespace
} // namespace depthtouch::playback
