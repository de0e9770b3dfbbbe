// HAL contract: hal::MediaSource (media_source.h), for every backend in the media source table.
#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "contract_support.h"

namespace depthtouch::contract {
namespace {

using hal::MediaSource;
using State = MediaSource::State;

class MediaSourceContractTest : public BackendContractTest<MediaSource, MediaSourceHarness> {
protected:
    void SetUp() override
    {
        createBackend(mediaSourceHarness, "media source", nullptr, drivers::createMediaSource);
    }
    void openOrFail() { ASSERT_TRUE(src_->open(harness_->url.c_str())) << harness_->url; }

    std::unique_ptr<MediaSource> &src_ = backend_;
};

TEST_P(MediaSourceContractTest, closedSourceRejectsReadsAndSeeks)
{
    EXPECT_EQ(src_->state(), State::Closed);
    EXPECT_TRUE(src_->info().streams.empty());
    EXPECT_EQ(errcOf(src_->readPacket()), Errc::InvalidState);
    EXPECT_EQ(errcOf(src_->seek(hal::Pts{0})), Errc::InvalidState);
    src_->close(); // no-op
    EXPECT_EQ(src_->state(), State::Closed);
}

TEST_P(MediaSourceContractTest, badUrlLeavesTheSourceClosed)
{
    const auto r = src_->open(harness_->badUrl.c_str());
    ASSERT_FALSE(r);
    const Errc code = r.error().code;
    EXPECT_TRUE(code == Errc::NotSupported || code == Errc::NoDevice || code == Errc::Io ||
                code == Errc::InvalidArgument)
        << errcName(code);
    EXPECT_EQ(src_->state(), State::Closed);
    openOrFail();
}

TEST_P(MediaSourceContractTest, openListsAColorAndADepthStream)
{
    openOrFail();
    EXPECT_EQ(src_->state(), State::Open);
    const hal::MediaInfo &info = src_->info();
    int color = 0;
    int depth = 0;
    for (std::size_t i = 0; i < info.streams.size(); ++i) {
        const hal::StreamInfo &s = info.streams[i];
        EXPECT_EQ(s.index, static_cast<int>(i));
        EXPECT_GT(s.width, 0);
        EXPECT_GT(s.height, 0);
        EXPECT_NE(s.codec, hal::CodecId::Unknown);
        EXPECT_GT(s.frameRate.toDouble(), 0.0);
        if (s.kind == hal::StreamKind::Color) {
            ++color;
            EXPECT_EQ(s.title, "color");
        } else {
            ++depth;
            EXPECT_EQ(s.title, "depth");
            EXPECT_GT(s.depth.bits, 0);
            EXPECT_GT(s.depth.nearMetres, 0.0);
            EXPECT_GT(s.depth.farMetres, s.depth.nearMetres);
            EXPECT_FALSE(s.depth.mapping.empty());
        }
    }
    EXPECT_EQ(color, 1);
    EXPECT_EQ(depth, 1);
    EXPECT_GE(info.duration, platform::Duration::zero());
    // Opening again needs close().
    EXPECT_EQ(errcOf(src_->open(harness_->url.c_str())), Errc::InvalidState);
    EXPECT_EQ(src_->state(), State::Open);
}

TEST_P(MediaSourceContractTest, readsEveryPacketThenEndOfStream)
{
    openOrFail();
    const auto &streams = src_->info().streams;
    std::map<int, int> count;
    std::map<int, hal::Pts> lastDts;
    for (;;) {
        auto p = src_->readPacket();
        if (!p) {
            ASSERT_EQ(p.error().code, Errc::EndOfStream) << p.error().what;
            break;
        }
        ASSERT_GE(p->streamIndex, 0);
        ASSERT_LT(p->streamIndex, static_cast<int>(streams.size()));
        ASSERT_NE(p->data, nullptr);
        ASSERT_GT(p->size, 0u);
        if (count[p->streamIndex] == 0) {
            EXPECT_TRUE(p->keyframe)
                << "stream " << p->streamIndex << " must start with a keyframe";
        }
        if (p->dts != hal::kNoPts) {
            if (lastDts.count(p->streamIndex) != 0) {
                EXPECT_GE(p->dts, lastDts[p->streamIndex]);
            }
            lastDts[p->streamIndex] = p->dts;
        }
        ++count[p->streamIndex];
        ASSERT_LT(count[p->streamIndex], 1'000'000);
    }
    for (const hal::StreamInfo &s : streams) {
        if (harness_->framesPerStream > 0) {
            EXPECT_EQ(count[s.index], harness_->framesPerStream) << "stream " << s.index;
        } else {
            EXPECT_GT(count[s.index], 0);
        }
    }
    // The end is sticky.
    EXPECT_EQ(errcOf(src_->readPacket()), Errc::EndOfStream);
}

TEST_P(MediaSourceContractTest, seekLandsOnAKeyframeAtOrBeforeTheTarget)
{
    openOrFail();
    const hal::MediaInfo &info = src_->info();
    if (!info.seekable)
        GTEST_SKIP() << "Source not seekable";
    const auto first = src_->readPacket();
    ASSERT_TRUE(first);
    const hal::Pts firstPts = first->pts;

    const hal::Pts target = info.duration / 2;
    ASSERT_TRUE(src_->seek(target));
    std::map<int, bool> seen;
    for (int i = 0; i < 8; ++i) {
        auto p = src_->readPacket();
        ASSERT_TRUE(p);
        if (seen[p->streamIndex])
            continue;
        seen[p->streamIndex] = true;
        EXPECT_TRUE(p->keyframe) << "first packet of stream " << p->streamIndex << " after seek";
        EXPECT_LE(p->pts, target);
        EXPECT_GT(p->pts, firstPts);
    }

    ASSERT_TRUE(src_->seek(hal::Pts{0}));
    const auto again = src_->readPacket();
    ASSERT_TRUE(again);
    EXPECT_EQ(again->pts, firstPts);
    EXPECT_TRUE(again->keyframe);
}

TEST_P(MediaSourceContractTest, closeAndReopen)
{
    openOrFail();
    ASSERT_TRUE(src_->readPacket());
    src_->close();
    EXPECT_EQ(src_->state(), State::Closed);
    EXPECT_EQ(errcOf(src_->readPacket()), Errc::InvalidState);
    openOrFail();
    const auto p = src_->readPacket();
    ASSERT_TRUE(p);
    EXPECT_TRUE(p->keyframe);
}

DT_CONTRACT_ON_ALL_BACKENDS(MediaSourceContractTest, drivers::mediaSourceBackends());

} // namespace
} // namespace depthtouch::contract
