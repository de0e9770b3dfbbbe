// HAL contract: hal::HapticDevice (haptic_device.h), for every backend in the haptic device table.
#include <cmath>
#include <type_traits>

#include <gtest/gtest.h>

#include "contract_support.h"

namespace depthtouch::contract {
namespace {

using hal::HapticDevice;
using hal::HapticState;
using hal::Vec3;
using State = HapticDevice::State;
using std::chrono::milliseconds;

// The real-time methods are noexcept in every backend (checked on the interface).
static_assert(noexcept(std::declval<HapticDevice &>().read(std::declval<HapticState &>())));
static_assert(noexcept(std::declval<HapticDevice &>().commandForce(Vec3{})));
static_assert(noexcept(std::declval<const HapticDevice &>().isConnected()));
static_assert(noexcept(std::declval<const HapticDevice &>().state()));

bool inside(const Vec3 &p, const hal::HapticCapabilities &c)
{
    constexpr double kEps = 1e-12;
    return p.x >= c.workspaceMin.x - kEps && p.x <= c.workspaceMax.x + kEps &&
           p.y >= c.workspaceMin.y - kEps && p.y <= c.workspaceMax.y + kEps &&
           p.z >= c.workspaceMin.z - kEps && p.z <= c.workspaceMax.z + kEps;
}

/// The maximum force each backend declares, N: 8.5 N for the simulated devices (their default) and
/// the Falcon (its specification), none for `none`. A backend not listed must declare some.
double expectedMaxForce(const std::string &backend)
{
    if (backend == "none")
        return 0.0;
    if (backend == "mock" || backend == "sim" || backend == "falcon")
        return 8.5;
    return std::nan("");
}

class HapticDeviceContractTest : public ClosingContractTest<HapticDevice, HapticHarness> {
protected:
    void SetUp() override
    {
        createBackend(hapticHarness, "haptic device", "Haptic device", drivers::createHapticDevice);
    }
    void openOrFail() { ASSERT_TRUE(dev_->open()); }

    std::unique_ptr<HapticDevice> &dev_ = backend_;
};

TEST_P(HapticDeviceContractTest, capabilitiesAreSaneAndConstant)
{
    const hal::HapticCapabilities &c = dev_->capabilities();
    EXPECT_FALSE(c.name.empty());
    EXPECT_TRUE(std::isfinite(c.maxForce));
    // A device that renders forces declares what it can push, within 1e-9 N of its known value.
    if (const double expected = expectedMaxForce(GetParam()); !std::isnan(expected)) {
        EXPECT_NEAR(c.maxForce, expected, 1e-9);
    } else {
        EXPECT_GT(c.maxForce, 0.0) << "a backend without a known maximum must declare one";
    }
    EXPECT_EQ(c.maxForce > 0.0, harness_->hasDevice);
    EXPECT_LE(c.workspaceMin.x, c.workspaceMax.x);
    EXPECT_LE(c.workspaceMin.y, c.workspaceMax.y);
    EXPECT_LE(c.workspaceMin.z, c.workspaceMax.z);
    // The device frame's origin is the workspace centre.
    EXPECT_TRUE(inside(Vec3{}, c));
    EXPECT_GT(c.servoRateHz, 0.0);
    EXPECT_GE(c.buttonCount, 0);
    EXPECT_LE(c.buttonCount, 32);
    const double maxForce = c.maxForce;
    openOrFail();
    EXPECT_EQ(&dev_->capabilities(), &c);
    EXPECT_EQ(dev_->capabilities().maxForce, maxForce);
}

TEST_P(HapticDeviceContractTest, closedDeviceRejectsIoWithoutEffect)
{
    // GIVEN a device never opened
    EXPECT_EQ(dev_->state(), State::Closed);
    EXPECT_FALSE(dev_->isConnected());
    // WHEN reading or commanding  THEN InvalidState, and the output sample is untouched
    HapticState s;
    s.buttons = 0xdead;
    EXPECT_EQ(errcOf(dev_->read(s)), Errc::InvalidState);
    EXPECT_EQ(s.buttons, 0xdeadu);
    EXPECT_EQ(errcOf(dev_->commandForce({1.0, 0.0, 0.0})), Errc::InvalidState);
    EXPECT_EQ(dev_->state(), State::Closed);
    dev_->close(); // no-op
    EXPECT_EQ(dev_->state(), State::Closed);
}

TEST_P(HapticDeviceContractTest, openTwiceIsInvalidState)
{
    openOrFail();
    const State opened = dev_->state();
    EXPECT_NE(opened, State::Closed);
    EXPECT_EQ(errcOf(dev_->open()), Errc::InvalidState);
    EXPECT_EQ(dev_->state(), opened);
}

/// The cases for the backends that are never connected (`none`).
class HapticNoDeviceContractTest : public HapticDeviceContractTest {};

/// The cases for the backends connected after open(), whose output force the harness observes.
class HapticConnectedContractTest : public HapticDeviceContractTest {
protected:
    void SetUp() override
    {
        HapticDeviceContractTest::SetUp();
        if (harness_ != nullptr && !IsSkipped()) {
            ASSERT_TRUE(harness_->hasDevice && harness_->outputForce);
        }
    }
};

/// The cases for the connected backends whose harness can unplug and replug the device.
class HapticUnplugContractTest : public HapticConnectedContractTest {};

TEST_P(HapticNoDeviceContractTest, deviceWithoutHardwareReportsNoDevice)
{
    ASSERT_FALSE(harness_->hasDevice);
    openOrFail();
    HapticState s;
    EXPECT_EQ(dev_->state(), State::Disconnected);
    EXPECT_FALSE(dev_->isConnected());
    EXPECT_EQ(errcOf(dev_->read(s)), Errc::NoDevice);
    EXPECT_EQ(errcOf(dev_->commandForce({1.0, 0.0, 0.0})), Errc::NoDevice);
}

TEST_P(HapticConnectedContractTest, readsStayInsideTheWorkspaceWithMonotonicTimestamps)
{
    openOrFail();
    ASSERT_TRUE(dev_->isConnected());
    if (harness_->sweep)
        harness_->sweep(*dev_, clock_->clock().now());
    const hal::HapticCapabilities &c = dev_->capabilities();
    const std::uint32_t buttonMask = c.buttonCount >= 32 ? ~0u : (1u << c.buttonCount) - 1u;
    platform::TimePoint last{};
    for (int i = 0; i < 80; ++i) {
        HapticState s;
        ASSERT_TRUE(dev_->read(s)) << "read " << i;
        EXPECT_TRUE(inside(s.position, c))
            << "read " << i << ": " << s.position.x << ' ' << s.position.y << ' ' << s.position.z;
        EXPECT_TRUE(hal::isFinite(s.position));
        if (s.velocityValid) {
            EXPECT_TRUE(hal::isFinite(s.velocity));
        }
        EXPECT_EQ(s.buttons & ~buttonMask, 0u);
        EXPECT_GE(s.time, last);
        EXPECT_LE(s.time, clock_->clock().now());
        last = s.time;
        clock_->pass(milliseconds(1));
    }
}

TEST_P(HapticConnectedContractTest, forcesAreClampedToMaxForceKeepingDirection)
{
    openOrFail();
    const double maxForce = dev_->capabilities().maxForce;
    EXPECT_EQ(harness_->outputForce(*dev_), Vec3{}) << "force must be zero after open()";
    // WHEN commanding ten times the maximum along (3, -4, 0)/5
    ASSERT_TRUE(dev_->commandForce(Vec3{3.0, -4.0, 0.0} * (2.0 * maxForce)));
    // THEN the output has the maximum magnitude and the same direction
    const Vec3 out = harness_->outputForce(*dev_);
    EXPECT_NEAR(hal::norm(out), maxForce, 1e-9);
    EXPECT_NEAR(out.x, 0.6 * maxForce, 1e-9);
    EXPECT_NEAR(out.y, -0.8 * maxForce, 1e-9);
    EXPECT_NEAR(out.z, 0.0, 1e-12);
    // AND a force within the limit is output as commanded
    const Vec3 small{0.1 * maxForce, 0.0, -0.2 * maxForce};
    ASSERT_TRUE(dev_->commandForce(small));
    EXPECT_EQ(harness_->outputForce(*dev_), small);
}

TEST_P(HapticConnectedContractTest, nonFiniteForceOutputsZero)
{
    openOrFail();
    ASSERT_TRUE(dev_->commandForce({1.0, 1.0, 1.0}));
    EXPECT_EQ(errcOf(dev_->commandForce({std::nan(""), 0.0, 0.0})), Errc::InvalidArgument);
    EXPECT_EQ(errcOf(dev_->commandForce({0.0, HUGE_VAL, 0.0})), Errc::InvalidArgument);
    EXPECT_TRUE(dev_->isConnected());
    EXPECT_EQ(harness_->outputForce(*dev_), Vec3{});
}

TEST_P(HapticConnectedContractTest, closeOutputsZeroAndReturnsToClosed)
{
    openOrFail();
    ASSERT_TRUE(dev_->commandForce({1.0, 0.0, 0.0}));
    dev_->close();
    EXPECT_EQ(dev_->state(), State::Closed);
    EXPECT_FALSE(dev_->isConnected());
    EXPECT_EQ(harness_->outputForce(*dev_), Vec3{});
    HapticState s;
    EXPECT_EQ(errcOf(dev_->read(s)), Errc::InvalidState);
    // A closed device opens again with zero force.
    openOrFail();
    EXPECT_EQ(harness_->outputForce(*dev_), Vec3{});
}

TEST_P(HapticUnplugContractTest, unplugGivesNoDeviceAndZeroForce)
{
    ASSERT_TRUE(harness_->unplug && harness_->replug);
    openOrFail();
    ASSERT_TRUE(dev_->commandForce({2.0, 0.0, 0.0}));
    // WHEN the device is unplugged
    harness_->unplug(*dev_);
    // THEN read and command fail with NoDevice, the state is Disconnected and the output is zero
    HapticState s;
    EXPECT_EQ(errcOf(dev_->read(s)), Errc::NoDevice);
    EXPECT_EQ(dev_->state(), State::Disconnected);
    EXPECT_FALSE(dev_->isConnected());
    EXPECT_EQ(errcOf(dev_->commandForce({2.0, 0.0, 0.0})), Errc::NoDevice);
    EXPECT_EQ(harness_->outputForce(*dev_), Vec3{});
    // AND it stays Disconnected after replug until closed and opened again
    harness_->replug(*dev_);
    EXPECT_EQ(errcOf(dev_->read(s)), Errc::NoDevice);
    dev_->close();
    harness_->unplug(*dev_);
    EXPECT_EQ(errcOf(dev_->open()), Errc::NoDevice);
    EXPECT_EQ(dev_->state(), State::Closed);
    harness_->replug(*dev_);
    openOrFail();
    EXPECT_TRUE(dev_->read(s));
}

TEST_P(HapticDeviceContractTest, realTimeCallsDoNotAllocate)
{
    openOrFail();
    HapticState s;
    std::size_t allocations = 0;
    {
        const AllocationCounter counter;
        for (int i = 0; i < 100; ++i) {
            (void)dev_->read(s);
            (void)dev_->commandForce({0.01 * i, 0.0, 0.0});
            (void)dev_->isConnected();
            (void)dev_->state();
        }
        allocations = counter.count();
    }
    EXPECT_EQ(allocations, 0u);
}

DT_CONTRACT_ON_ALL_BACKENDS(HapticDeviceContractTest, drivers::hapticDeviceBackends());
DT_CONTRACT_ON_BACKENDS_WHERE(HapticNoDeviceContractTest, drivers::hapticDeviceBackends(),
                              hapticHarness, [](const HapticHarness &h) { return !h.hasDevice; });
DT_CONTRACT_ON_BACKENDS_WHERE(HapticConnectedContractTest, drivers::hapticDeviceBackends(),
                              hapticHarness, [](const HapticHarness &h) {
                                  return h.hasDevice && bool(h.outputForce);
                              });
DT_CONTRACT_ON_BACKENDS_WHERE(HapticUnplugContractTest, drivers::hapticDeviceBackends(),
                              hapticHarness, [](const HapticHarness &h) {
                                  return h.hasDevice && h.outputForce && h.unplug && h.replug;
                              });

} // namespace
} // namespace depthtouch::contract
