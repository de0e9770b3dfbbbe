// HAL contract: hal::Display (display.h), for every backend in the display table.
#include <gtest/gtest.h>

#include "contract_support.h"

namespace depthtouch::contract {
namespace {

using hal::Display;
using State = Display::State;

class DisplayContractTest : public ClosingContractTest<Display, DisplayHarness> {
protected:
    void SetUp() override
    {
        createBackend(displayHarness, "display", "Display", drivers::createDisplay);
    }
    void openOrFail(const hal::DisplayConfig &cfg = {}) { ASSERT_TRUE(display_->open(cfg)); }

    std::unique_ptr<Display> &display_ = backend_;
};

TEST_P(DisplayContractTest, closedDisplayRejectsCallsWithoutEffect)
{
    EXPECT_EQ(display_->state(), State::Closed);
    EXPECT_EQ(display_->size().width, 0);
    EXPECT_EQ(display_->size().height, 0);
    EXPECT_EQ(display_->refreshHz(), 0.0);
    EXPECT_EQ(errcOf(display_->makeCurrent()), Errc::InvalidState);
    EXPECT_EQ(errcOf(display_->present()), Errc::InvalidState);
    display_->close();
    EXPECT_EQ(display_->state(), State::Closed);
}

TEST_P(DisplayContractTest, openGivesASurfaceAndConstantCapabilities)
{
    const hal::DisplayCapabilities &caps = display_->capabilities();
    const bool gles = caps.hasGlesContext;
    openOrFail();
    EXPECT_EQ(display_->state(), State::Open);
    EXPECT_GT(display_->size().width, 0);
    EXPECT_GT(display_->size().height, 0);
    EXPECT_GT(display_->refreshHz(), 0.0);
    EXPECT_EQ(&display_->capabilities(), &caps);
    EXPECT_EQ(display_->capabilities().hasGlesContext, gles);
    EXPECT_TRUE(display_->makeCurrent());
    EXPECT_EQ(errcOf(display_->open({})), Errc::InvalidState);
    EXPECT_EQ(display_->state(), State::Open);
}

TEST_P(DisplayContractTest, openHonoursTheRequestedSize)
{
    if (!harness_->honoursSize)
        GTEST_SKIP() << "Backend uses the connected display's mode";
    hal::DisplayConfig cfg;
    cfg.width = 320;
    cfg.height = 200;
    cfg.refreshHz = 50.0;
    openOrFail(cfg);
    EXPECT_EQ(display_->size().width, 320);
    EXPECT_EQ(display_->size().height, 200);
    EXPECT_DOUBLE_EQ(display_->refreshHz(), 50.0);
}

TEST_P(DisplayContractTest, presentsArePacedAtTheRefreshRate)
{
    openOrFail();
    ASSERT_TRUE(display_->makeCurrent());
    const platform::Duration period = platform::fromSeconds(1.0 / display_->refreshHz());
    hal::PresentInfo last{};
    for (std::uint64_t i = 1; i <= 12; ++i) {
        if (i == 6)
            clock_->pass(period * 3); // a late frame
        const platform::TimePoint before = clock_->clock().now();
        auto info = display_->present();
        ASSERT_TRUE(info) << info.error().what;
        EXPECT_EQ(info->frameCounter, i);
        EXPECT_GE(info->vsyncTime, before);
        EXPECT_LE(info->vsyncTime, clock_->clock().now());
        if (i > 1) {
            const platform::Duration gap = info->vsyncTime - last.vsyncTime;
            EXPECT_GT(info->vsyncTime, last.vsyncTime);
            // One period per vsync (the ones skipped included), within 1 ms of jitter.
            const platform::Duration expected = period * (1 + info->skippedVsyncs);
            EXPECT_LT(std::chrono::abs(gap - expected), std::chrono::milliseconds(1))
                << "present " << i << " gap " << gap.count() << " ns, skipped "
                << info->skippedVsyncs;
        }
        if (i == 6) {
            EXPECT_GE(info->skippedVsyncs, 2u);
        }
        last = *info;
    }
}

/// The cases for the backends whose harness can lose and restore the display.
class DisplayLossContractTest : public DisplayContractTest {};

TEST_P(DisplayLossContractTest, lostDisplayReportsNoDeviceUntilReopened)
{
    ASSERT_TRUE(harness_->lose && harness_->restore);
    openOrFail();
    ASSERT_TRUE(display_->present());
    // WHEN the display goes away
    harness_->lose(*display_);
    // THEN rendering calls fail with NoDevice and the state is Lost
    EXPECT_EQ(errcOf(display_->present()), Errc::NoDevice);
    EXPECT_EQ(errcOf(display_->makeCurrent()), Errc::NoDevice);
    EXPECT_EQ(display_->state(), State::Lost);
    display_->close();
    EXPECT_EQ(display_->state(), State::Closed);
    EXPECT_EQ(errcOf(display_->open({})), Errc::NoDevice);
    EXPECT_EQ(display_->state(), State::Closed);
    // AND once it is back, open() works again and counting restarts
    harness_->restore(*display_);
    openOrFail();
    auto info = display_->present();
    ASSERT_TRUE(info);
    EXPECT_EQ(info->frameCounter, 1u);
}

DT_CONTRACT_ON_ALL_BACKENDS(DisplayContractTest, drivers::displayBackends());
DT_CONTRACT_ON_BACKENDS_WHERE(DisplayLossContractTest, drivers::displayBackends(), displayHarness,
                              [](const DisplayHarness &h) { return h.lose && h.restore; });

} // namespace
} // namespace depthtouch::contract
