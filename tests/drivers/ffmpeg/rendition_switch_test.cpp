// An HLS ladder read with `rendition=auto` (the default) changes rendition with the throughput at
// a key frame: reading on to the next key frame when the link slows before any key frame interval
// is known (the way up too), at once when it is known (skipping less than a segment instead of
// stalling for it); every picture delivered once, in order, decodable. The rule that picks the
// rung, up included, is rendition_policy_test's.
// The two renditions differ in colour (red 320x240, blue 160x120), so each decoded frame says
// which one it came from. The link is a clock that moves only when read (ScriptedClock): every
// read appears to wait one step, so the throughput is the packets' bytes over that step, with no
// real waiting and no network. Media made with the ffmpeg CLI at run time.

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/platform/log.h"
#include "ffmpeg_test_support.h"

namespace depthtouch {
namespace {

using namespace ffmpegtest;
using platform::Duration;
using platform::TimePoint;

constexpr int kFrames = 240; ///< 8 s at 30 fps
constexpr double kFps = 30.0;
constexpr double kSegment = 2.0; ///< Seconds: the key frame interval and the segment duration.

/// A clock that advances by a step each time it is read: `step` until `calls` reads, then
/// `later`.
class ScriptedClock final : public platform::Clock {
public:
    explicit ScriptedClock(Duration step, long calls = -1, Duration later = Duration(0))
        : step_(step), calls_(calls), later_(later)
    {
    }
    TimePoint now() const noexcept override
    {
        const long n = reads_.fetch_add(1);
        const Duration d = calls_ >= 0 && n >= calls_ ? later_ : step_;
        return TimePoint(Duration(t_.fetch_add(d.count()) + d.count()));
    }
    bool sleepUntil(TimePoint deadline) noexcept override
    {
        const auto want = deadline.time_since_epoch().count();
        auto have = t_.load();
        while (have < want && !t_.compare_exchange_weak(have, want)) {
        }
        return true;
    }

private:
    Duration step_;
    long calls_;
    Duration later_;
    mutable std::atomic<long> reads_{0};
    mutable std::atomic<std::int64_t> t_{0};
};

class RenditionSwitchTest : public FfmpegCliTest {
protected:
    RenditionSwitchTest() : FfmpegCliTest("dt-rendition-switch-test-") {}
    void SetUp() override
    {
        FfmpegCliTest::SetUp();
        if (IsSkipped() || HasFatalFailure())
            return;
        // Two renditions, key frames every 2 s in both, one 2 s segment per key frame.
        ASSERT_TRUE(ffmpeg("-f lavfi -i color=c=red:s=320x240:r=30:d=8 -f lavfi -i "
                           "color=c=blue:s=160x120:r=30:d=8 -map 0:v -map 1:v -c:v libx264 "
                           "-preset ultrafast -g 60 -keyint_min 60 -sc_threshold 0 -b:v:0 1000k "
                           "-b:v:1 200k -f hls -hls_time 2 -hls_playlist_type vod "
                           "-hls_segment_filename " +
                           tmp_.path("seg_%v_%d.ts") +
                           " -var_stream_map 'v:0 v:1' -master_pl_name master.m3u8 " +
                           tmp_.path("out_%v.m3u8")));
    }
    /// \return the colour of each decoded frame, 'r' or 'b' (by its first luma sample: red is
    /// about 81, blue about 41 in BT.601 limited range), checking every frame is 320x240 (the
    /// stream's size, the smaller rendition scaled to it), not corrupt, and the presentation
    /// times rising by one frame but across \a allowedGap seconds at most once.
    std::string colours(const Decoded &d, double allowedGap)
    {
        std::string out;
        int gaps = 0;
        for (std::size_t i = 0; i < d.frames.size(); ++i) {
            EXPECT_EQ(d.frames[i].size(), 320u * 240u * 3u / 2u) << "frame " << i;
            EXPECT_FALSE(d.corrupt[i]) << "frame " << i;
            out += !d.frames[i].empty() && d.frames[i][0] > 61 ? 'r' : 'b';
            if (i == 0)
                continue;
            const double step = std::chrono::duration<double>(d.pts[i] - d.pts[i - 1]).count();
            EXPECT_GT(step, 0.5 / kFps) << "frame " << i << ": times rise, none twice";
            if (step > 1.5 / kFps) {
                ++gaps;
                EXPECT_LT(step, allowedGap) << "frame " << i;
            }
        }
        EXPECT_LE(gaps, allowedGap > 0.0 ? 1 : 0);
        return out;
    }
    /// \return the index of the first frame of colour \a c at or after \a from.
    static std::size_t firstOf(const std::string &s, char c, std::size_t from = 0)
    {
        return s.find(c, from);
    }
    Decoded play(ScriptedClock &clock)
    {
        return decodeAll(tmp_.path("master.m3u8"), hal::StreamKind::Color, "timeout_ms=1000000",
                         nullptr, "", &clock);
    }
    double seconds(const Decoded &d, std::size_t i) const
    {
        return std::chrono::duration<double>(d.pts[i] - d.pts[0]).count();
    }
};

TEST_F(RenditionSwitchTest, aSlowLinkFromTheStartGoesDownAtTheNextKeyFrameLosingNothing)
{
    ScriptedClock link(std::chrono::milliseconds(200)); // far below even the smaller rendition
    const Decoded d = play(link);
    ASSERT_EQ(d.frames.size(), static_cast<std::size_t>(kFrames)) << "no picture lost";
    const std::string c = colours(d, 0.0);
    const std::size_t down = firstOf(c, 'b');
    ASSERT_NE(down, std::string::npos) << c;
    EXPECT_EQ(c.find('r', down), std::string::npos) << "stays down: " << c;
    EXPECT_NEAR(seconds(d, down), kSegment, 1e-3) << "at the first key frame after the start";
}

TEST_F(RenditionSwitchTest, aLinkThatSlowsMidStreamGoesDownAtOnceSkippingLessThanASegment)
{
    // Fast (1 us a read: far above the taller rendition) for about 3 s of video, then slow.
    ScriptedClock link(std::chrono::microseconds(1), 600, std::chrono::milliseconds(200));
    const Decoded d = play(link);
    const std::string c = colours(d, kSegment);
    const std::size_t down = firstOf(c, 'b');
    ASSERT_NE(down, std::string::npos) << c;
    ASSERT_GT(down, 0u);
    EXPECT_EQ(c.find('r', down), std::string::npos) << c;
    const double at = seconds(d, down);
    EXPECT_NEAR(at, kSegment * std::round(at / kSegment), 1e-3) << "at a key frame: " << at;
    EXPECT_GT(at, kSegment) << "after the first key frame interval was seen";
    const double skipped = at - seconds(d, down - 1) - 1.0 / kFps;
    EXPECT_GT(skipped, 0.0) << "the rest of the slow segment is not waited for";
    EXPECT_LT(skipped, kSegment);
    EXPECT_EQ(d.frames.size(), static_cast<std::size_t>(kFrames - std::lround(skipped * kFps)));
}

TEST_F(RenditionSwitchTest, aFixedRenditionNeverChanges)
{
    ScriptedClock link(std::chrono::milliseconds(200));
    const Decoded d = decodeAll(tmp_.path("master.m3u8"), hal::StreamKind::Color,
                                "timeout_ms=1000000,rendition=highest", nullptr, "", &link);
    ASSERT_EQ(d.frames.size(), static_cast<std::size_t>(kFrames));
    EXPECT_EQ(colours(d, 0.0), std::string(kFrames, 'r'));
}

/// A ladder whose renditions are not all coded alike (issue 60, class 7): red H.264 320x240,
/// optionally green (lime) H.264 240x180, and blue HEVC 160x120 (the shortest). The decoders are
/// opened for the H.264 rendition read at open: the HEVC one is never switched to (its packets
/// would not decode: before, every picture after the switch was a decode error), one warning says
/// so, and the way down goes to the shortest H.264 rendition instead, when there is one.
class RenditionCodecTest : public RenditionSwitchTest {
protected:
    void SetUp() override
    {
        FfmpegCliTest::SetUp(); // not the H.264-only ladder
        if (IsSkipped() || HasFatalFailure())
            return;
        platform::setLogSink(
            [](void *user, platform::LogLevel level, const char *, const char *message) {
                if (level == platform::LogLevel::Warning &&
                    std::string_view(message).substr(0, 10) == "Rendition ")
                    static_cast<std::vector<std::string> *>(user)->push_back(message);
            },
            &warnings_);
    }
    void TearDown() override { platform::setLogSink(nullptr, nullptr); }
    /// Writes the ladder: with \a green, three renditions, else two.
    void ladder(bool green)
    {
        const std::string in = green ? " -f lavfi -i color=c=lime:s=240x180:r=30:d=8" : "";
        const std::string map = green ? "-map 0:v -map 2:v -map 1:v " : "-map 0:v -map 1:v ";
        const std::string codecs = green
                                       ? "-c:v:0 libx264 -c:v:1 libx264 -c:v:2 libx265 -b:v:0 "
                                         "1000k -b:v:1 500k -b:v:2 200k "
                                       : "-c:v:0 libx264 -c:v:1 libx265 -b:v:0 1000k -b:v:1 200k ";
        ASSERT_TRUE(ffmpeg("-f lavfi -i color=c=red:s=320x240:r=30:d=8 -f lavfi -i "
                           "color=c=blue:s=160x120:r=30:d=8" +
                           in + " " + map + codecs +
                           "-pix_fmt yuv420p -x265-params log-level=error -preset ultrafast -g 60 "
                           "-keyint_min 60 -sc_threshold 0 -f hls -hls_time 2 -hls_playlist_type "
                           "vod -hls_segment_filename " +
                           tmp_.path("seg_%v_%d.ts") + " -var_stream_map '" +
                           (green ? "v:0 v:1 v:2" : "v:0 v:1") + "' -master_pl_name master.m3u8 " +
                           tmp_.path("out_%v.m3u8")));
    }
    /// \return each decoded frame's colour: 'g' green (luma about 145), 'r' red (81), 'b' blue
    /// (41); checks every frame is 320x240, not corrupt, and the times rising by one frame.
    static std::string hues(const Decoded &d)
    {
        std::string out;
        for (std::size_t i = 0; i < d.frames.size(); ++i) {
            EXPECT_EQ(d.frames[i].size(), 320u * 240u * 3u / 2u) << "frame " << i;
            EXPECT_FALSE(d.corrupt[i]) << "frame " << i;
            const int y = d.frames[i].empty() ? 0 : d.frames[i][0];
            out += y > 120 ? 'g' : y > 61 ? 'r' : 'b';
            if (i > 0) {
                EXPECT_NEAR(std::chrono::duration<double>(d.pts[i] - d.pts[i - 1]).count(),
                            1.0 / kFps, 1e-3)
                    << "frame " << i;
            }
        }
        return out;
    }
    std::vector<std::string> warnings_;
};

TEST_F(RenditionCodecTest, aSlowLinkKeepsTheRenditionItDecodesRatherThanSwitchToAnotherCodec)
{
    ladder(false);
    ScriptedClock link(std::chrono::milliseconds(200)); // far below even the smaller rendition
    const Decoded d = play(link);
    EXPECT_EQ(d.stats.framesDropped, 0u);
    ASSERT_EQ(d.frames.size(), static_cast<std::size_t>(kFrames)) << "every picture decoded";
    EXPECT_EQ(hues(d), std::string(kFrames, 'r')) << "stays on the H.264 rendition";
    ASSERT_EQ(warnings_.size(), 1u) << "one line says why";
    EXPECT_NE(warnings_[0].find("Rendition 160x120 refused"), std::string::npos) << warnings_[0];
    EXPECT_NE(warnings_[0].find("hevc"), std::string::npos) << warnings_[0];
    EXPECT_NE(warnings_[0].find("h264"), std::string::npos) << warnings_[0];
}

TEST_F(RenditionCodecTest, theWayDownGoesToTheShortestRenditionOfTheSameCodec)
{
    ladder(true);
    ScriptedClock link(std::chrono::milliseconds(200));
    const Decoded d = play(link);
    EXPECT_EQ(d.stats.framesDropped, 0u);
    ASSERT_EQ(d.frames.size(), static_cast<std::size_t>(kFrames)) << "no picture lost";
    const std::string c = hues(d);
    EXPECT_EQ(c, std::string(60, 'r') + std::string(kFrames - 60, 'g'))
        << "down to green (H.264) at the first key frame, never to blue (HEVC)";
    ASSERT_EQ(warnings_.size(), 1u);
    EXPECT_NE(warnings_[0].find("playing 240x180"), std::string::npos) << warnings_[0];
}

} // namespace
} // namespace depthtouch
