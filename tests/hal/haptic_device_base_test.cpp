// hal::HapticDeviceBase: a backend that implements only the device hooks gets the whole contract
// from the base (state checks, presence, clamp, non-finite force), and cannot bypass it: its hooks
// see only finite forces within the maximum, and are not called for a closed or lost device.
#include "depthtouch/hal/haptic_device_base.h"

#include <cmath>
#include <cstring>
#include <optional>
#include <type_traits>

#include <gtest/gtest.h>

#include "support/expectations.h"

namespace depthtouch::hal {
namespace {

using State = HapticDevice::State;

/// The least a backend writes: the hooks, recording what reaches them.
class HookOnlyDevice final : public HapticDeviceBase {
public:
    explicit HookOnlyDevice(double maxForce)
    {
        caps_.name = "hook-only test device";
        caps_.maxForce = maxForce;
        caps_.servoRateHz = 1000.0;
    }

    bool present = true;          ///< devicePresent().
    State openAs = State::Open;   ///< What openDevice() returns.
    std::optional<Errc> failWith; ///< readDevice() and commandForceDevice() fail with it.
    int opens = 0;                ///< openDevice() calls.
    int closes = 0;               ///< closeDevice() calls.
    int reads = 0;                ///< readDevice() calls.
    int commands = 0;             ///< commandForceDevice() calls.
    int zeroes = 0;               ///< zeroForceDevice() calls.
    ForceCommand last{{9.0, 9.0, 9.0}, -1.0, true}; ///< The last command received.

protected:
    Result<State> openDevice() override
    {
        ++opens;
        return openAs;
    }
    void closeDevice() noexcept override { ++closes; }
    bool devicePresent() const noexcept override { return present; }
    Result<void> readDevice(HapticState &out) noexcept override
    {
        ++reads;
        if (failWith)
            return unexpected(*failWith, "test failure");
        out.position = {0.001, 0.002, 0.003};
        return ok();
    }
    Result<void> commandForceDevice(const ForceCommand &command) noexcept override
    {
        ++commands;
        if (failWith)
            return unexpected(*failWith, "test failure");
        last = command;
        return ok();
    }
    void zeroForceDevice() noexcept override { ++zeroes; }
};

using depthtouch::testing::errcOf;

/// Opens \a dev and makes its hooks fail with \a code from then on. \return the error of the
/// read() that follows.
std::optional<Errc> readErrorOnceFailingWith(HookOnlyDevice &dev, Errc code)
{
    EXPECT_TRUE(dev.open());
    dev.failWith = code;
    HapticState s;
    return errcOf(dev.read(s));
}

bool sameBits(double a, double b)
{
    return std::memcmp(&a, &b, sizeof a) == 0;
}

// The public methods are the base's (final): a backend reaches them only through its hooks.
static_assert(std::is_base_of_v<HapticDevice, HapticDeviceBase>);
static_assert(!std::is_constructible_v<HapticDeviceBase>);

TEST(HapticDeviceBaseTest, forceLongerThanTheMaximumReachesTheDeviceClampedKeepingItsDirection)
{
    HookOnlyDevice dev(8.5);
    ASSERT_TRUE(dev.open());
    // WHEN commanding twice the maximum along (3, -4, 0)/5 ...
    ASSERT_TRUE(dev.commandForce(Vec3{3.0, -4.0, 0.0} * (2.0 * 8.5 / 5.0)));
    // THEN the hook gets the maximum along the same direction, marked clamped
    EXPECT_TRUE(dev.last.clamped);
    EXPECT_EQ(dev.last.magnitude, 8.5);
    EXPECT_NEAR(norm(dev.last.force), 8.5, 1e-12);
    EXPECT_NEAR(dev.last.force.x, 0.6 * 8.5, 1e-12);
    EXPECT_NEAR(dev.last.force.y, -0.8 * 8.5, 1e-12);
    EXPECT_EQ(dev.last.force.z, 0.0);
    // AND a force within the maximum reaches it bit for bit, not clamped
    const Vec3 small{0.1, -2.5, 3.25};
    ASSERT_TRUE(dev.commandForce(small));
    EXPECT_FALSE(dev.last.clamped);
    EXPECT_TRUE(sameBits(dev.last.force.x, small.x) && sameBits(dev.last.force.y, small.y) &&
                sameBits(dev.last.force.z, small.z));
    EXPECT_EQ(dev.last.magnitude, norm(small));
}

TEST(HapticDeviceBaseTest, clampForceScalesByMaximumOverMagnitude)
{
    const Vec3 f{0.0, 0.0, -20.0};
    const ForceCommand c = clampForce(f, 4.0);
    EXPECT_TRUE(c.clamped);
    EXPECT_EQ(c.magnitude, 4.0);
    EXPECT_EQ(c.force, (Vec3{0.0, 0.0, -4.0}));
    const ForceCommand at = clampForce({4.0, 0.0, 0.0}, 4.0);
    EXPECT_FALSE(at.clamped); // exactly the maximum is not clamped
    EXPECT_EQ(at.force, (Vec3{4.0, 0.0, 0.0}));
}

TEST(HapticDeviceBaseTest, nonFiniteForceReachesTheDeviceAsZeroAndIsRejected)
{
    HookOnlyDevice dev(8.5);
    ASSERT_TRUE(dev.open());
    ASSERT_TRUE(dev.commandForce({1.0, 1.0, 1.0}));
    for (const Vec3 bad :
         {Vec3{std::nan(""), 0.0, 0.0}, Vec3{0.0, HUGE_VAL, 0.0}, Vec3{0.0, 0.0, -HUGE_VAL}}) {
        dev.last = {{9.0, 9.0, 9.0}, -1.0, true};
        EXPECT_EQ(errcOf(dev.commandForce(bad)), Errc::InvalidArgument);
        EXPECT_EQ(dev.last.force, Vec3{});
        EXPECT_EQ(dev.last.magnitude, 0.0);
        EXPECT_FALSE(dev.last.clamped);
    }
    EXPECT_EQ(dev.state(), State::Open);
    EXPECT_TRUE(dev.isConnected());
}

TEST(HapticDeviceBaseTest, closedDeviceRejectsIoWithoutReachingTheDevice)
{
    HookOnlyDevice dev(8.5);
    HapticState s;
    EXPECT_EQ(errcOf(dev.read(s)), Errc::InvalidState);
    EXPECT_EQ(errcOf(dev.commandForce({1.0, 0.0, 0.0})), Errc::InvalidState);
    EXPECT_FALSE(dev.isConnected());
    EXPECT_EQ(dev.reads + dev.commands, 0);
    ASSERT_TRUE(dev.open());
    EXPECT_EQ(errcOf(dev.open()), Errc::InvalidState);
    EXPECT_EQ(dev.opens, 1);
    dev.close();
    EXPECT_EQ(dev.state(), State::Closed);
    EXPECT_EQ(dev.closes, 1);
    EXPECT_EQ(errcOf(dev.commandForce({1.0, 0.0, 0.0})), Errc::InvalidState);
    EXPECT_EQ(dev.commands, 0);
}

TEST(HapticDeviceBaseTest, unpluggedDeviceIsZeroedAndNeverCommandedAgain)
{
    HookOnlyDevice dev(8.5);
    ASSERT_TRUE(dev.open());
    ASSERT_TRUE(dev.commandForce({2.0, 0.0, 0.0}));
    ASSERT_EQ(dev.commands, 1);
    // WHEN the device goes away
    dev.present = false;
    EXPECT_FALSE(dev.isConnected());
    // THEN the next command is NoDevice, the output zeroed, the state Disconnected
    EXPECT_EQ(errcOf(dev.commandForce({2.0, 0.0, 0.0})), Errc::NoDevice);
    EXPECT_EQ(dev.state(), State::Disconnected);
    EXPECT_EQ(dev.zeroes, 1);
    // AND nothing reaches the device until it is closed and opened again, even once it is back
    dev.present = true;
    HapticState s;
    EXPECT_EQ(errcOf(dev.read(s)), Errc::NoDevice);
    EXPECT_EQ(errcOf(dev.commandForce({2.0, 0.0, 0.0})), Errc::NoDevice);
    EXPECT_EQ(dev.commands, 1);
    EXPECT_EQ(dev.reads, 0);
    EXPECT_FALSE(dev.isConnected());
    dev.close();
    ASSERT_TRUE(dev.open());
    EXPECT_TRUE(dev.read(s));
    EXPECT_EQ(s.position, (Vec3{0.001, 0.002, 0.003}));
}

TEST(HapticDeviceBaseTest, deviceReportingNoDeviceIsMarkedDisconnected)
{
    HookOnlyDevice dev(8.5);
    EXPECT_EQ(readErrorOnceFailingWith(dev, Errc::NoDevice), Errc::NoDevice);
    EXPECT_EQ(dev.state(), State::Disconnected);
    EXPECT_EQ(dev.zeroes, 1);
    dev.close();
    ASSERT_TRUE(dev.open());
    EXPECT_EQ(errcOf(dev.commandForce({std::nan(""), 0.0, 0.0})), Errc::NoDevice);
    EXPECT_EQ(dev.state(), State::Disconnected);
}

TEST(HapticDeviceBaseTest, timeoutKeepsTheDeviceOpen)
{
    HookOnlyDevice dev(8.5);
    EXPECT_EQ(readErrorOnceFailingWith(dev, Errc::Timeout), Errc::Timeout);
    EXPECT_EQ(errcOf(dev.commandForce({1.0, 0.0, 0.0})), Errc::Timeout);
    EXPECT_EQ(errcOf(dev.commandForce({std::nan(""), 0.0, 0.0})), Errc::Timeout);
    EXPECT_EQ(dev.state(), State::Open);
    EXPECT_EQ(dev.zeroes, 0);
}

TEST(HapticDeviceBaseTest, backendWithoutDeviceOpensDisconnected)
{
    HookOnlyDevice dev(0.0);
    dev.present = false;
    dev.openAs = State::Disconnected;
    ASSERT_TRUE(dev.open());
    EXPECT_EQ(dev.state(), State::Disconnected);
    HapticState s;
    EXPECT_EQ(errcOf(dev.read(s)), Errc::NoDevice);
    EXPECT_EQ(errcOf(dev.commandForce({1.0, 0.0, 0.0})), Errc::NoDevice);
    EXPECT_EQ(dev.reads + dev.commands, 0);
}

TEST(HapticDeviceBaseTest, stateNamesAreTheEnumerators)
{
    depthtouch::testing::expectNames<State>(
        {{State::Closed, "Closed"}, {State::Open, "Open"}, {State::Disconnected, "Disconnected"}});
}

} // namespace
} // namespace depthtouch::hal
