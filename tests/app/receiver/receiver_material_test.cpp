// The receiver's material track on the mock backends (deterministic, ManualClock): decoding into
// its own store, pairing with depth frames i and i+1, stills, gaps, a size mismatch, seek, a
// consumer holding frames, a lagging material decoder and memory.
#include <cstring>
#include <functional>
#include <initializer_list>
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

constexpr std::uint32_t kNone = ~std::uint32_t{0};
constexpr std::uint32_t kAny = kNone - 1; ///< An expectation that checks nothing.

/// \brief Adds a material track to a mock clip: a third stream (Mock codec, Rgb24) whose frame k
/// is sent right after the depth packet of frame k when `has(k)`. The mock decoder stamps the frame
/// index into it (readMockFrameIndex()), so a test sees which material frame it got.
class MaterialSource final : public hal::MediaSource {
public:
    std::function<bool(std::uint32_t)> has = [](std::uint32_t) { return true; };
    /// Frame k's packet is sent with its payload damaged (the decoder conceals it) when true.
    std::function<bool(std::uint32_t)> damaged = [](std::uint32_t) { return false; };
    int width = 0;  ///< 0: the depth's.
    int height = 0; ///< 0: the depth's.
    std::string title = "material";
    int lag = 0; ///< Frame k's material is sent after depth frame k + lag instead.

    explicit MaterialSource(std::unique_ptr<hal::MediaSource> inner) : inner_(std::move(inner)) {}

    [[nodiscard]] State state() const noexcept override { return inner_->state(); }
    [[nodiscard]] Result<void> open(const char *url) override
    {
        DT_TRY(inner_->open(url));
        info_ = inner_->info();
        const hal::StreamInfo &depth = info_.streams.back();
        depthIndex_ = depth.index;
        hal::StreamInfo m = depth;
        m.index = static_cast<int>(info_.streams.size());
        m.kind = hal::StreamKind::Color;
        m.title = title;
        m.titleFrom = "title";
        m.format = hal::PixelFormat::Rgb24;
        m.depth = {};
        m.width = width > 0 ? width : depth.width;
        m.height = height > 0 ? height : depth.height;
        info_.streams.push_back(m);
        queued_.clear();
        queued_.reserve(64); // readPacket() must not allocate (noAllocationPerFrameAfterOpen)
        return ok();
    }
    void close() noexcept override { inner_->close(); }
    [[nodiscard]] const hal::MediaInfo &info() const noexcept override { return info_; }
    [[nodiscard]] Result<hal::Packet> readPacket() override
    {
        if (!queued_.empty() && queued_.front().due <= depthSeen_) {
            const Queued q = queued_.front();
            queued_.erase(queued_.begin());
            const hal::StreamInfo &m = info_.streams.back();
            const std::size_t size = drivers::writeMockPacket(buffer_, hal::StreamKind::Color,
                                                              q.frame, m.width, m.height, true);
            if (damaged(q.frame))
                buffer_[size - 1] ^= 0x5a; // the payload, not the header
            hal::Packet p;
            p.streamIndex = m.index;
            p.data = buffer_;
            p.size = size;
            p.pts = p.dts = q.pts;
            p.keyframe = true;
            return p;
        }
        auto p = inner_->readPacket();
        if (!p) {
            if (!queued_.empty() && p.error().code == Errc::EndOfStream) {
                depthSeen_ = ~std::uint64_t{0} >> 1; // flush what lags at the end
                return readPacket();
            }
            return p;
        }
        if (p->streamIndex == depthIndex_) {
            drivers::MockPacketHeader h;
            (void)drivers::parseMockPacket(p->data, p->size, h);
            depthSeen_ = h.frameIndex;
            if (has(h.frameIndex))
                queued_.push_back(
                    {h.frameIndex + static_cast<std::uint64_t>(lag), h.frameIndex, p->pts});
        }
        return p;
    }
    [[nodiscard]] Result<void> seek(hal::Pts position) override
    {
        DT_TRY(inner_->seek(position));
        queued_.clear();
        depthSeen_ = 0;
        return ok();
    }

private:
    struct Queued {
        std::uint64_t due = 0; ///< Depth frame after which it is sent.
        std::uint32_t frame = 0;
        hal::Pts pts = hal::kNoPts;
    };
    std::unique_ptr<hal::MediaSource> inner_;
    hal::MediaInfo info_;
    int depthIndex_ = -1;
    std::uint64_t depthSeen_ = 0;
    std::vector<Queued> queued_;
    std::uint8_t buffer_[drivers::kMockPacketMaxBytes] = {};
};

/// Mock source with a material track + mock decoders on a ManualClock.
class MaterialRig {
public:
    std::function<void(MaterialSource &)> onSource;
    /// Applied to each decoder as it is made, with the stream it decodes.
    std::function<void(drivers::MockVideoDecoder &, const hal::StreamInfo &)> onDecoder;

    Result<std::unique_ptr<Receiver>> open(const std::string &url, const ReceiverConfig &cfg = {})
    {
        auto src = std::make_unique<MaterialSource>(std::make_unique<drivers::MockMediaSource>());
        source = src.get();
        if (onSource)
            onSource(*src);
        receiver::DecoderFactory factory =
            [this](const hal::StreamInfo &si) -> Result<std::unique_ptr<hal::VideoDecoder>> {
            auto dec = std::make_unique<drivers::MockVideoDecoder>(clock);
            if (onDecoder)
                onDecoder(*dec, si);
            return std::unique_ptr<hal::VideoDecoder>(std::move(dec));
        };
        return Receiver::open(std::move(src), url.c_str(), factory, cfg);
    }

    platform::ManualClock clock;
    MaterialSource *source = nullptr;
};

/// What a test checks of the material of one paired frame.
struct MaterialRecord {
    std::uint32_t color = kNone;        ///< Color frame index.
    std::uint32_t material = kNone;     ///< Material frame index of depth i; kNone: empty.
    std::uint32_t materialNext = kNone; ///< Of depth i+1.
    bool hasNext = false;
};

std::uint32_t indexOf(const receiver::FrameHandle &h)
{
    return h ? drivers::readMockFrameIndex(h->image) : kNone;
}

std::vector<MaterialRecord> drainMaterial(Receiver &r, std::size_t limit = 10'000)
{
    return drainAs<MaterialRecord>(r, limit, [](const PairedFrame &f) {
        MaterialRecord m;
        m.color = indexOf(f.color);
        m.material = indexOf(f.material);
        m.materialNext = indexOf(f.materialNext);
        m.hasNext = static_cast<bool>(f.depthNext);
        const receiver::StoredDepthPair p = f.depthPair();
        EXPECT_EQ(p.material, f.material.get());
        EXPECT_EQ(p.materialNext, f.materialNext.get());
        return m;
    });
}

/// Expects the material counters of \a s: \a frames material frames decoded, \a held outputs that
/// reused an older material frame, \a missing outputs without one.
void expectMaterialCounts(const receiver::ReceiverStats &s, std::uint64_t frames,
                          std::uint64_t held, std::uint64_t missing)
{
    EXPECT_EQ(s.materialFrames, frames);
    EXPECT_EQ(s.materialHeld, held);
    EXPECT_EQ(s.materialMissing, missing);
}

/// What a test expects of depth frame \a frame: the material frame paired with it as frame i and
/// the one paired as frame i+1 (kAny: not checked).
struct ExpectedMaterial {
    std::size_t frame = 0;
    std::uint32_t material = kAny;
    std::uint32_t materialNext = kAny;
};

/// Expects each of \a expected of \a frames.
void expectMaterials(const std::vector<MaterialRecord> &frames,
                     std::initializer_list<ExpectedMaterial> expected)
{
    for (const ExpectedMaterial &e : expected) {
        ASSERT_LT(e.frame, frames.size());
        if (e.material != kAny) {
            EXPECT_EQ(frames[e.frame].material, e.material) << "depth frame " << e.frame;
        }
        if (e.materialNext != kAny) {
            EXPECT_EQ(frames[e.frame].materialNext, e.materialNext) << "depth frame " << e.frame;
        }
    }
}

/// Reads every paired frame of \a r and expects \a count of them, none with material (the file
/// plays on without its material track). \return the receiver's counters after the last frame.
receiver::ReceiverStats drainWithoutMaterial(Receiver &r, std::size_t count)
{
    const auto frames = drainMaterial(r);
    EXPECT_EQ(frames.size(), count);
    for (const auto &m : frames)
        EXPECT_EQ(m.material, kNone);
    return r.stats();
}

/// What a test reads of a material clip: every paired frame, then the receiver's counters.
struct MaterialRun {
    std::vector<MaterialRecord> frames;
    receiver::ReceiverStats stats;
};

/// Opens \a url on a MaterialRig whose source \a setUp adjusts, and reads every paired frame
/// (drainMaterial()). A failed open is a test failure and reads no frame.
MaterialRun readMaterialClip(const std::string &url,
                             const std::function<void(MaterialSource &)> &setUp)
{
    MaterialRig rig;
    rig.onSource = setUp;
    auto r = rig.open(url);
    if (!r) {
        ADD_FAILURE() << "open(" << url << ") failed: " << r.error().what;
        return {};
    }
    MaterialRun run;
    run.frames = drainMaterial(**r);
    run.stats = (*r)->stats();
    return run;
}

TEST(ReceiverMaterialTest, eachDepthFrameGetsTheMaterialFrameOfItsPts)
{
    // GIVEN a clip of 20 frames with one material frame per depth frame
    MaterialRig rig;
    auto r = rig.open("mock://clip?frames=20&fps=25&width=32&height=24");
    ASSERT_TRUE(r) << r.error().what;
    const receiver::ReceiverInfo &info = (*r)->info();
    ASSERT_TRUE(info.hasMaterial);
    EXPECT_EQ(info.roles.material, 2);
    EXPECT_STREQ(info.roles.materialReason, "title");
    EXPECT_EQ(info.material.index, 2);
    EXPECT_EQ(info.mode, receiver::ReceiverMode::ColorAndDepth);
    // WHEN every paired frame is read
    PairedFrame f;
    auto n = (*r)->next(f);
    ASSERT_TRUE(n && *n);
    ASSERT_TRUE(f.material);
    EXPECT_EQ(f.material->image.format, hal::PixelFormat::Rgb24);
    EXPECT_EQ(f.material->image.width, f.depth->image.width);
    EXPECT_EQ(f.material->image.height, f.depth->image.height);
    EXPECT_EQ(f.material->pts, f.depth->pts);
    f = PairedFrame{};
    const auto rest = drainMaterial(**r);
    // THEN color i has material i and material i+1 (none after the last depth frame)
    ASSERT_EQ(rest.size(), 19u);
    for (std::size_t k = 0; k < rest.size(); ++k) {
        const auto i = static_cast<std::uint32_t>(k + 1);
        EXPECT_EQ(rest[k].color, i);
        EXPECT_EQ(rest[k].material, i);
        EXPECT_EQ(rest[k].materialNext, rest[k].hasNext ? i + 1 : kNone);
    }
    const auto s = (*r)->stats();
    expectMaterialCounts(s, 20, 0, 0);
    EXPECT_EQ(s.pairingForced, 0u);
    EXPECT_EQ(s.framesOutput, 20u);
}

TEST(ReceiverMaterialTest, stillMaterialHoldsForTheWholeVideo)
{
    // GIVEN one material frame, at the first PTS
    const MaterialRun run = readMaterialClip("mock://clip?frames=30", [](MaterialSource &s) {
        s.has = [](std::uint32_t k) { return k == 0; };
    });
    // THEN every frame plays with it, as frame i and as frame i+1
    ASSERT_EQ(run.frames.size(), 30u);
    for (const auto &m : run.frames) {
        EXPECT_EQ(m.material, 0u);
        EXPECT_EQ(m.materialNext, m.hasNext ? 0u : kNone);
    }
    expectMaterialCounts(run.stats, 1, 29, 0);
}

TEST(ReceiverMaterialTest, missingMaterialFrameIsHeldAndCounted)
{
    // GIVEN material frame 7 lost, and none before frame 2
    const MaterialRun run = readMaterialClip("mock://clip?frames=12", [](MaterialSource &s) {
        s.has = [](std::uint32_t k) { return k != 7 && k >= 2; };
    });
    const auto &frames = run.frames;
    ASSERT_EQ(frames.size(), 12u);
    // THEN frames 0 and 1 have none, frame 7 holds frame 6's, the others their own
    expectMaterials(frames, {{0, kNone}, {1, kNone, 2}, {6, kAny, 6}, {7, 6, 8}, {8, 8}});
    expectMaterialCounts(run.stats, 9, 1, 2);
}

TEST(ReceiverMaterialTest, damagedMaterialFramesAreSkippedAndThePreviousHolds)
{
    // GIVEN material frames 4 and 5 damaged (a damaged file: the decoder conceals them, and their
    // concealed codes would read as stiffness 0, nothing under the finger)
    const MaterialRun run = readMaterialClip("mock://clip?frames=10", [](MaterialSource &s) {
        s.damaged = [](std::uint32_t k) { return k == 4 || k == 5; };
    });
    const auto &frames = run.frames;
    ASSERT_EQ(frames.size(), 10u);
    // THEN depth frames 4 and 5 keep frame 3's material, and frame 6 has its own again
    expectMaterials(frames, {{3, 3}, {4, 3}, {5, 3, 6}, {6, 6}});
    // AND the damage is counted, apart from frames that never came
    EXPECT_EQ(run.stats.materialDamaged, 2u);
    expectMaterialCounts(run.stats, 10, 2, 0);
}

TEST(ReceiverMaterialTest, twoMissingMaterialFramesInARowHoldTheLastOne)
{
    // GIVEN material frames 7 and 8 lost (a gap of two)
    const MaterialRun run = readMaterialClip("mock://clip?frames=12", [](MaterialSource &s) {
        s.has = [](std::uint32_t k) { return k != 7 && k != 8; };
    });
    const auto &frames = run.frames;
    ASSERT_EQ(frames.size(), 12u);
    // THEN depth frames 7 and 8 play with frame 6's material, as frame i and as frame i+1: never
    // with none (the stiffness and friction of the material would vanish under the finger)
    expectMaterials(frames, {{6, 6, 6}, {7, 6, 6}, {8, 6, 9}, {9, 9}});
    for (std::size_t i = 0; i < frames.size(); ++i)
        EXPECT_NE(frames[i].material, kNone) << "depth frame " << i << " has no material";
    expectMaterialCounts(run.stats, 10, 2, 0);
}

TEST(ReceiverMaterialTest, depthOnlyFileWithMaterialFindsDepth)
{
    MaterialRig rig;
    auto r = rig.open("mock://clip?frames=6&color=0");
    ASSERT_TRUE(r);
    EXPECT_EQ((*r)->info().mode, receiver::ReceiverMode::DepthOnly);
    EXPECT_EQ((*r)->info().roles.depth, 0);
    ASSERT_TRUE((*r)->info().hasMaterial);
    const auto frames = drainMaterial(**r);
    ASSERT_EQ(frames.size(), 6u);
    for (std::uint32_t i = 0; i < 6; ++i)
        EXPECT_EQ(frames[i].material, i);
}

TEST(ReceiverMaterialTest, materialOfAnotherSizeIsLeftOutAndTheFilePlays)
{
    MaterialRig rig;
    rig.onSource = [](MaterialSource &s) { s.width = 32; };
    auto r = rig.open("mock://clip?frames=10&width=64&height=48");
    ASSERT_TRUE(r) << r.error().what;
    EXPECT_FALSE((*r)->info().hasMaterial);
    EXPECT_EQ((*r)->info().roles.material, 2); // found, then refused
    EXPECT_TRUE(hasNoteWith((*r)->info(), "material stream 2 left out: its size 32x48"));
    const auto s = drainWithoutMaterial(**r, 10);
    EXPECT_EQ(s.materialFrames, 0u);
    EXPECT_EQ(s.materialMissing, 0u); // no track: nothing is missing
    EXPECT_EQ(s.packetsIgnored, 10u);
}

TEST(ReceiverMaterialTest, materialNoDecoderTakesIsLeftOutAndTheFilePlays)
{
    MaterialRig rig;
    rig.onDecoder = [](drivers::MockVideoDecoder &d, const hal::StreamInfo &si) {
        if (si.title == "material")
            d.failNextConfigure(Errc::NotSupported);
    };
    auto r = rig.open("mock://clip?frames=5");
    ASSERT_TRUE(r);
    EXPECT_FALSE((*r)->info().hasMaterial);
    EXPECT_TRUE(hasNoteWith((*r)->info(), "material stream 2"));
    EXPECT_EQ(drainMaterial(**r).size(), 5u);
}

TEST(ReceiverMaterialTest, seekFlushesTheMaterialAndAStillHoldsAfterIt)
{
    // GIVEN one material frame per depth frame
    MaterialRig rig;
    std::unique_ptr<Receiver> r;
    // WHEN seeking to 1 s (frame 25)
    ASSERT_TRUE(openReadAndSeekTo1s(rig, r));
    const auto frames = drainMaterial(*r);
    // THEN frames 25..49 come with their own material
    ASSERT_EQ(frames.size(), 25u);
    for (std::size_t k = 0; k < frames.size(); ++k)
        EXPECT_EQ(frames[k].material, frames[k].color) << k;
    EXPECT_EQ(r->stats().materialMissing, 0u);
    // AND backwards: the material frames before the old position pair again
    ASSERT_TRUE(r->seek(milliseconds(0)));
    const auto again = drainMaterial(*r);
    ASSERT_EQ(again.size(), 50u);
    for (std::size_t k = 0; k < again.size(); ++k)
        EXPECT_EQ(again[k].material, again[k].color) << k;
    EXPECT_EQ(r->stats().materialMissing, 0u);

    // GIVEN a still material: WHEN seeking forward past it, THEN it still holds
    MaterialRig still;
    still.onSource = [](MaterialSource &s) { s.has = [](std::uint32_t k) { return k == 0; }; };
    std::unique_ptr<Receiver> s;
    ASSERT_TRUE(
        openReadAndSeek(still, "mock://clip?frames=50&fps=25&gop=10", 3, milliseconds(1200), s));
    const auto after = drainMaterial(*s);
    ASSERT_EQ(after.size(), 20u);
    for (const auto &m : after)
        EXPECT_EQ(m.material, 0u);
    EXPECT_EQ(s->stats().materialMissing, 0u);
}

TEST(ReceiverMaterialTest, consumerHoldingFramesHoldsTheirMaterialFrames)
{
    // GIVEN a consumer that keeps every paired frame
    MaterialRig rig;
    HoldingConsumer consumer = holdEveryFrame(rig, "mock://clip?frames=40", 100);
    ASSERT_TRUE(consumer.receiver);
    EXPECT_EQ(consumer.refusal, Errc::Busy);
    const std::vector<PairedFrame> &held = consumer.held;
    ASSERT_GE(held.size(), static_cast<std::size_t>(kHeldConsumerFrames));
    // THEN each held frame still holds the material frames of its own depth frames (40 ms per
    // frame), none reused for later frames
    const auto frameOf = [](const receiver::FrameHandle &h) {
        return static_cast<std::uint32_t>(h->pts / milliseconds(40));
    };
    for (const auto &f : held) {
        ASSERT_TRUE(f.depth && f.material);
        EXPECT_EQ(drivers::readMockFrameIndex(f.material->image), frameOf(f.depth));
        EXPECT_EQ(f.material->pts, f.depth->pts);
        if (f.depthNext) {
            ASSERT_TRUE(f.materialNext);
            EXPECT_EQ(drivers::readMockFrameIndex(f.materialNext->image), frameOf(f.depthNext));
        }
    }
    // AND once it lets go, nothing was lost
    const std::size_t before = consumer.letGo();
    EXPECT_EQ(before + drainMaterial(*consumer.receiver).size(), 40u);
}

TEST(ReceiverMaterialTest, lateMaterialPacketsAreStillPaired)
{
    // GIVEN material packets written 2 frames after their depth frame (within the window)
    const MaterialRun run =
        readMaterialClip("mock://clip?frames=20", [](MaterialSource &s) { s.lag = 2; });
    ASSERT_EQ(run.frames.size(), 20u);
    for (std::uint32_t i = 0; i < 20; ++i)
        EXPECT_EQ(run.frames[i].material, i);
    EXPECT_EQ(run.stats.pairingForced, 0u);
}

TEST(ReceiverMaterialTest, materialDecoderThatNeverOutputsCannotStallPairing)
{
    // GIVEN a material decoder that never gives a frame (every frame lent)
    MaterialRig rig;
    rig.onDecoder = [](drivers::MockVideoDecoder &d, const hal::StreamInfo &si) {
        if (si.title == "material")
            d.exhaustPool(true);
    };
    ReceiverConfig cfg;
    cfg.pairingWindow = 2;
    auto r = rig.open("mock://clip?frames=30", cfg);
    ASSERT_TRUE(r);
    // THEN every frame still comes out, without material, decided early
    const auto s = drainWithoutMaterial(**r, 30);
    EXPECT_GT(s.pairingForced, 0u);
    EXPECT_EQ(s.materialMissing, 30u);
}

TEST(ReceiverMaterialTest, noAllocationPerFrameAfterOpen)
{
    MaterialRig rig;
    auto r = rig.open("mock://clip?frames=200&fps=25&width=32&height=24");
    ASSERT_TRUE(r);
    std::size_t withMaterial = 0;
    const CountedDrain d = drainCountingAllocations(
        **r, [&](const PairedFrame &f) { withMaterial += f.material ? 1u : 0u; });
    EXPECT_EQ(d.allocations, 0u);
    EXPECT_EQ(d.frames, 199u);
    EXPECT_EQ(withMaterial, 199u);
}

} // namespace
} // namespace depthtouch::receivertest
