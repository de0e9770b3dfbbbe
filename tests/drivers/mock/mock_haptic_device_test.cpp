#include "depthtouch/drivers/mock/mock_haptic_device.h"

#include <gtest/gtest.h>

#include "depthtouch/drivers/mock/null_haptic_device.h"
#include "mock_test_util.h"

namespace depthtouch::drivers {
namespace {

using hal::Vec3;
using testing::at;
using testing::errcOf;

class MockHapticDeviceTest : public ::testing::Test {
protected:
    void SetUp() override { ASSERT_TRUE(dev_.open()); }
    hal::HapticState read()
    {
        hal::HapticState s;
        EXPECT_TRUE(dev_.read(s));
        return s;
    }

    platform::ManualClock clock_;
    MockHapticDevice dev_{clock_};
};

TEST_F(MockHapticDeviceTest, defaultsMatchTheDesignValues)
{
    const hal::HapticCapabilities &c = dev_.capabilities();
    EXPECT_DOUBLE_EQ(c.maxForce, 8.5);
    EXPECT_EQ(c.workspaceMin, (Vec3{-0.05, -0.05, -0.05}));
    EXPECT_EQ(c.workspaceMax, (Vec3{0.05, 0.05, 0.05}));
    EXPECT_DOUBLE_EQ(c.servoRateHz, 1000.0);
    EXPECT_EQ(c.buttonCount, 4);
    // No script: the handle rests at the workspace centre.
    EXPECT_EQ(read().position, Vec3{});
}

TEST_F(MockHapticDeviceTest, followsWaypointsInterpolatedOnTheClock)
{
    // GIVEN a script (unsorted on purpose)
    dev_.setWaypoints({{at(200), {0.0, 0.02, -0.01}, 2}, {at(100), {0.01, 0.0, 0.0}, 1}});
    // WHEN reading before, between and after the waypoints
    clock_.advanceTo(at(50));
    hal::HapticState s = read();
    EXPECT_EQ(s.position, (Vec3{0.01, 0.0, 0.0}));
    EXPECT_EQ(s.velocity, Vec3{});
    EXPECT_EQ(s.buttons, 1u);
    EXPECT_EQ(s.time, at(50));

    clock_.advanceTo(at(150));
    s = read();
    EXPECT_NEAR(s.position.x, 0.005, 1e-12);
    EXPECT_NEAR(s.position.y, 0.01, 1e-12);
    EXPECT_NEAR(s.position.z, -0.005, 1e-12);
    EXPECT_TRUE(s.velocityValid);
    EXPECT_NEAR(s.velocity.x, -0.1, 1e-9); // -0.01 m in 0.1 s
    EXPECT_NEAR(s.velocity.y, 0.2, 1e-9);
    EXPECT_EQ(s.buttons, 1u);

    clock_.advanceTo(at(500));
    s = read();
    EXPECT_EQ(s.position, (Vec3{0.0, 0.02, -0.01}));
    EXPECT_EQ(s.velocity, Vec3{});
    EXPECT_EQ(s.buttons, 2u);
    EXPECT_EQ(dev_.readCount(), 3u);
}

TEST_F(MockHapticDeviceTest, positionsAreClampedToTheWorkspace)
{
    dev_.setWaypoints({{at(0), {0.0, 0.0, 0.0}, 0xff}, {at(100), {0.2, 0.0, -0.2}, 0}});
    clock_.advanceTo(at(50)); // scripted (0.1, 0, -0.1)
    const hal::HapticState s = read();
    EXPECT_EQ(s.position, (Vec3{0.05, 0.0, -0.05}));
    EXPECT_EQ(s.velocity, Vec3{}); // clamped axes do not move
    EXPECT_EQ(s.buttons, 0xfu);    // only the device's 4 buttons
}

TEST_F(MockHapticDeviceTest, recordsAndClampsForces)
{
    ASSERT_TRUE(dev_.commandForce({1.0, 2.0, 2.0}));
    EXPECT_EQ(dev_.lastForce(), (Vec3{1.0, 2.0, 2.0}));
    ASSERT_TRUE(dev_.commandForce({0.0, 0.0, -17.0}));
    EXPECT_EQ(dev_.lastForce(), (Vec3{0.0, 0.0, -8.5}));
    EXPECT_EQ(dev_.forceCount(), 2u);
    EXPECT_EQ(dev_.clampCount(), 1u);
    EXPECT_DOUBLE_EQ(dev_.maxForceMagnitude(), 8.5);
    EXPECT_EQ(errcOf(dev_.commandForce({std::nan(""), 0.0, 0.0})), Errc::InvalidArgument);
    EXPECT_EQ(dev_.lastForce(), Vec3{});
    EXPECT_EQ(dev_.forceCount(), 3u);
}

TEST_F(MockHapticDeviceTest, disconnectZeroesTheForceUntilReopened)
{
    ASSERT_TRUE(dev_.commandForce({3.0, 0.0, 0.0}));
    dev_.disconnect();
    EXPECT_EQ(dev_.lastForce(), Vec3{});
    EXPECT_FALSE(dev_.isConnected());
    hal::HapticState s;
    EXPECT_EQ(errcOf(dev_.read(s)), Errc::NoDevice);
    EXPECT_EQ(dev_.state(), hal::HapticDevice::State::Disconnected);
    dev_.reconnect();
    EXPECT_EQ(errcOf(dev_.commandForce({1.0, 0.0, 0.0})), Errc::NoDevice);
    EXPECT_EQ(dev_.lastForce(), Vec3{});
    dev_.close();
    ASSERT_TRUE(dev_.open());
    EXPECT_EQ(dev_.lastForce(), Vec3{}); // not the force from before the unplug
    EXPECT_TRUE(dev_.read(s));
}

TEST_F(MockHapticDeviceTest, stallTimesOutAndKeepsTheForce)
{
    ASSERT_TRUE(dev_.commandForce({0.0, 1.0, 0.0}));
    dev_.setStalled(true);
    hal::HapticState s;
    EXPECT_EQ(errcOf(dev_.read(s)), Errc::Timeout);
    EXPECT_EQ(errcOf(dev_.commandForce({0.0, 5.0, 0.0})), Errc::Timeout);
    EXPECT_EQ(dev_.lastForce(), (Vec3{0.0, 1.0, 0.0}));
    EXPECT_TRUE(dev_.isConnected());
    dev_.setStalled(false);
    EXPECT_TRUE(dev_.read(s));
}

TEST(MockHapticOptionsTest, optionsSetTheCapabilities)
{
    platform::ManualClock clock;
    const hal::BackendConfig cfg =
        testing::configWith(&clock, "max_force=3,workspace=0.1,servo_rate=4000,buttons=1");
    auto d = MockHapticDevice::create(cfg);
    ASSERT_TRUE(d);
    EXPECT_DOUBLE_EQ((*d)->capabilities().maxForce, 3.0);
    EXPECT_DOUBLE_EQ((*d)->capabilities().workspaceMax.y, 0.1);
    EXPECT_DOUBLE_EQ((*d)->capabilities().servoRateHz, 4000.0);
    EXPECT_EQ((*d)->capabilities().buttonCount, 1);
    testing::expectOptionsRefused(&MockHapticDevice::create, cfg, {"max_force=-1", "maxforce=1"});
}

TEST(NullHapticDeviceTest, opensWithoutADevice)
{
    NullHapticDevice dev;
    EXPECT_EQ(dev.capabilities().name, "none");
    EXPECT_EQ(dev.capabilities().maxForce, 0.0);
    hal::HapticState s;
    EXPECT_EQ(errcOf(dev.read(s)), Errc::InvalidState);
    ASSERT_TRUE(dev.open());
    EXPECT_EQ(dev.state(), hal::HapticDevice::State::Disconnected);
    EXPECT_EQ(errcOf(dev.read(s)), Errc::NoDevice);
    EXPECT_EQ(errcOf(dev.commandForce({})), Errc::NoDevice);
    EXPECT_FALSE(dev.isConnected());
    dev.close();
    EXPECT_EQ(dev.state(), hal::HapticDevice::State::Closed);
}

} // namespace
} // namespace depthtouch::drivers
