// HAL contract: hal::VideoDecoder (video_decoder.h), for every backend in the video decoder table.
#include <algorithm>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "contract_support.h"

namespace depthtouch::contract {
namespace {

using hal::VideoDecoder;
using State = VideoDecoder::State;
using std::chrono::milliseconds;

/// A packet copied out of the source (MediaSource data is only valid until the next read).
struct OwnedPacket {
    std::vector<std::uint8_t> bytes;
    hal::Packet packet;

    hal::Packet view() const
    {
        hal::Packet p = packet;
        p.data = bytes.data();
        p.size = bytes.size();
        return p;
    }
};

class VideoDecoderContractTest : public BackendContractTest<VideoDecoder, VideoDecoderHarness> {
protected:
    void SetUp() override
    {
        createBackend(videoDecoderHarness, "video decoder", "Decoder", drivers::createVideoDecoder);
        if (!dec_)
            return;
        readClip();
    }

    void readClip()
    {
        hal::BackendConfig srcCfg;
        srcCfg.clock = &clock_->clock();
        srcCfg.options = hal::OptionList(harness_->sourceOptions);
        auto src = drivers::createMediaSource(harness_->sourceBackend, srcCfg);
        ASSERT_TRUE(src) << src.error().what;
        ASSERT_TRUE((*src)->open(harness_->url.c_str()));
        streams_ = (*src)->info().streams;
        packets_.resize(streams_.size());
        for (;;) {
            auto p = (*src)->readPacket();
            if (!p)
                break;
            OwnedPacket owned{{p->data, p->data + p->size}, *p};
            packets_[static_cast<std::size_t>(p->streamIndex)].push_back(std::move(owned));
        }
    }

    const hal::StreamInfo &stream(hal::StreamKind kind) const
    {
        return *std::find_if(streams_.begin(), streams_.end(),
                             [&](const hal::StreamInfo &s) { return s.kind == kind; });
    }
    const std::vector<OwnedPacket> &packetsOf(const hal::StreamInfo &s) const
    {
        return packets_[static_cast<std::size_t>(s.index)];
    }
    void configureColor()
    {
        ASSERT_TRUE(dec_->configure(hal::StreamConfig::fromStream(stream(hal::StreamKind::Color))));
    }
    /// Configures the decoder for the clip's color stream (configureColor()). \return the packets
    /// of that stream.
    const std::vector<OwnedPacket> &configureColorPackets()
    {
        configureColor();
        return packetsOf(stream(hal::StreamKind::Color));
    }
    hal::Deadline soon() const { return clock_->clock().now() + milliseconds(500); }

    std::unique_ptr<VideoDecoder> &dec_ = backend_;
    std::vector<hal::StreamInfo> streams_;
    std::vector<std::vector<OwnedPacket>> packets_;
};

TEST_P(VideoDecoderContractTest, closedDecoderRejectsCallsWithoutEffect)
{
    EXPECT_EQ(dec_->state(), State::Closed);
    const auto &pkts = packetsOf(stream(hal::StreamKind::Color));
    ASSERT_FALSE(pkts.empty());
    EXPECT_EQ(errcOf(dec_->queuePacket(pkts[0].view())), Errc::InvalidState);
    EXPECT_EQ(errcOf(dec_->dequeueFrame(soon())), Errc::InvalidState);
    EXPECT_EQ(errcOf(dec_->flush()), Errc::InvalidState);
    EXPECT_EQ(dec_->state(), State::Closed);
    EXPECT_EQ(dec_->stats().packetsQueued, 0u);
    EXPECT_EQ(dec_->stats().framesDecoded, 0u);
}

TEST_P(VideoDecoderContractTest, capabilitiesAreSaneAndConstant)
{
    const hal::VideoDecoderCapabilities &c = dec_->capabilities();
    EXPECT_GE(c.poolFrames, 1);
    EXPECT_GE(c.queuePackets, 1);
    EXPECT_GT(c.maxWidth, 0);
    EXPECT_GT(c.maxHeight, 0);
    for (const hal::StreamInfo &s : streams_) {
        EXPECT_TRUE(c.supports(s.codec)) << hal::codecName(s.codec);
    }
    const int pool = c.poolFrames;
    configureColor();
    EXPECT_EQ(&dec_->capabilities(), &c);
    EXPECT_EQ(dec_->capabilities().poolFrames, pool);
}

TEST_P(VideoDecoderContractTest, refusedConfigurationChangesNothing)
{
    hal::StreamConfig cfg = hal::StreamConfig::fromStream(stream(hal::StreamKind::Color));
    cfg.codec = hal::CodecId::Unknown;
    EXPECT_EQ(errcOf(dec_->configure(cfg)), Errc::NotSupported);
    EXPECT_EQ(dec_->state(), State::Closed);
    cfg = hal::StreamConfig::fromStream(stream(hal::StreamKind::Color));
    cfg.width = 0;
    EXPECT_TRUE(errcOf(dec_->configure(cfg)).has_value());
    EXPECT_EQ(dec_->state(), State::Closed);
}

TEST_P(VideoDecoderContractTest, configuredDecoderNeedsAPacketBeforeDequeue)
{
    configureColor();
    EXPECT_EQ(dec_->state(), State::Configured);
    EXPECT_EQ(errcOf(dec_->dequeueFrame(soon())), Errc::InvalidState);
    EXPECT_EQ(dec_->state(), State::Configured);
    EXPECT_TRUE(dec_->flush()); // no-op
    configureColor();           // reconfigure
    dec_->close();
    EXPECT_EQ(dec_->state(), State::Closed);
}

TEST_P(VideoDecoderContractTest, decodesEveryPacketOfEachStreamThenDrains)
{
    for (const hal::StreamInfo &s : streams_) {
        SCOPED_TRACE(hal::streamKindName(s.kind));
        ASSERT_TRUE(dec_->configure(hal::StreamConfig::fromStream(s)));
        const hal::DecoderStats before = dec_->stats();
        const auto &pkts = packetsOf(s);
        std::vector<hal::Pts> expectedPts;
        std::vector<hal::Pts> gotPts;
        std::uint64_t lastSequence = 0;
        bool draining = false;
        bool ended = false;
        std::size_t next = 0;
        auto take = [&](hal::Deadline until) {
            auto f = dec_->dequeueFrame(until);
            if (!f) {
                if (f.error().code == Errc::EndOfStream)
                    ended = true;
                else {
                    EXPECT_EQ(f.error().code, Errc::Timeout) << f.error().what;
                }
                return;
            }
            const hal::Frame &frame = **f;
            EXPECT_EQ(frame.image.width, s.width);
            EXPECT_EQ(frame.image.height, s.height);
            EXPECT_EQ(frame.image.format, s.format);
            EXPECT_FALSE(frame.image.empty());
            EXPECT_EQ(frame.kind, s.kind);
            EXPECT_FALSE(frame.corrupt);
            if (!gotPts.empty()) {
                EXPECT_GT(frame.sequence, lastSequence);
            }
            lastSequence = frame.sequence;
            gotPts.push_back(frame.pts);
        };
        for (int guard = 0; !ended; ++guard) {
            ASSERT_LT(guard, 10'000) << "decoder makes no progress";
            if (next < pkts.size()) {
                const auto r = dec_->queuePacket(pkts[next].view());
                if (r) {
                    expectedPts.push_back(pkts[next].packet.pts);
                    ++next;
                    EXPECT_EQ(dec_->state(), State::Running);
                    continue;
                }
                ASSERT_EQ(r.error().code, Errc::Busy) << r.error().what;
                take(soon());
            } else if (!draining) {
                ASSERT_TRUE(dec_->queuePacket(hal::Packet::endOfStream(s.index)));
                draining = true;
            } else {
                take(soon());
            }
            ASSERT_LE(gotPts.size(), pkts.size());
        }
        std::sort(expectedPts.begin(), expectedPts.end());
        std::sort(gotPts.begin(), gotPts.end());
        EXPECT_EQ(gotPts, expectedPts);
        const hal::DecoderStats after = dec_->stats();
        EXPECT_EQ(after.packetsQueued - before.packetsQueued, pkts.size());
        EXPECT_EQ(after.framesDecoded - before.framesDecoded, pkts.size());
        // Drained: EndOfStream is sticky and packets are refused until flush().
        EXPECT_EQ(errcOf(dec_->dequeueFrame(soon())), Errc::EndOfStream);
        EXPECT_EQ(errcOf(dec_->queuePacket(pkts[0].view())), Errc::InvalidState);
        ASSERT_TRUE(dec_->flush());
        EXPECT_EQ(dec_->state(), State::Configured);
        EXPECT_TRUE(dec_->queuePacket(pkts[0].view()));
        ASSERT_TRUE(dec_->flush());
    }
}

TEST_P(VideoDecoderContractTest, heldFramesExhaustThePoolAndComeBackOnRelease)
{
    const auto &pkts = configureColorPackets();
    const int pool = dec_->capabilities().poolFrames;
    ASSERT_GT(pkts.size(), static_cast<std::size_t>(pool) + 2);
    std::vector<hal::FrameRef> held;
    std::size_t next = 0;
    bool busy = false;
    for (int guard = 0; !busy && next < pkts.size(); ++guard) {
        ASSERT_LT(guard, 10'000) << "decoder makes no progress";
        if (dec_->queuePacket(pkts[next].view())) {
            ++next;
            continue;
        }
        auto f = dec_->dequeueFrame(soon());
        if (f)
            held.push_back(std::move(*f));
        else if (f.error().code == Errc::Busy)
            busy = true;
        else {
            ASSERT_EQ(f.error().code, Errc::Timeout);
        }
    }
    // Fill the queue with what is left so a frame is pending, then ask again.
    while (next < pkts.size() && dec_->queuePacket(pkts[next].view()))
        ++next;
    auto f = dec_->dequeueFrame(soon());
    ASSERT_FALSE(f);
    EXPECT_EQ(f.error().code, Errc::Busy);
    EXPECT_EQ(held.size(), static_cast<std::size_t>(pool));
    // WHEN one FrameRef is dropped  THEN its frame returns to the pool and decoding goes on
    held.erase(held.begin());
    auto again = dec_->dequeueFrame(soon());
    ASSERT_TRUE(again) << again.error().what;
    held.clear();
}

TEST_P(VideoDecoderContractTest, fullInputQueueIsBusyWithoutBlocking)
{
    const auto &pkts = configureColorPackets();
    const platform::TimePoint start = clock_->clock().now();
    std::size_t accepted = 0;
    bool busy = false;
    for (const OwnedPacket &p : pkts) {
        const auto r = dec_->queuePacket(p.view());
        if (!r) {
            EXPECT_EQ(r.error().code, Errc::Busy);
            busy = true;
            break;
        }
        ++accepted;
    }
    EXPECT_TRUE(busy);
    EXPECT_GE(accepted, static_cast<std::size_t>(dec_->capabilities().queuePackets));
    if (clock_->simulated()) {
        EXPECT_EQ(clock_->clock().now(), start) << "queuePacket() must not wait";
    }
}

TEST_P(VideoDecoderContractTest, flushKeepsHeldFramesValid)
{
    const auto &pkts = configureColorPackets();
    ASSERT_TRUE(dec_->queuePacket(pkts[0].view()));
    auto first = dec_->dequeueFrame(soon());
    ASSERT_TRUE(first);
    const hal::ImageView &img = (*first)->image;
    const std::size_t rowBytes =
        static_cast<std::size_t>(hal::planeLayout(img.format, img.width, img.height, 0).rowBytes);
    const std::vector<std::uint8_t> copy(img.row(0, 0), img.row(0, 0) + rowBytes);
    const hal::Pts pts = (*first)->pts;

    ASSERT_TRUE(dec_->queuePacket(pkts[1].view()));
    ASSERT_TRUE(dec_->flush());
    EXPECT_EQ(dec_->state(), State::Configured);
    // Decoding goes on after the flush (from a keyframe) without touching the held frame.
    ASSERT_TRUE(dec_->queuePacket(pkts[0].view()));
    for (std::size_t i = 1; i < 4; ++i) {
        ASSERT_TRUE(dec_->queuePacket(pkts[i].view()));
    }
    for (int i = 0; i < 3; ++i) {
        ASSERT_TRUE(dec_->dequeueFrame(soon()));
    }
    EXPECT_EQ((*first)->pts, pts);
    EXPECT_EQ(std::memcmp(img.row(0, 0), copy.data(), rowBytes), 0);
}

TEST_P(VideoDecoderContractTest, configureNeedsEveryFrameBack)
{
    const auto &pkts = configureColorPackets();
    ASSERT_TRUE(dec_->queuePacket(pkts[0].view()));
    auto frame = dec_->dequeueFrame(soon());
    ASSERT_TRUE(frame);
    ASSERT_TRUE(dec_->flush());
    EXPECT_EQ(
        errcOf(dec_->configure(hal::StreamConfig::fromStream(stream(hal::StreamKind::Depth)))),
        Errc::Busy);
    EXPECT_EQ(dec_->state(), State::Configured);
    frame->reset();
    EXPECT_TRUE(dec_->configure(hal::StreamConfig::fromStream(stream(hal::StreamKind::Depth))));
    // Running refuses configure() (flush first).
    ASSERT_TRUE(dec_->queuePacket(packetsOf(stream(hal::StreamKind::Depth))[0].view()));
    EXPECT_EQ(
        errcOf(dec_->configure(hal::StreamConfig::fromStream(stream(hal::StreamKind::Depth)))),
        Errc::InvalidState);
    EXPECT_EQ(dec_->state(), State::Running);
}

TEST_P(VideoDecoderContractTest, dequeueWithNothingQueuedTimesOutAtTheDeadline)
{
    const auto &pkts = configureColorPackets();
    ASSERT_TRUE(dec_->queuePacket(pkts[0].view()));
    ASSERT_TRUE(dec_->dequeueFrame(soon()));
    // A deadline in the past polls.
    const platform::TimePoint now = clock_->clock().now();
    EXPECT_EQ(errcOf(dec_->dequeueFrame(now - milliseconds(1))), Errc::Timeout);
    if (clock_->simulated()) {
        EXPECT_EQ(clock_->clock().now(), now);
    }
    // A future deadline waits for it.
    const hal::Deadline until = clock_->clock().now() + milliseconds(5);
    EXPECT_EQ(errcOf(dec_->dequeueFrame(until)), Errc::Timeout);
    EXPECT_GE(clock_->clock().now(), until);
}

DT_CONTRACT_ON_ALL_BACKENDS(VideoDecoderContractTest, drivers::videoDecoderBackends());

} // namespace
} // namespace depthtouch::contract
