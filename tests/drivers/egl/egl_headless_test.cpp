// The headless EGL display on Mesa's surfaceless platform: offscreen buffers, swap on present(),
// read-back orientation, several displays in one process. Skips when the platform is missing.
#include <cstdint>
#include <memory>
#include <vector>

#include <GLES3/gl3.h>
#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/drivers/egl/egl_headless_display.h"
#include "gl_pixels.h"

namespace depthtouch::drivers {
namespace {

using test::drawHalves;
using test::pixelAt;
using test::pixelView;
using test::Rgb;

class EglHeadlessTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        cfg_.clock = &clock_;
        auto d = EglHeadlessDisplay::create(cfg_);
        if (!d && d.error().code == Errc::NoDevice)
            GTEST_SKIP() << "No EGL surfaceless platform: " << d.error().what;
        ASSERT_TRUE(d) << d.error().what;
        display_ = std::move(*d);
    }

    platform::ManualClock clock_{platform::ManualClock::Mode::AutoAdvance};
    hal::BackendConfig cfg_;
    std::unique_ptr<hal::Display> display_;
};

TEST_F(EglHeadlessTest, capabilitiesPromiseAContextAndReadback)
{
    EXPECT_TRUE(display_->capabilities().hasGlesContext);
    EXPECT_TRUE(display_->capabilities().offscreen);
    EXPECT_TRUE(display_->capabilities().readback);
    EXPECT_EQ(display_->framebuffer(), 0u); // closed
}

TEST_F(EglHeadlessTest, presentedFrameReadsBackTopRowFirst)
{
    hal::DisplayConfig dc;
    dc.mode = "64x48@50";
    ASSERT_TRUE(display_->open(dc));
    ASSERT_TRUE(display_->makeCurrent());
    EXPECT_EQ(display_->size().width, 64);
    EXPECT_EQ(display_->size().height, 48);
    EXPECT_DOUBLE_EQ(display_->refreshHz(), 50.0);
    std::vector<std::uint8_t> buf;
    const hal::ImageView img = pixelView(buf, 64, 48);
    // GIVEN nothing presented THEN there is nothing to read
    EXPECT_EQ(display_->readPixels(img).error().code, Errc::InvalidState);

    // WHEN a frame red on top, blue below is presented
    const std::uint32_t first = display_->framebuffer();
    EXPECT_NE(first, 0u);
    drawHalves(64, 48, {255, 0, 0}, {0, 0, 255});
    ASSERT_TRUE(display_->present());
    // THEN the next frame goes to the other buffer
    EXPECT_NE(display_->framebuffer(), first);
    GLint bound = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
    EXPECT_EQ(static_cast<std::uint32_t>(bound), display_->framebuffer());
    // AND drawing it does not change what was presented
    drawHalves(64, 48, {0, 255, 0}, {0, 255, 0});
    ASSERT_TRUE(display_->readPixels(img));
    const Rgb top = pixelAt(img, 10, 2);
    const Rgb bottom = pixelAt(img, 50, 45);
    EXPECT_EQ(top.r, 255);
    EXPECT_EQ(top.b, 0);
    EXPECT_EQ(bottom.r, 0);
    EXPECT_EQ(bottom.b, 255);
    // AND presenting the green frame shows green, as RGBA too
    ASSERT_TRUE(display_->present());
    std::vector<std::uint8_t> rgbaBuf;
    const hal::ImageView rgba = pixelView(rgbaBuf, 64, 48, hal::PixelFormat::Rgba8);
    ASSERT_TRUE(display_->readPixels(rgba));
    EXPECT_EQ(rgba.row(0, 0)[1], 255);
    EXPECT_EQ(rgba.row(0, 47)[2], 0);
}

TEST_F(EglHeadlessTest, readPixelsRefusesAWrongImage)
{
    ASSERT_TRUE(display_->open({}));
    ASSERT_TRUE(display_->present());
    std::vector<std::uint8_t> buf;
    EXPECT_EQ(display_->readPixels(pixelView(buf, 64, 48)).error().code, Errc::InvalidArgument);
    hal::ImageView gray = pixelView(buf, 1280, 720);
    gray.format = hal::PixelFormat::Gray8;
    EXPECT_EQ(display_->readPixels(gray).error().code, Errc::InvalidArgument);
    hal::ImageView none;
    none.width = 1280;
    none.height = 720;
    none.format = hal::PixelFormat::Rgb24;
    EXPECT_EQ(display_->readPixels(none).error().code, Errc::InvalidArgument);
    display_->close();
    EXPECT_EQ(display_->readPixels(pixelView(buf, 1280, 720)).error().code, Errc::InvalidState);
}

TEST_F(EglHeadlessTest, twoDisplaysInOneProcessKeepTheirOwnContexts)
{
    // GIVEN a second headless display open next to the first
    auto second = EglHeadlessDisplay::create(cfg_);
    ASSERT_TRUE(second);
    hal::DisplayConfig small;
    small.width = 32;
    small.height = 16;
    ASSERT_TRUE(display_->open(small));
    ASSERT_TRUE((*second)->open(small));
    // WHEN the second closes (dropping its reference to the shared EGL display)
    (*second)->close();
    // THEN the first still draws and reads back
    ASSERT_TRUE(display_->makeCurrent());
    drawHalves(32, 16, {10, 20, 30}, {10, 20, 30});
    ASSERT_TRUE(display_->present());
    std::vector<std::uint8_t> buf;
    const hal::ImageView img = pixelView(buf, 32, 16);
    ASSERT_TRUE(display_->readPixels(img));
    EXPECT_EQ(pixelAt(img, 5, 5).g, 20);
}

TEST_F(EglHeadlessTest, reopensAfterCloseAndRefusesBadModes)
{
    hal::DisplayConfig bad;
    bad.mode = "12x";
    EXPECT_EQ(display_->open(bad).error().code, Errc::NotSupported);
    EXPECT_EQ(display_->state(), hal::Display::State::Closed);
    ASSERT_TRUE(display_->open({}));
    ASSERT_TRUE(display_->present());
    display_->close();
    ASSERT_TRUE(display_->open({}));
    auto info = display_->present();
    ASSERT_TRUE(info);
    EXPECT_EQ(info->frameCounter, 1u);
}

TEST(EglHeadlessSelectionTest, namedAndBadOptionsRefused)
{
    hal::BackendConfig cfg;
    cfg.options = hal::OptionList("depth=9");
    EXPECT_EQ(EglHeadlessDisplay::create(cfg).error().code, Errc::InvalidArgument);
    hal::SelectionReport report;
    auto d = createDisplay("headless", {}, &report);
    if (!d && d.error().code == Errc::NoDevice)
        GTEST_SKIP() << "No EGL surfaceless platform";
    ASSERT_TRUE(d);
    EXPECT_EQ(report.chosen, "headless");
}

} // namespace
} // namespace depthtouch::drivers
