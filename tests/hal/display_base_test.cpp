// hal::DisplayBase: a display backend that implements only the hooks gets the open guard, the
// Closed and Lost checks and the size and refresh rate bookkeeping from the base; its hooks are not
// reached in a state that does not allow them.
#include "depthtouch/hal/display_base.h"

#include <optional>

#include <gtest/gtest.h>

#include "support/expectations.h"

namespace depthtouch::hal {
namespace {

using depthtouch::testing::errcOf;
using State = Display::State;

class HookOnlyDisplay final : public DisplayBase {
public:
    explicit HookOnlyDisplay(bool readback) { caps_.readback = readback; }

    std::optional<Errc> failOpen; ///< openDevice() fails with it.
    bool knowsRefresh = true;     ///< openDevice() sets refreshHz_ (a pbuffer cannot tell one).
    int opens = 0;
    int closes = 0;
    int currents = 0;
    int presents = 0;
    int reads = 0;

    void lose() noexcept { markLost(); }

protected:
    Result<void> openDevice(const DisplayConfig &cfg) override
    {
        ++opens;
        if (failOpen)
            return unexpected(*failOpen, "test failure");
        size_ = {cfg.width, cfg.height};
        if (knowsRefresh)
            refreshHz_ = cfg.refreshHz;
        return ok();
    }
    void closeDevice() noexcept override { ++closes; }
    Result<void> makeCurrentDevice() override
    {
        ++currents;
        return ok();
    }
    Result<PresentInfo> presentDevice() override
    {
        ++presents;
        PresentInfo info;
        info.frameCounter = static_cast<std::uint64_t>(presents);
        return info;
    }
    std::uint32_t framebufferDevice() const noexcept override { return 7; }
    Result<void> readPixelsDevice(const ImageView &) override
    {
        ++reads;
        return ok();
    }
};

DisplayConfig config640()
{
    DisplayConfig c;
    c.width = 640;
    c.height = 480;
    c.refreshHz = 50.0;
    return c;
}

TEST(DisplayBaseTest, aReopenedOutputThatCannotTellItsRefreshRateReadsZeroNotTheLastRate)
{
    // GIVEN a display opened at 50 Hz and closed
    HookOnlyDisplay d(false);
    ASSERT_TRUE(d.open(config640()));
    ASSERT_EQ(d.refreshHz(), 50.0);
    d.close();
    // WHEN it is opened again on an output that cannot tell its rate
    d.knowsRefresh = false;
    ASSERT_TRUE(d.open(config640()));
    // THEN the rate reads 0 (unknown), not the 50 Hz of before
    EXPECT_EQ(d.refreshHz(), 0.0);
    EXPECT_EQ(d.size().width, 640);
}

TEST(DisplayBaseTest, closedDisplayRejectsCallsWithoutReachingTheBackend)
{
    HookOnlyDisplay d(true);
    EXPECT_EQ(d.state(), State::Closed);
    EXPECT_EQ(errcOf(d.makeCurrent()), Errc::InvalidState);
    EXPECT_EQ(errcOf(d.present()), Errc::InvalidState);
    EXPECT_EQ(errcOf(d.readPixels(ImageView{})), Errc::InvalidState);
    EXPECT_EQ(d.size().width, 0);
    EXPECT_EQ(d.refreshHz(), 0.0);
    EXPECT_EQ(d.framebuffer(), 0u);
    d.close(); // no-op
    EXPECT_EQ(d.currents + d.presents + d.reads + d.closes, 0);
}

TEST(DisplayBaseTest, openReachesTheBackendOnceUntilClosed)
{
    HookOnlyDisplay d(false);
    ASSERT_TRUE(d.open(config640()));
    EXPECT_EQ(d.state(), State::Open);
    EXPECT_EQ(d.size().width, 640);
    EXPECT_EQ(d.size().height, 480);
    EXPECT_EQ(d.refreshHz(), 50.0);
    EXPECT_EQ(d.framebuffer(), 7u);
    EXPECT_EQ(errcOf(d.open(config640())), Errc::InvalidState);
    EXPECT_EQ(d.opens, 1);
    EXPECT_TRUE(d.makeCurrent());
    auto shown = d.present();
    ASSERT_TRUE(shown);
    EXPECT_EQ(shown->frameCounter, 1u);
    d.close();
    EXPECT_EQ(d.closes, 1);
    EXPECT_EQ(d.state(), State::Closed);
    EXPECT_EQ(d.size().width, 0);
    EXPECT_EQ(d.refreshHz(), 0.0);
}

TEST(DisplayBaseTest, failedOpenStaysClosed)
{
    HookOnlyDisplay d(false);
    d.failOpen = Errc::NoDevice;
    EXPECT_EQ(errcOf(d.open(config640())), Errc::NoDevice);
    EXPECT_EQ(d.state(), State::Closed);
    d.failOpen.reset();
    EXPECT_TRUE(d.open(config640()));
}

TEST(DisplayBaseTest, lostDisplayGivesNoDeviceUntilClosed)
{
    HookOnlyDisplay d(true);
    ASSERT_TRUE(d.open(config640()));
    d.lose();
    EXPECT_EQ(d.state(), State::Lost);
    EXPECT_EQ(errcOf(d.makeCurrent()), Errc::NoDevice);
    EXPECT_EQ(errcOf(d.present()), Errc::NoDevice);
    EXPECT_EQ(errcOf(d.readPixels(ImageView{})), Errc::NoDevice);
    EXPECT_EQ(d.currents + d.presents + d.reads, 0);
    EXPECT_EQ(d.framebuffer(), 0u);
    EXPECT_EQ(d.size().width, 640); // the surface is still there until close()
    EXPECT_EQ(errcOf(d.open(config640())), Errc::InvalidState);
    d.close();
    EXPECT_EQ(d.closes, 1);
    d.lose(); // no-op when Closed
    EXPECT_EQ(d.state(), State::Closed);
}

TEST(DisplayBaseTest, readPixelsWithoutReadbackIsNotSupportedInEveryState)
{
    HookOnlyDisplay d(false);
    EXPECT_EQ(errcOf(d.readPixels(ImageView{})), Errc::NotSupported);
    ASSERT_TRUE(d.open(config640()));
    EXPECT_EQ(errcOf(d.readPixels(ImageView{})), Errc::NotSupported);
    EXPECT_EQ(d.reads, 0);
    HookOnlyDisplay r(true);
    ASSERT_TRUE(r.open(config640()));
    EXPECT_TRUE(r.readPixels(ImageView{}));
    EXPECT_EQ(r.reads, 1);
}

TEST(DisplayBaseTest, stateNamesAreTheEnumerators)
{
    depthtouch::testing::expectNames<State>(
        {{State::Closed, "Closed"}, {State::Open, "Open"}, {State::Lost, "Lost"}});
}

} // namespace
} // namespace depthtouch::hal
