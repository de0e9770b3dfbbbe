#include "depthtouch/drivers/mock/mock_display.h"

#include <gtest/gtest.h>

#include "mock_test_util.h"

namespace depthtouch::drivers {
namespace {

using std::chrono::milliseconds;
using std::chrono::nanoseconds;
using testing::errcOf;

class MockDisplayTest : public ::testing::Test {
protected:
    platform::ManualClock clock_;
    MockDisplay display_{clock_};
};

TEST_F(MockDisplayTest, hasNoGlContextAndIsOffscreen)
{
    EXPECT_FALSE(display_.capabilities().hasGlesContext);
    EXPECT_TRUE(display_.capabilities().offscreen);
}

TEST_F(MockDisplayTest, presentsLandOnConsecutiveVsyncs)
{
    hal::DisplayConfig cfg;
    cfg.refreshHz = 50.0;
    ASSERT_TRUE(display_.open(cfg));
    const platform::TimePoint epoch = clock_.now();
    for (std::uint64_t i = 1; i <= 5; ++i) {
        auto info = display_.present();
        ASSERT_TRUE(info);
        EXPECT_EQ(info->vsyncTime, epoch + milliseconds(20 * static_cast<int>(i)));
        EXPECT_EQ(clock_.now(), info->vsyncTime); // present() slept until the blank
        EXPECT_EQ(info->skippedVsyncs, 0u);
        EXPECT_EQ(info->frameCounter, i);
    }
    EXPECT_EQ(display_.presentCount(), 5u);
}

TEST_F(MockDisplayTest, latePresentSkipsVsyncs)
{
    hal::DisplayConfig cfg;
    cfg.refreshHz = 50.0;
    ASSERT_TRUE(display_.open(cfg));
    const platform::TimePoint epoch = clock_.now();
    ASSERT_TRUE(display_.present());  // vsync 1 at 20 ms
    clock_.advance(milliseconds(45)); // now 65 ms: blanks 2 and 3 passed
    auto info = display_.present();
    ASSERT_TRUE(info);
    EXPECT_EQ(info->vsyncTime, epoch + milliseconds(80));
    EXPECT_EQ(info->skippedVsyncs, 2u);
    clock_.advance(milliseconds(20)); // exactly on blank 5
    info = display_.present();
    ASSERT_TRUE(info);
    EXPECT_EQ(info->vsyncTime, epoch + milliseconds(100));
    EXPECT_EQ(info->skippedVsyncs, 0u);
}

TEST_F(MockDisplayTest, modeStringSetsSizeAndRefresh)
{
    hal::DisplayConfig cfg;
    cfg.mode = "1920x1080@24";
    ASSERT_TRUE(display_.open(cfg));
    EXPECT_EQ(display_.size().width, 1920);
    EXPECT_EQ(display_.size().height, 1080);
    EXPECT_DOUBLE_EQ(display_.refreshHz(), 24.0);
    display_.close();
    cfg.mode = "640x480";
    ASSERT_TRUE(display_.open(cfg));
    EXPECT_DOUBLE_EQ(display_.refreshHz(), 60.0);
    display_.close();
    for (const char *bad : {"HDMI-A-1", "640x480@", "640x480@60Hz", "640x480p"}) {
        cfg.mode = bad;
        EXPECT_EQ(errcOf(display_.open(cfg)), Errc::NotSupported) << bad;
    }
    cfg.mode = "0x480";
    EXPECT_EQ(errcOf(display_.open(cfg)), Errc::InvalidArgument);
    EXPECT_EQ(display_.state(), hal::Display::State::Closed);
}

TEST_F(MockDisplayTest, loseAndRestore)
{
    ASSERT_TRUE(display_.open({}));
    ASSERT_TRUE(display_.makeCurrent());
    EXPECT_TRUE(display_.isCurrent());
    display_.loseDisplay();
    EXPECT_EQ(display_.state(), hal::Display::State::Lost);
    EXPECT_FALSE(display_.isCurrent());
    EXPECT_EQ(errcOf(display_.present()), Errc::NoDevice);
    // Restoring plugs the display back in, but a lost one must be reopened.
    display_.restoreDisplay();
    EXPECT_EQ(errcOf(display_.present()), Errc::NoDevice);
    display_.close();
    ASSERT_TRUE(display_.open({}));
    EXPECT_TRUE(display_.present());
}

TEST_F(MockDisplayTest, optionsSetTheDefaults)
{
    const hal::BackendConfig cfg = testing::configWith(&clock_, "width=800,height=600,refresh=75");
    auto d = MockDisplay::create(cfg);
    ASSERT_TRUE(d);
    ASSERT_TRUE((*d)->open({}));
    EXPECT_EQ((*d)->size().width, 800);
    EXPECT_DOUBLE_EQ((*d)->refreshHz(), 75.0);
    testing::expectOptionsRefused(&MockDisplay::create, cfg, {"refresh=0"});
}

} // namespace
} // namespace depthtouch::drivers
