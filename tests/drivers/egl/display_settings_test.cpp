// EGL display settings, mode strings and the simulated vertical blank (no EGL needed).
#include <gtest/gtest.h>

#include "depthtouch/drivers/egl/display_settings.h"

namespace depthtouch::drivers {
namespace {

using namespace std::chrono_literals;

TEST(ModeSpecTest, parsesConnectorsSizesAndRates)
{
    auto s = parseModeSpec("1920x1080@50");
    ASSERT_TRUE(s);
    EXPECT_EQ(s->connector, "");
    EXPECT_EQ(s->width, 1920);
    EXPECT_EQ(s->height, 1080);
    EXPECT_DOUBLE_EQ(s->refreshHz, 50.0);

    s = parseModeSpec("HDMI-A-1");
    ASSERT_TRUE(s);
    EXPECT_EQ(s->connector, "HDMI-A-1");
    EXPECT_EQ(s->width, 0);

    s = parseModeSpec("DP-2:1280x720@59.94");
    ASSERT_TRUE(s);
    EXPECT_EQ(s->connector, "DP-2");
    EXPECT_EQ(s->width, 1280);
    EXPECT_EQ(s->height, 720);
    EXPECT_DOUBLE_EQ(s->refreshHz, 59.94);

    s = parseModeSpec("640x480");
    ASSERT_TRUE(s);
    EXPECT_EQ(s->refreshHz, 0.0);
}

TEST(ModeSpecTest, rejectsMalformedModes)
{
    for (const char *bad : {"1920x", "x1080", "640x480@", "0x0", "640x480@abc", "HDMI-A-1:",
                            ":640x480", "640x480@5000", "big", "HDMI A:640x480", "99999999x2", "640x48O"})
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

TEST(VsyncPacerTest, blanksFallOnTheGridAndLateFramesSkip)
{
    // GIVEN a 50 Hz pacer on a manual clock
    platform::ManualClock clock(platform::ManualClock::Mode::AutoAdvance,
                                platform::TimePoint(std::chrono::seconds(1)));
    VsyncPacer pacer;
    const platform::TimePoint epoch = clock.now();
    pacer.start(epoch, 50.0);
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

} // namespace
} // namespace depthtouch::drivers
