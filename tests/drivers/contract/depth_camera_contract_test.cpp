// HAL contract: hal::DepthCamera (depth_camera.h), for every backend in the depth camera table.
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "contract_support.h"
#include "support/camera_config.h"

namespace depthtouch::contract {
namespace {

using hal::DepthCamera;
using State = DepthCamera::State;
using std::chrono::milliseconds;

class DepthCameraContractTest : public BackendContractTest<DepthCamera, DepthCameraHarness> {
protected:
    void SetUp() override
    {
        createBackend(depthCameraHarness, "depth camera", "Camera", drivers::createDepthCamera);
        if (!camera_)
            return;
        ASSERT_FALSE(camera_->capabilities().modes.empty());
    }
    void TearDown() override
    {
        if (camera_ && camera_->state() == State::Streaming)
            (void)camera_->stop();
    }

    /// The smallest mode with depth, both streams on when it has color.
    hal::CameraConfig smallestMode() const
    {
        const hal::CameraMode *best = nullptr;
        for (const hal::CameraMode &m : camera_->capabilities().modes)
            if (m.depthFormat != hal::PixelFormat::Unknown &&
                (best == nullptr || m.width * m.height < best->width * best->height))
                best = &m;
        return best == nullptr ? hal::CameraConfig{} : testing::configOf(*best);
    }
    void startOrFail()
    {
        const hal::CameraConfig cfg = smallestMode();
        ASSERT_GT(cfg.width, 0) << "no depth mode";
        ASSERT_TRUE(camera_->configure(cfg));
        ASSERT_TRUE(camera_->start());
    }
    hal::Deadline soon() const { return clock_->clock().now() + std::chrono::seconds(1); }

    std::unique_ptr<DepthCamera> &camera_ = backend_;
};

TEST_P(DepthCameraContractTest, modesAreSane)
{
    for (const hal::CameraMode &m : camera_->capabilities().modes) {
        EXPECT_GT(m.width, 0);
        EXPECT_GT(m.height, 0);
        EXPECT_GT(m.fps, 0.0);
        EXPECT_TRUE(m.depthFormat != hal::PixelFormat::Unknown ||
                    m.colorFormat != hal::PixelFormat::Unknown);
        if (m.depthFormat != hal::PixelFormat::Unknown) {
            EXPECT_TRUE(m.depthFormat == hal::PixelFormat::Z16 ||
                        m.depthFormat == hal::PixelFormat::Gray16);
        }
    }
    EXPECT_GE(camera_->capabilities().poolFrames, 1);
}

TEST_P(DepthCameraContractTest, unconfiguredCameraRejectsCallsWithoutEffect)
{
    EXPECT_EQ(camera_->state(), State::Unconfigured);
    EXPECT_EQ(errcOf(camera_->start()), Errc::InvalidState);
    EXPECT_EQ(errcOf(camera_->capture(soon())), Errc::InvalidState);
    EXPECT_EQ(errcOf(camera_->stop()), Errc::InvalidState);
    EXPECT_EQ(camera_->intrinsics().fx, 0.0);
    EXPECT_EQ(camera_->state(), State::Unconfigured);
}

TEST_P(DepthCameraContractTest, refusedConfigurationChangesNothing)
{
    hal::CameraConfig cfg = smallestMode();
    cfg.width = 7; // no camera offers 7 pixels
    EXPECT_EQ(errcOf(camera_->configure(cfg)), Errc::NotSupported);
    cfg = smallestMode();
    cfg.depth = false;
    cfg.color = false;
    EXPECT_EQ(errcOf(camera_->configure(cfg)), Errc::InvalidArgument);
    EXPECT_EQ(camera_->state(), State::Unconfigured);
}

TEST_P(DepthCameraContractTest, streamingStateMachine)
{
    startOrFail();
    EXPECT_EQ(camera_->state(), State::Streaming);
    EXPECT_EQ(errcOf(camera_->start()), Errc::InvalidState);
    EXPECT_EQ(errcOf(camera_->configure(smallestMode())), Errc::InvalidState);
    EXPECT_EQ(camera_->state(), State::Streaming);
    ASSERT_TRUE(camera_->stop());
    EXPECT_EQ(camera_->state(), State::Configured);
    EXPECT_EQ(errcOf(camera_->capture(soon())), Errc::InvalidState);
    ASSERT_TRUE(camera_->start());
}

TEST_P(DepthCameraContractTest, capturesHaveTheModeAndIncreasingTimestamps)
{
    const hal::CameraConfig cfg = smallestMode();
    startOrFail();
    const hal::CameraIntrinsics k = camera_->intrinsics();
    EXPECT_GT(k.fx, 0.0);
    EXPECT_GT(k.fy, 0.0);
    std::uint64_t lastSequence = 0;
    platform::TimePoint lastTime{};
    for (int i = 0; i < 5; ++i) {
        auto c = camera_->capture(soon());
        ASSERT_TRUE(c) << c.error().what;
        ASSERT_TRUE(c->depth);
        EXPECT_EQ(c->color.get() != nullptr, cfg.color);
        const hal::Frame &d = *c->depth;
        EXPECT_EQ(d.kind, hal::StreamKind::Depth);
        EXPECT_EQ(d.image.width, cfg.width);
        EXPECT_EQ(d.image.height, cfg.height);
        EXPECT_EQ(d.image.format, cfg.depthFormat);
        EXPECT_GE(d.pts, hal::Pts::zero());
        EXPECT_LE(d.time, clock_->clock().now());
        if (i > 0) {
            EXPECT_GT(d.sequence, lastSequence);
            EXPECT_GT(d.time, lastTime);
        }
        if (c->color) {
            EXPECT_EQ(c->color->sequence, d.sequence);
            EXPECT_EQ(c->color->time, d.time);
            EXPECT_EQ(c->color->image.format, cfg.colorFormat);
        }
        // Some samples carry a measurement.
        bool anyValid = false;
        for (int y = 0; y < d.image.height && !anyValid; ++y) {
            const std::uint8_t *row = d.image.row(0, y);
            for (int x = 0; x < d.image.width && !anyValid; ++x) {
                std::uint16_t v = 0;
                std::memcpy(&v, row + 2 * x, sizeof(v));
                anyValid = v != 0;
            }
        }
        EXPECT_TRUE(anyValid);
        lastSequence = d.sequence;
        lastTime = d.time;
    }
}

TEST_P(DepthCameraContractTest, heldCapturesExhaustThePoolAndComeBackOnRelease)
{
    startOrFail();
    const int pool = camera_->capabilities().poolFrames;
    std::vector<hal::Capture> held;
    for (int i = 0; i < pool; ++i) {
        auto c = camera_->capture(soon());
        ASSERT_TRUE(c) << "capture " << i << ": " << c.error().what;
        held.push_back(std::move(*c));
    }
    EXPECT_EQ(errcOf(camera_->capture(soon())), Errc::Busy);
    EXPECT_EQ(errcOf(camera_->stop()), std::nullopt);
    EXPECT_EQ(errcOf(camera_->configure(smallestMode())), Errc::Busy);
    held.erase(held.begin());
    ASSERT_TRUE(camera_->start());
    EXPECT_TRUE(camera_->capture(soon()));
}

TEST_P(DepthCameraContractTest, nothingBeforeTheDeadlineIsTimeout)
{
    startOrFail();
    ASSERT_TRUE(camera_->capture(soon()));
    // The next frame is a frame period away.
    const platform::TimePoint now = clock_->clock().now();
    EXPECT_EQ(errcOf(camera_->capture(now)), Errc::Timeout);
    if (clock_->simulated()) {
        EXPECT_EQ(clock_->clock().now(), now);
    }
}

TEST_P(DepthCameraContractTest, unpluggedCameraReportsNoDevice)
{
    if (!harness_->unplug || !harness_->replug)
        GTEST_SKIP() << "Backend cannot simulate an unplug";
    startOrFail();
    harness_->unplug(*camera_);
    EXPECT_EQ(errcOf(camera_->capture(soon())), Errc::NoDevice);
    EXPECT_TRUE(camera_->stop());
    EXPECT_EQ(errcOf(camera_->start()), Errc::NoDevice);
    EXPECT_EQ(camera_->state(), State::Configured);
    harness_->replug(*camera_);
    ASSERT_TRUE(camera_->start());
    EXPECT_TRUE(camera_->capture(soon()));
}

DT_CONTRACT_ON_ALL_BACKENDS(DepthCameraContractTest, drivers::depthCameraBackends());

} // namespace
} // namespace depthtouch::contract
