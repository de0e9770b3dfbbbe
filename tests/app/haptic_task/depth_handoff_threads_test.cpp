// DepthHandoff under concurrency: a decoder thread publishes frames as fast as it can while the
// reader takes pairs and re-checks every sample of the frames it holds. Each frame is filled with
// one value derived from its PTS, so a frame overwritten while held shows mixed values.
#include "depthtouch/haptic_task/depth_handoff.h"

#include <atomic>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "app/haptic_task/frames.h"

namespace depthtouch::haptic_task {
namespace {

std::uint16_t valueOf(double pts)
{
    return static_cast<std::uint16_t>(static_cast<std::uint64_t>(pts) * 2654435761u >> 16);
}

/// \return true when every sample of \a v has the value derived from its PTS.
bool intact(const scene::DepthFrameView &v)
{
    return test::allSamples(v, valueOf(v.pts));
}

TEST(DepthHandoffThreadsTest, manyPublishesWhileReadingGiveNoTornFrame)
{
    auto created = DepthHandoff::create(64, 48, scene::SampleFormat::Gray16);
    ASSERT_TRUE(created);
    DepthHandoff &handoff = **created;
    constexpr int kFrames = 20000;
    std::atomic<bool> done{false};
    std::atomic<int> newestAcquired{0}; // the reader's newest pts, so the writer can let it in

    std::thread decoder([&] {
        test::Frame16 frame(64, 48, 0.0);
        for (int i = 1; i <= kFrames; ++i) {
            // Every 2000 frames, wait (at most 2 s) until the reader has had a pair of the last
            // stretch: on a loaded machine the writer could otherwise publish all before the
            // reader runs once, and the test would see no concurrency at all.
            if (i % 2000 == 0) {
                const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
                while (newestAcquired.load() < i - 2000 && std::chrono::steady_clock::now() < until)
                    std::this_thread::yield();
            }
            frame.pts = i;
            std::fill(frame.samples.begin(), frame.samples.end(), valueOf(i));
            if (!handoff.push(frame.view())) {
                ADD_FAILURE() << "push failed";
                break;
            }
        }
        done.store(true);
    });

    DepthPair pair;
    std::uint64_t pairs = 0;
    std::uint64_t checks = 0;
    std::uint64_t torn = 0;
    std::uint64_t outOfOrder = 0;
    double lastPts = 0.0;
    bool have = false;
    for (;;) {
        const bool finished = done.load();
        const bool got = handoff.acquire(pair);
        if (got) {
            ++pairs;
            have = true;
            if (pair.current.pts < lastPts)
                ++outOfOrder;
            if (pair.hasNext && pair.next.pts != pair.current.pts + 1.0)
                ++outOfOrder;
            lastPts = pair.current.pts;
            newestAcquired.store(static_cast<int>(pair.current.pts));
        }
        if (have) {
            // Checks the held frames again and again while the writer keeps publishing.
            ++checks;
            if (!intact(pair.current) || (pair.hasNext && !intact(pair.next)))
                ++torn;
        }
        if (finished && !got)
            break;
    }
    decoder.join();
    EXPECT_EQ(torn, 0u) << "a held frame changed under the reader";
    EXPECT_EQ(outOfOrder, 0u);
    EXPECT_GT(pairs, 1u);
    EXPECT_GT(checks, pairs);
    // The newest pair is the last one pushed.
    ASSERT_TRUE(have);
    EXPECT_DOUBLE_EQ(pair.next.pts, kFrames);
}

} // namespace
} // namespace depthtouch::haptic_task
