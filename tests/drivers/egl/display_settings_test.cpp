// EGL display settings, mode strings and the simulated vertical blank (no EGL needed).
#include <gtest/gtest.h>

#include "depthtouch/drivers/egl/display_settings.h"

namespace depthtouch::drivers {
namespace {

using namespace std::chrono_literals;

TEST(ModeSpecTest, parsesConnectorsSizesAndRates)
{
    struct Case {
        const char *text;
        const char *connector;
        int width;
        int height;
        double refreshHz; ///< 0: none given
    };
    const Case cases[] = {
        {"1920x1080@50", "", 1920, 1080, 50.0},
        {"HDMI-A-1", "HDMI-A-1", 0, 0, 0.0},
        {"DP-2:1280x720@59.94", "DP-2", 1280, 720, 59.94},
        {"640x480", "", 640, 480, 0.0},
    };
    for (const Case &c : cases) {
        const auto s = parseModeSpec(c.text);
        ASSERT_TRUE(s) << c.text;
        EXPECT_EQ(s->connector, c.connector) << c.text;
        EXPECT_EQ(s->width, c.width) << c.text;
        EXPECT_EQ(s->height, c.height) << c.text;
        EXPECT_DOUBLE_EQ(s->refreshHz, c.refreshHz) << c.text;
    }
}

TEST(ModeSpecTest, rejectsMalformedModes)
{
    for (const char *bad :
         {"1920x", "x1080", "640x480@", "0x0", "640x480@abc", "HDMI-A-1:", ":640x480",
          "640x480@5000", "big", "HDMI A:640x480", "99999999x2", "640x48O"})
        EXPECT_EQ(parseModeSpec(bad).error().code, Errc::NotSupported) << bad;
}

TEST(EglDisplaySettingsTest, optionsOverDefaultsAndBadOptionsRefused)
{
    auto s = EglDisplaySettings::parse(hal::OptionList("width=640,height=360,refresh=50"));
    ASSERT_TRUE(s);
    EXPECT_EQ(s->width, 640);
    EXPECT_EQ(s->height, 360);
    EXPECT_DOUBLE_EQ(s->refreshHz, 50.0);
    EXPECT_EQ(s->swapInterval, 1);
    EXPECT_EQ(EglDisplaySettings::parse(hal::OptionList("widht=640")).error().code,
              Errc::InvalidArgument);
    EXPECT_EQ(EglDisplaySettings::parse(hal::OptionList("refresh=0")).error().code,
              Errc::InvalidArgument);
    EXPECT_EQ(EglDisplaySettings::parse(hal::OptionList("width=-3")).error().code,
              Errc::InvalidArgument);
}

TEST(EglDisplaySettingsTest, windowOnlyOptionsNeedAWindow)
{
    // GIVEN the window options THEN a window backend takes them and an offscreen one refuses them
    auto s = EglDisplaySettings::parse(hal::OptionList("fullscreen=1,readback=yes,swap_interval=0"),
                                       /*window=*/true);
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->fullscreen);
    EXPECT_TRUE(s->readback);
    EXPECT_EQ(s->swapInterval, 0);
    s = EglDisplaySettings::parse(hal::OptionList(""), true);
    ASSERT_TRUE(s);
    EXPECT_FALSE(s->fullscreen);
    EXPECT_FALSE(s->readback);
    EXPECT_EQ(EglDisplaySettings::parse(hal::OptionList("fullscreen=1")).error().code,
              Errc::InvalidArgument);
    EXPECT_EQ(EglDisplaySettings::parse(hal::OptionList("readback=2"), true).error().code,
              Errc::InvalidArgument);
    EXPECT_EQ(EglDisplaySettings::parse(hal::OptionList("swap_interval=5"), true).error().code,
              Errc::InvalidArgument);
}

TEST(EglDisplaySettingsTest, configFieldsWinOverModeOverSettings)
{
    const EglDisplaySettings defaults;
    hal::DisplayConfig cfg;
    cfg.mode = "800x600@75";
    auto r = resolveWindowConfig(cfg, defaults);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->width, 800);
    EXPECT_DOUBLE_EQ(r->refreshHz, 75.0);
    cfg.width = 320;
    r = resolveWindowConfig(cfg, defaults);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->width, 320);
    EXPECT_EQ(r->height, 600);
    cfg = {};
    r = resolveWindowConfig(cfg, defaults);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->width, 1280);
    EXPECT_EQ(r->height, 720);
    EXPECT_DOUBLE_EQ(r->refreshHz, 60.0);
    cfg.height = -1;
    EXPECT_EQ(resolveWindowConfig(cfg, defaults).error().code, Errc::InvalidArgument);
    cfg = {};
    cfg.mode = "HDMI-A-1";
    // A connector name alone is accepted (and ignored) by window backends.
    EXPECT_TRUE(resolveWindowConfig(cfg, defaults));
    cfg.mode = "7x";
    EXPECT_EQ(resolveWindowConfig(cfg, defaults).error().code, Errc::NotSupported);
}

/// A 50 Hz pacer started at 1 s on a manual clock.
class VsyncPacerTest : public ::testing::Test {
protected:
    void SetUp() override { pacer.start(epoch, 50.0); }

    platform::ManualClock clock{platform::ManualClock::Mode::AutoAdvance,
                                platform::TimePoint(std::chrono::seconds(1))};
    VsyncPacer pacer;
    const platform::TimePoint epoch = clock.now();
};

TEST_F(VsyncPacerTest, blanksFallOnTheGridAndLateFramesSkip)
{
    // GIVEN a 50 Hz pacer on a manual clock
    // WHEN frames come on time THEN each lands on the next blank, 20 ms apart
    for (std::uint64_t i = 1; i <= 3; ++i) {
        const hal::PresentInfo info = pacer.next(clock);
        EXPECT_EQ(info.frameCounter, i);
        EXPECT_EQ(info.vsyncTime, epoch + 20ms * static_cast<int>(i));
        EXPECT_EQ(info.skippedVsyncs, 0u);
        EXPECT_EQ(clock.now(), info.vsyncTime);
    }
    // WHEN the caller is 50 ms late THEN the frame shows at the first blank at or after now
    clock.advance(50ms); // now = epoch + 110 ms
    const hal::PresentInfo late = pacer.next(clock);
    EXPECT_EQ(late.vsyncTime, epoch + 120ms);
    EXPECT_EQ(late.skippedVsyncs, 2u); // the blanks at 80 and 100 ms
    EXPECT_EQ(late.frameCounter, 4u);
    // AND a restart counts from 1 again
    pacer.start(clock.now(), 50.0);
    EXPECT_EQ(pacer.next(clock).frameCounter, 1u);
}

TEST_F(VsyncPacerTest, followSleepsOnlyWhenTheSwapDidNotWait)
{
    // GIVEN swaps that return at once (no server pacing) THEN frames are one period apart
    hal::PresentInfo a = pacer.follow(clock, 1);
    EXPECT_EQ(a.vsyncTime, epoch + 20ms);
    EXPECT_EQ(clock.now(), epoch + 20ms);
    EXPECT_EQ(pacer.follow(clock, 1).vsyncTime, epoch + 40ms);
    // AND at interval 2, two periods apart with one blank left out
    hal::PresentInfo b = pacer.follow(clock, 2);
    EXPECT_EQ(b.vsyncTime, epoch + 80ms);
    EXPECT_EQ(b.skippedVsyncs, 1u);
    // GIVEN a swap the server held until its blank, 21 ms after the previous frame
    clock.advance(21ms);
    const platform::TimePoint held = clock.now();
    hal::PresentInfo c = pacer.follow(clock, 1);
    // THEN the frame is shown at once, at the swap's return, with no blank skipped
    EXPECT_EQ(c.vsyncTime, held);
    EXPECT_EQ(clock.now(), held);
    EXPECT_EQ(c.skippedVsyncs, 0u);
    EXPECT_EQ(c.frameCounter, 4u);
    // AND a caller 50 ms late has about two blanks skipped, with no wait
    clock.advance(61ms);
    hal::PresentInfo d = pacer.follow(clock, 1);
    EXPECT_EQ(d.vsyncTime, held + 61ms);
    EXPECT_EQ(d.skippedVsyncs, 2u);
    // AND interval 0 never waits
    EXPECT_EQ(pacer.follow(clock, 0).vsyncTime, held + 61ms);
}

TEST_F(VsyncPacerTest, observedBlanksEstimateTheSkippedOnesAndMoveTheGrid)
{
    // GIVEN swaps the server showed at 21 ms, 40 ms (on time, some jitter) and 103 ms (late)
    hal::PresentInfo a = pacer.observe(epoch + 21ms);
    EXPECT_EQ(a.vsyncTime, epoch + 21ms);
    EXPECT_EQ(a.frameCounter, 1u);
    EXPECT_EQ(a.skippedVsyncs, 0u);
    hal::PresentInfo b = pacer.observe(epoch + 40ms);
    EXPECT_EQ(b.skippedVsyncs, 0u);
    hal::PresentInfo c = pacer.observe(epoch + 103ms);
    // THEN 63 ms after the previous frame is about three periods: two blanks without a new frame
    EXPECT_EQ(c.skippedVsyncs, 2u);
    EXPECT_EQ(c.frameCounter, 3u);
    // AND a frame shown sooner than a period after the previous one still counts one period
    EXPECT_EQ(pacer.observe(epoch + 105ms).skippedVsyncs, 0u);
    // AND simulated pacing afterwards continues from the observed grid
    clock.advance(105ms); // now = the last observed frame
    const hal::PresentInfo next = pacer.next(clock);
    EXPECT_EQ(next.vsyncTime, epoch + 125ms);
    EXPECT_EQ(next.skippedVsyncs, 0u);
}

} // namespace
} // namespace depthtouch::drivers
