// Receiver on the mock backends (deterministic, ManualClock): pairing, bad input, seek, memory.
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/drivers/mock/mock_media_source.h"
#include "depthtouch/drivers/mock/mock_pattern.h"
#include "depthtouch/drivers/mock/mock_video_decoder.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/receiver/receiver.h"
#include "test_support.h"

namespace depthtouch::receivertest {
namespace {

using receiver::PairedFrame;
using receiver::Receiver;
using receiver::ReceiverConfig;
using std::chrono::milliseconds;

/// Mock source + mock decoders on a ManualClock, with hooks for fault injection.
class MockRig {
public:
    /// Applied to the source before open().
    std::function<void(drivers::MockMediaSource &)> onSource;
    /// Applied to each decoder as it is made (stream kind from the title).
    std::function<void(drivers::MockVideoDecoder &, const hal::StreamInfo &)> onDecoder;
    FaultySource::InfoEdit editInfo;
    FaultySource::PacketEdit editPacket;

    Result<std::unique_ptr<Receiver>> open(const std::string &url, const ReceiverConfig &cfg = {})
    {
        auto src = std::make_unique<drivers::MockMediaSource>();
        source = src.get();
        if (onSource)
            onSource(*src);
        std::unique_ptr<hal::MediaSource> s = std::move(src);
        if (editInfo || editPacket)
            s = std::make_unique<FaultySource>(std::move(s), editInfo, editPacket);
        receiver::DecoderFactory factory =
            [this](const hal::StreamInfo &si) -> Result<std::unique_ptr<hal::VideoDecoder>> {
            auto dec = std::make_unique<drivers::MockVideoDecoder>(clock);
            decoders.push_back(dec.get());
            if (onDecoder)
                onDecoder(*dec, si);
            return std::unique_ptr<hal::VideoDecoder>(std::move(dec));
        };
        return Receiver::open(std::move(s), url.c_str(), factory, cfg);
    }

    platform::ManualClock clock;
    drivers::MockMediaSource *source = nullptr;
    std::vector<drivers::MockVideoDecoder *> decoders;
};

/// The mock depth frame the decoder renders at \a pts.
std::vector<std::uint8_t> mockDepthAt(hal::Pts pts, int width, int height)
{
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width * height));
    hal::ImageView v;
    v.width = width;
    v.height = height;
    v.format = hal::PixelFormat::Gray8;
    v.planes[0] = {pixels.data(), width};
    drivers::renderMockDepth(v, platform::toSeconds(pts));
    return pixels;
}

bool sameDepth(const receiver::StoredFrame &f, const std::vector<std::uint8_t> &expected)
{
    const auto n = static_cast<std::size_t>(f.image.width * f.image.height);
    return n == expected.size() && std::memcmp(f.image.planes[0].data, expected.data(), n) == 0;
}

TEST(ReceiverMockTest, framePeriodsComeFromTheStreamsRates)
{
    // GIVEN clips at 1 fps (a still shown once a second), 25 fps and 240 fps
    for (const int fps : {1, 25, 240}) {
        MockRig rig;
        auto r = rig.open("mock://clip?frames=3&fps=" + std::to_string(fps));
        ASSERT_TRUE(r) << r.error().what;
        // THEN the pairer's frame periods are 1/fps (ns, rounded)
        const hal::Pts want(std::llround(1e9 / fps));
        EXPECT_EQ((*r)->info().colorPeriod, want) << fps << " fps";
        EXPECT_EQ((*r)->info().depthPeriod, want) << fps << " fps";
    }
    // AND a clip whose streams give no rate (0/0) is paired at 30 fps, the documented default
    MockRig rig;
    rig.editInfo = [](hal::MediaInfo &mi) {
        for (hal::StreamInfo &s : mi.streams)
            s.frameRate = hal::Rational{0, 0};
    };
    auto r = rig.open("mock://clip?frames=3");
    ASSERT_TRUE(r) << r.error().what;
    EXPECT_EQ((*r)->info().colorPeriod, hal::Pts(33'333'333));
    EXPECT_EQ((*r)->info().depthPeriod, hal::Pts(33'333'333));
}

TEST(ReceiverMockTest, framePeriodsOutsideOneTenthHertzToTenKilohertzAreTakenAsUnknown)
{
    // GIVEN streams whose rates give periods at and beyond the limits the receiver trusts
    // (0.1 ms to 10 s): a rate beyond them is a broken header, paired at the 30 fps default
    struct Case {
        hal::Rational rate;
        hal::Pts want;
    };
    const hal::Pts unknown(33'333'333);
    for (const Case &c :
         {Case{{1, 10}, hal::Pts(10'000'000'000)}, Case{{1, 15}, unknown}, Case{{2, 31}, unknown},
          Case{{10'000, 1}, hal::Pts(100'000)}, Case{{20'000, 1}, unknown}}) {
        MockRig rig;
        rig.editInfo = [&c](hal::MediaInfo &mi) {
            for (hal::StreamInfo &s : mi.streams)
                s.frameRate = c.rate;
        };
        auto r = rig.open("mock://clip?frames=3");
        ASSERT_TRUE(r) << r.error().what;
        // THEN the period is 1/rate inside the limits, the default outside them
        EXPECT_EQ((*r)->info().colorPeriod, c.want) << c.rate.num << "/" << c.rate.den;
        EXPECT_EQ((*r)->info().depthPeriod, c.want) << c.rate.num << "/" << c.rate.den;
    }
}

TEST(ReceiverMockTest, pairsEveryColorFrameWithItsDepthFrameAndTheNext)
{
    // GIVEN a mock clip of 20 frames at 25 fps with color and depth
    MockRig rig;
    auto r = rig.open("mock://clip?frames=20&fps=25&width=32&height=24");
    ASSERT_TRUE(r) << r.error().what;
    const receiver::ReceiverInfo &info = (*r)->info();
    EXPECT_EQ(info.mode, receiver::ReceiverMode::ColorAndDepth);
    EXPECT_EQ(info.roles.colorReason, std::string("title"));
    EXPECT_DOUBLE_EQ(info.depth.depth.nearMetres, 0.5);
    EXPECT_EQ(info.depth.depth.mapping, "inverse");
    EXPECT_EQ(info.tolerance, milliseconds(20));
    // WHEN every paired frame is read
    int count = 0;
    PairedFrame f;
    for (;;) {
        auto n = (*r)->next(f);
        ASSERT_TRUE(n);
        if (!*n)
            break;
        // THEN color i has depth i (rendered at the same time) and depth i+1
        ASSERT_TRUE(f.color);
        EXPECT_EQ(drivers::readMockFrameIndex(f.color->image), static_cast<std::uint32_t>(count));
        EXPECT_EQ(f.pts, milliseconds(40 * count));
        const receiver::StoredDepthPair pair = f.depthPair();
        ASSERT_NE(pair.current, nullptr);
        EXPECT_EQ(pair.currentPts, f.pts);
        EXPECT_TRUE(sameDepth(*pair.current, mockDepthAt(f.pts, 32, 24))) << count;
        if (count < 19) {
            ASSERT_NE(pair.next, nullptr) << count;
            EXPECT_EQ(pair.nextPts, f.pts + milliseconds(40));
            EXPECT_TRUE(sameDepth(*pair.next, mockDepthAt(pair.nextPts, 32, 24)));
        } else {
            EXPECT_EQ(pair.next, nullptr);
        }
        EXPECT_FALSE(f.depthMissing || f.depthDuplicated || f.concealed);
        EXPECT_EQ(f.index, static_cast<std::uint64_t>(count));
        ++count;
    }
    EXPECT_EQ(count, 20);
    const auto s = (*r)->stats();
    EXPECT_EQ(s.colorFrames, 20u);
    EXPECT_EQ(s.depthFrames, 20u);
    EXPECT_EQ(s.framesOutput, 20u);
    EXPECT_EQ(s.depthUnpaired, 0u);
    EXPECT_TRUE((*r)->ended());
    // the end is sticky
    auto again = (*r)->next(f);
    ASSERT_TRUE(again);
    EXPECT_FALSE(*again);
}

TEST(ReceiverMockTest, theDepthPairIsOnTheOutputTimelineAcrossATimestampReset)
{
    // GIVEN an encoder reset at frame 10 (its PTS start again at 0)  WHEN reading every pair  THEN
    // depth frame i+1 is after frame i on the output timeline, as the haptic task interpolates
    // between them (the stored frames keep their stream's own PTS, which go back at the reset).
    MockRig rig;
    rig.onSource = [](drivers::MockMediaSource &s) {
        s.jumpPtsAt(10, -std::chrono::duration_cast<hal::Pts>(std::chrono::milliseconds(400)));
    };
    auto r = rig.open("mock://clip?frames=20&fps=25&width=32&height=24");
    ASSERT_TRUE(r);
    receiver::PairedFrame f;
    hal::Pts last = hal::kNoPts;
    int pairs = 0;
    int outputs = 0;
    int discontinuities = 0;
    for (int i = 0; i < 40; ++i) {
        auto n = (*r)->next(f);
        ASSERT_TRUE(n);
        if (!*n)
            break;
        const receiver::StoredDepthPair p = f.depthPair();
        ASSERT_NE(p.current, nullptr);
        EXPECT_EQ(p.currentPts, f.pts) << "depth i is the color frame's, on its timeline";
        if (p.next != nullptr) {
            EXPECT_GT(p.nextPts, p.currentPts) << "output " << f.index;
            ++pairs;
        }
        if (last != hal::kNoPts) {
            EXPECT_GT(f.pts, last);
        }
        last = f.pts;
        discontinuities += f.discontinuity ? 1 : 0;
        ++outputs;
        f = receiver::PairedFrame{};
    }
    EXPECT_GE(outputs, 19) << "at most the frame that confirms the reset is lost";
    EXPECT_EQ(pairs, outputs - 1) << "every output but the last has its next depth frame";
    EXPECT_EQ(discontinuities, 1);
}

TEST(ReceiverMockTest, noAllocationPerFrameAfterOpen)
{
    MockRig rig;
    auto r = rig.open("mock://clip?frames=200&fps=25&width=32&height=24");
    ASSERT_TRUE(r);
    const CountedDrain d = drainCountingAllocations(**r, [](const PairedFrame &) {});
    EXPECT_EQ(d.allocations, 0u);
    EXPECT_EQ(d.frames, 199u);
}

TEST(ReceiverMockTest, corruptPacketIsConcealedAndDecodingGoesOn)
{
    MockRig rig;
    rig.onSource = [](drivers::MockMediaSource &s) { s.corruptPacket(7); }; // depth of frame 3
    auto r = rig.open("mock://clip?frames=10");
    ASSERT_TRUE(r);
    const auto frames = drain(**r);
    ASSERT_EQ(frames.size(), 10u);
    int concealed = 0;
    for (const auto &f : frames)
        concealed += f.concealed ? 1 : 0;
    EXPECT_EQ(concealed, 1);
    EXPECT_TRUE(frames[3].concealed);
    EXPECT_EQ((*r)->stats().framesConcealed, 1u);
}

TEST(ReceiverMockTest, undecodablePacketIsCountedAndItsFrameBridged)
{
    MockRig rig;
    rig.onDecoder = [](drivers::MockVideoDecoder &d, const hal::StreamInfo &si) {
        if (si.kind == hal::StreamKind::Depth)
            d.failPacket(4);
    };
    auto r = rig.open("mock://clip?frames=10");
    ASSERT_TRUE(r);
    const auto frames = drain(**r);
    ASSERT_EQ(frames.size(), 10u);
    EXPECT_TRUE(frames[4].depthDuplicated);
    EXPECT_EQ(frames[4].depthPts, frames[3].depthPts);
    EXPECT_EQ(frames[3].nextPts, frames[5].pts); // frame 4's depth never existed
    const auto s = (*r)->stats();
    EXPECT_EQ(s.decodeErrors, 1u);
    EXPECT_EQ(s.depthDuplicated, 1u);
}

TEST(ReceiverMockTest, truncatedInputEndsCleanlyWithTheFramesBeforeTheCut)
{
    MockRig rig;
    rig.onSource = [](drivers::MockMediaSource &s) { s.truncateAt(12); }; // 6 frames of each
    auto r = rig.open("mock://clip?frames=50");
    ASSERT_TRUE(r);
    const auto frames = drain(**r);
    EXPECT_EQ(frames.size(), 6u);
    EXPECT_FALSE(frames.back().hasNext);
    EXPECT_EQ((*r)->stats().readErrors, 1u);
    EXPECT_TRUE((*r)->ended());
}

TEST(ReceiverMockTest, colorOnlyAndDepthOnlyInputsAreAcceptedAndReported)
{
    MockRig rig;
    auto colorOnly = rig.open("mock://clip?frames=5&depth=0");
    ASSERT_TRUE(colorOnly);
    EXPECT_EQ((*colorOnly)->info().mode, receiver::ReceiverMode::ColorOnly);
    EXPECT_FALSE((*colorOnly)->info().notes.empty());
    const auto c = drain(**colorOnly);
    ASSERT_EQ(c.size(), 5u);
    for (const auto &f : c)
        EXPECT_TRUE(f.depthMissing && f.hasColor && !f.hasDepth);

    MockRig rig2;
    auto depthOnly = rig2.open("mock://clip?frames=5&color=0");
    ASSERT_TRUE(depthOnly);
    EXPECT_EQ((*depthOnly)->info().mode, receiver::ReceiverMode::DepthOnly);
    const auto d = drain(**depthOnly);
    ASSERT_EQ(d.size(), 5u);
    for (std::size_t i = 0; i < d.size(); ++i) {
        EXPECT_FALSE(d[i].hasColor);
        EXPECT_TRUE(d[i].hasDepth);
        EXPECT_EQ(d[i].hasNext, i + 1 < d.size());
    }
}

TEST(ReceiverMockTest, requiredStreamMissingIsAClearError)
{
    MockRig rig;
    ReceiverConfig cfg;
    cfg.requireDepth = true;
    auto r = rig.open("mock://clip?depth=0", cfg);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::NotSupported);
}

TEST(ReceiverMockTest, streamTheDecoderRefusesIsLeftOut)
{
    // GIVEN a depth decoder that refuses its stream (an unsupported codec)
    MockRig rig;
    rig.onDecoder = [](drivers::MockVideoDecoder &d, const hal::StreamInfo &si) {
        if (si.kind == hal::StreamKind::Depth)
            d.failNextConfigure(Errc::NotSupported);
    };
    auto r = rig.open("mock://clip?frames=4");
    ASSERT_TRUE(r);
    EXPECT_EQ((*r)->info().mode, receiver::ReceiverMode::ColorOnly);
    EXPECT_EQ(drain(**r).size(), 4u);

    // AND when every stream is refused, open() fails with the decoder's error
    MockRig rig2;
    rig2.onDecoder = [](drivers::MockVideoDecoder &d, const hal::StreamInfo &) {
        d.failNextConfigure(Errc::NotSupported);
    };
    auto none = rig2.open("mock://clip");
    ASSERT_FALSE(none);
    EXPECT_EQ(none.error().code, Errc::NotSupported);
}

TEST(ReceiverMockTest, zeroOrHugeFrameSizesAreRefused)
{
    for (const int width : {0, -5, 100'000}) {
        MockRig rig;
        rig.editInfo = [width](hal::MediaInfo &mi) {
            for (auto &s : mi.streams)
                s.width = width;
        };
        auto r = rig.open("mock://clip");
        ASSERT_FALSE(r) << width;
        EXPECT_EQ(r.error().code, Errc::InvalidArgument);
    }
    // one bad stream: the other plays
    MockRig rig;
    rig.editInfo = [](hal::MediaInfo &mi) { mi.streams[1].height = 0; };
    auto r = rig.open("mock://clip?frames=3");
    ASSERT_TRUE(r);
    EXPECT_EQ((*r)->info().mode, receiver::ReceiverMode::ColorOnly);
    // and a size within the limits but above the memory bound
    MockRig rig2;
    ReceiverConfig small;
    small.maxPoolBytes = 1000;
    auto tooBig = rig2.open("mock://clip", small);
    ASSERT_FALSE(tooBig);
    EXPECT_EQ(tooBig.error().code, Errc::OutOfResources);
}

TEST(ReceiverMockTest, duplicateBackwardAndGappedPtsAreCountedNeverFatal)
{
    MockRig rig;
    // packet ordinals: 2k color, 2k+1 depth of frame k (40 ms each)
    rig.editPacket = [](hal::Packet &p, std::uint64_t ordinal) {
        if (ordinal == 9) // depth of frame 4 gets frame 3's PTS (duplicate)
            p.pts = milliseconds(120);
        if (ordinal == 12) // color of frame 6 jumps back (non-monotonic)
            p.pts = milliseconds(40);
        if (ordinal == 16 || ordinal == 17) // frame 8 lost in both streams (gap)
            return false;
        return true;
    };
    auto r = rig.open("mock://clip?frames=12");
    ASSERT_TRUE(r);
    const auto frames = drain(**r);
    const auto s = (*r)->stats();
    EXPECT_EQ(s.ptsDuplicates, 1u);
    EXPECT_EQ(s.ptsNonMonotonic, 1u);
    // gaps: color 5→7 (6 dropped) and 7→9, depth 3→5 (4 dropped) and 7→9
    EXPECT_EQ(s.ptsGaps, 4u);
    // 12 frames - color 6 (dropped) - frame 8 (lost) = 10 outputs, in increasing PTS order
    ASSERT_EQ(frames.size(), 10u);
    for (std::size_t i = 1; i < frames.size(); ++i)
        EXPECT_GT(frames[i].pts, frames[i - 1].pts);
    EXPECT_TRUE(frames[4].depthDuplicated); // frame 4's depth was the dropped duplicate
}

TEST(ReceiverMockTest, consumerHoldingEveryFrameGetsBusyAndLosesNothing)
{
    MockRig rig;
    HoldingConsumer consumer = holdEveryFrame(rig, "mock://clip?frames=40", 100);
    ASSERT_TRUE(consumer.receiver);
    EXPECT_EQ(consumer.refusal, Errc::Busy);
    EXPECT_GT(consumer.receiver->stats().consumerBusy, 0u);
    const std::size_t before = consumer.letGo();
    const auto rest = drain(*consumer.receiver);
    EXPECT_EQ(before + rest.size(), 40u);
}

TEST(ReceiverMockTest, seekRestartsAtTheTargetWithFreshPairing)
{
    MockRig rig;
    std::unique_ptr<Receiver> r;
    ASSERT_TRUE(openReadAndSeekTo1s(rig, r));
    const auto frames = drain(*r);
    // frames 25..49: decoding restarts at the keyframe (20) and skips up to the target
    ASSERT_EQ(frames.size(), 25u);
    EXPECT_EQ(frames.front().pts, milliseconds(1000));
    EXPECT_EQ(frames.front().index, 0u);
    EXPECT_EQ(frames.front().depthPts, milliseconds(1000));
    // and backwards
    ASSERT_TRUE(r->seek(milliseconds(0)));
    EXPECT_EQ(drain(*r).size(), 50u);
    EXPECT_EQ(r->stats().seeks, 2u);
}

TEST(ReceiverMockTest, unreadableInputIsTheSourceError)
{
    MockRig rig;
    rig.onSource = [](drivers::MockMediaSource &s) { s.failNextOpen(Errc::Io); };
    auto r = rig.open("mock://clip");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::Io);
    MockRig rig2;
    auto bad = rig2.open("notmock://x");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().code, Errc::NotSupported);
}

} // namespace
} // namespace depthtouch::receivertest
