// hal::DepthCameraBase: a camera backend that implements only the hooks gets the state machine of
// depth_camera.h from the base (configure, start, capture, stop), the checks of a configuration
// that asks for nothing, and an Unconfigured camera when its device lost the configuration.
#include "depthtouch/hal/depth_camera_base.h"

#include <optional>

#include <gtest/gtest.h>

#include "support/expectations.h"

namespace depthtouch::hal {
namespace {

using depthtouch::testing::errcOf;
using State = DepthCamera::State;

class HookOnlyCamera final : public DepthCameraBase {
public:
    std::optional<Errc> failConfigure; ///< configureDevice() fails with it.
    bool loseConfiguration = false;    ///< ... and calls markUnconfigured() first.
    int configures = 0;
    int starts = 0;
    int captures = 0;
    int stops = 0;

protected:
    Result<void> configureDevice(const CameraConfig &) override
    {
        ++configures;
        if (!failConfigure)
            return ok();
        if (loseConfiguration)
            markUnconfigured();
        return unexpected(*failConfigure, "test failure");
    }
    CameraIntrinsics intrinsicsDevice() const noexcept override { return {500, 500, 319.5, 239.5}; }
    Result<void> startDevice() override
    {
        ++starts;
        return ok();
    }
    Result<Capture> captureDevice(Deadline) override
    {
        ++captures;
        return unexpected(Errc::Timeout, "no frame");
    }
    void stopDevice() noexcept override { ++stops; }
};

CameraConfig depth16(double nearM, double farM)
{
    CameraConfig c;
    c.width = 640;
    c.height = 480;
    c.fps = 30.0;
    c.depth = true;
    c.depthFormat = PixelFormat::Gray16;
    c.nearMetres = nearM;
    c.farMetres = farM;
    return c;
}

TEST(DepthCameraBaseTest, aConfigurationWithoutAStreamOrWithInvertedPlanesNeverReachesTheDevice)
{
    HookOnlyCamera cam;
    CameraConfig none = depth16(0.5, 2.0);
    none.depth = false;
    none.color = false;
    EXPECT_EQ(errcOf(cam.configure(none)), Errc::InvalidArgument);
    EXPECT_EQ(errcOf(cam.configure(depth16(2.0, 0.5))), Errc::InvalidArgument);
    EXPECT_EQ(errcOf(cam.configure(depth16(0.0, 2.0))), Errc::InvalidArgument);
    EXPECT_EQ(cam.configures, 0);
    EXPECT_EQ(cam.state(), State::Unconfigured);
    EXPECT_EQ(cam.intrinsics().fx, 0.0);
    ASSERT_TRUE(cam.configure(depth16(0.5, 2.0)));
    EXPECT_EQ(cam.state(), State::Configured);
    EXPECT_EQ(cam.intrinsics().fx, 500.0);
}

TEST(DepthCameraBaseTest, startCaptureAndStopFollowTheStates)
{
    HookOnlyCamera cam;
    EXPECT_EQ(errcOf(cam.start()), Errc::InvalidState);
    EXPECT_EQ(errcOf(cam.capture(Deadline{})), Errc::InvalidState);
    EXPECT_EQ(errcOf(cam.stop()), Errc::InvalidState);
    ASSERT_TRUE(cam.configure(depth16(0.5, 2.0)));
    EXPECT_EQ(errcOf(cam.capture(Deadline{})), Errc::InvalidState);
    ASSERT_TRUE(cam.start());
    EXPECT_EQ(cam.state(), State::Streaming);
    EXPECT_EQ(errcOf(cam.configure(depth16(0.5, 2.0))), Errc::InvalidState);
    EXPECT_EQ(errcOf(cam.start()), Errc::InvalidState);
    EXPECT_EQ(errcOf(cam.capture(Deadline{})), Errc::Timeout);
    ASSERT_TRUE(cam.stop());
    EXPECT_EQ(cam.state(), State::Configured);
    EXPECT_EQ(cam.starts, 1);
    EXPECT_EQ(cam.captures, 1);
    EXPECT_EQ(cam.stops, 1);
    EXPECT_EQ(cam.configures, 1);
}

TEST(DepthCameraBaseTest, aFailedConfigureKeepsTheStateUnlessTheDeviceLostItsConfiguration)
{
    HookOnlyCamera cam;
    ASSERT_TRUE(cam.configure(depth16(0.5, 2.0)));
    cam.failConfigure = Errc::NotSupported;
    EXPECT_EQ(errcOf(cam.configure(depth16(0.5, 2.0))), Errc::NotSupported);
    EXPECT_EQ(cam.state(), State::Configured);
    cam.failConfigure = Errc::NoDevice;
    cam.loseConfiguration = true;
    EXPECT_EQ(errcOf(cam.configure(depth16(0.5, 2.0))), Errc::NoDevice);
    EXPECT_EQ(cam.state(), State::Unconfigured);
    EXPECT_EQ(cam.intrinsics().fx, 0.0);
    // AND a later failure that does not lose it says nothing of the earlier one
    cam.failConfigure.reset();
    ASSERT_TRUE(cam.configure(depth16(0.5, 2.0)));
    cam.failConfigure = Errc::Busy;
    cam.loseConfiguration = false;
    EXPECT_EQ(errcOf(cam.configure(depth16(0.5, 2.0))), Errc::Busy);
    EXPECT_EQ(cam.state(), State::Configured);
}

} // namespace
} // namespace depthtouch::hal
