// Receiver with a colour decoder that lends dma-buf frames (zero-copy): the frames are kept, not
// copied, until the consumer drops them; a small decoder pool makes next() Busy, never a stall.
#include <array>
#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/drivers/mock/mock_media_source.h"
#include "depthtouch/drivers/mock/mock_video_decoder.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/receiver/receiver.h"
#include "test_support.h"

namespace depthtouch::receivertest {
namespace {

using receiver::PairedFrame;
using receiver::Receiver;
using receiver::ReceiverConfig;

constexpr int kFdBase = 1000; ///< Fake dma-buf fds: never used as files by the receiver.

/// Decodes with a mock decoder, then lends each frame as a dma-buf-only frame (no CPU planes) from
/// its own pool of \a poolFrames, as a DRM PRIME decoder does.
class DmaBufDecoder final : public hal::VideoDecoder, public hal::FrameOwner {
public:
    DmaBufDecoder(platform::Clock &clock, int poolFrames)
        : inner_(clock), frames_(static_cast<std::size_t>(poolFrames)),
          lent_(static_cast<std::size_t>(poolFrames))
    {
        caps_ = inner_.capabilities();
        caps_.poolFrames = poolFrames;
    }

    const hal::VideoDecoderCapabilities &capabilities() const noexcept override { return caps_; }
    State state() const noexcept override { return inner_.state(); }
    Result<void> configure(const hal::StreamConfig &cfg) override { return inner_.configure(cfg); }
    Result<void> queuePacket(const hal::Packet &pkt) override { return inner_.queuePacket(pkt); }
    Result<void> flush() override { return inner_.flush(); }
    void close() noexcept override { inner_.close(); }
    hal::DecoderStats stats() const noexcept override { return inner_.stats(); }

    Result<hal::FrameRef> dequeueFrame(hal::Deadline until) override
    {
        std::size_t slot = 0;
        while (slot < lent_.size() && lent_[slot].load())
            ++slot;
        if (slot == lent_.size())
            return unexpected(Errc::Busy, "Every pool frame is lent");
        auto f = inner_.dequeueFrame(until);
        if (!f)
            return unexpected(f.error());
        hal::Frame &out = frames_[slot];
        out = **f;
        out.image.planes = {};
        out.dmabuf = hal::DmaBufImage{};
        out.dmabuf.fourcc = hal::kDrmFormatYuv420;
        out.dmabuf.width = out.image.width;
        out.dmabuf.height = out.image.height;
        out.dmabuf.planeCount = 3;
        for (auto &p : out.dmabuf.planes)
            p.fd = kFdBase + static_cast<int>(slot);
        lent_[slot].store(true);
        ++lentNow;
        return hal::FrameRef(this, static_cast<std::uint32_t>(slot), &out);
    }

    void releaseFrame(std::uint32_t slot) noexcept override
    {
        lent_[slot].store(false);
        --lentNow;
    }

    std::atomic<int> lentNow{0};

private:
    drivers::MockVideoDecoder inner_;
    hal::VideoDecoderCapabilities caps_;
    std::vector<hal::Frame> frames_;
    std::vector<std::atomic<bool>> lent_;
};

struct Rig {
    explicit Rig(int pool) : poolFrames(pool) {}

    Result<std::unique_ptr<Receiver>> open(const std::string &url, const ReceiverConfig &cfg = {})
    {
        receiver::DecoderFactory factory =
            [this](const hal::StreamInfo &si) -> Result<std::unique_ptr<hal::VideoDecoder>> {
            if (si.kind == hal::StreamKind::Color) {
                auto dec = std::make_unique<DmaBufDecoder>(clock, poolFrames);
                color = dec.get();
                return std::unique_ptr<hal::VideoDecoder>(std::move(dec));
            }
            return std::unique_ptr<hal::VideoDecoder>(
                std::make_unique<drivers::MockVideoDecoder>(clock));
        };
        return Receiver::open(std::make_unique<drivers::MockMediaSource>(), url.c_str(), factory,
                              cfg);
    }

    int poolFrames;
    platform::ManualClock clock;
    DmaBufDecoder *color = nullptr;
};

TEST(ReceiverZeroCopyTest, dmaBufColorFramesAreKeptUntilTheConsumerDropsThem)
{
    // GIVEN a colour decoder lending dma-buf frames from a pool larger than the receiver holds
    Rig rig(32);
    auto r = rig.open("mock://clip?frames=30");
    ASSERT_TRUE(r);
    ASSERT_NE(rig.color, nullptr);
    int count = 0;
    for (;;) {
        PairedFrame f;
        auto n = (*r)->next(f);
        ASSERT_TRUE(n) << n.error().what;
        if (!*n)
            break;
        ++count;
        // THEN the colour frame is the decoder's own: its dma-buf, no CPU planes, still lent
        ASSERT_TRUE(f.color);
        const receiver::StoredFrame &c = *f.color;
        EXPECT_FALSE(c.dmabuf.empty());
        EXPECT_EQ(c.dmabuf.fourcc, hal::kDrmFormatYuv420);
        EXPECT_GE(c.dmabuf.planes[0].fd, kFdBase);
        EXPECT_TRUE(c.image.empty());
        EXPECT_GT(c.image.width, 0);
        EXPECT_TRUE(static_cast<bool>(c.decoded));
        EXPECT_GE(rig.color->lentNow.load(), 1);
        // AND the depth frames are still copied as before
        ASSERT_TRUE(f.depth);
        EXPECT_FALSE(f.depth->image.empty());
        EXPECT_TRUE(f.depth->dmabuf.empty());
    }
    EXPECT_EQ(count, 30);
    EXPECT_EQ((*r)->stats().colorFramesZeroCopy, 30u);
    // AND every frame went back to the decoder once dropped
    EXPECT_EQ(rig.color->lentNow.load(), 0);
}

TEST(ReceiverZeroCopyTest, sharedHandlesReturnTheFrameWithTheLastOne)
{
    Rig rig(32);
    auto r = rig.open("mock://clip?frames=10");
    ASSERT_TRUE(r);
    PairedFrame f;
    ASSERT_TRUE((*r)->next(f));
    receiver::FrameHandle second = f.color.share();
    const int lentWithBoth = rig.color->lentNow.load();
    // WHEN one of two handles is dropped  THEN the frame stays lent
    f.color.reset();
    EXPECT_EQ(rig.color->lentNow.load(), lentWithBoth);
    EXPECT_FALSE(second->dmabuf.empty());
    // WHEN the last one is dropped  THEN it goes back
    second.reset();
    EXPECT_EQ(rig.color->lentNow.load(), lentWithBoth - 1);
}

TEST(ReceiverZeroCopyTest, smallDecoderPoolMakesNextBusyAndLosesNothing)
{
    // GIVEN a colour decoder that can lend only 3 frames and a consumer that holds every frame
    Rig rig(3);
    HoldingConsumer consumer = holdEveryFrame(rig, "mock://clip?frames=20", 50);
    ASSERT_TRUE(consumer.receiver);
    // THEN next() says Busy (the consumer must drop frames), it does not end the input
    EXPECT_EQ(consumer.refusal, Errc::Busy);
    EXPECT_FALSE(consumer.receiver->ended());
    EXPECT_LE(consumer.held.size(), 3u);
    // AND once the consumer drops them, every frame arrives
    const std::size_t before = consumer.letGo();
    EXPECT_EQ(before + drain(*consumer.receiver, 1000).size(), 20u);
}

} // namespace
} // namespace depthtouch::receivertest
