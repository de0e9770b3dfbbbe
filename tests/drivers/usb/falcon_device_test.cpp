// The whole Falcon driver (FalconHapticDevice) against the FakeFalcon device emulator: firmware
// upload, homing, positions, forces through the emulator's own Jacobian, safety, faults, reconnect,
// and no allocation in the real-time calls.
#include "depthtouch/drivers/usb/falcon_haptic_device.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "support/allocation_counter.h"
#include "depthtouch/drivers/backends.h"
#include "depthtouch/drivers/usb/fake_falcon.h"
#include "depthtouch/drivers/usb/libusb_transport.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {
namespace {

using hal::Vec3;
using State = hal::HapticDevice::State;

template <class R> Errc codeOf(const R &r)
{
    EXPECT_FALSE(r) << "expected an error";
    return r ? Errc::InvalidState : r.error().code;
}

/// A firmware image of \a size bytes in a temporary file, removed at the end.
class FirmwareFile {
public:
    explicit FirmwareFile(std::size_t size)
    {
        char tmpl[] = "/tmp/dt-falcon-fw-XXXXXX";
        const int fd = ::mkstemp(tmpl);
        EXPECT_GE(fd, 0);
        ::close(fd);
        path_ = tmpl;
        std::ofstream out(path_, std::ios::binary);
        for (std::size_t i = 0; i < size; ++i)
            out.put(static_cast<char>((i * 7 + 3) & 0xff));
    }
    ~FirmwareFile() { std::remove(path_.c_str()); }
    FirmwareFile(const FirmwareFile &) = delete;
    FirmwareFile &operator=(const FirmwareFile &) = delete;
    [[nodiscard]] const std::string &path() const { return path_; }

private:
    std::string path_;
};

class FalconDeviceTest : public ::testing::Test {
protected:
    void make(const FakeFalconSettings &fake, FalconSettings settings)
    {
        auto transport = std::make_unique<FakeFalcon>(fake);
        fake_ = transport.get();
        dev_ = std::make_unique<FalconHapticDevice>(clock_, std::move(transport),
                                                    std::move(settings));
    }
    /// A Falcon without firmware and a driver given the firmware file.
    void makeWithUpload()
    {
        FalconSettings s;
        s.firmwarePath = firmware_.path();
        make({}, s);
    }
    void openOrFail() { ASSERT_TRUE(dev_->open()); }
    hal::HapticState readOrFail()
    {
        hal::HapticState s;
        auto r = dev_->read(s);
        EXPECT_TRUE(r) << (r ? "" : r.error().what);
        return s;
    }

    platform::ManualClock clock_{platform::ManualClock::Mode::AutoAdvance,
                                 platform::TimePoint(std::chrono::seconds(5))};
    FirmwareFile firmware_{4096};
    FakeFalcon *fake_ = nullptr;
    std::unique_ptr<FalconHapticDevice> dev_;
};

TEST_F(FalconDeviceTest, openUploadsTheFirmwareAndHomes)
{
    // GIVEN a Falcon whose firmware is not running
    makeWithUpload();
    EXPECT_EQ(fake_->mode(), FakeFalcon::Mode::Off);
    // WHEN opening
    openOrFail();
    // THEN the image went through the loader, the firmware runs at its serial setup, and the
    // device homed with the homing flag (green LED after)
    EXPECT_EQ(fake_->uploads(), 1);
    EXPECT_EQ(fake_->firmwareBytes(), 4096u);
    EXPECT_EQ(fake_->mode(), FakeFalcon::Mode::Running);
    EXPECT_EQ(fake_->baudDivisor(), kFtdiBaud1456312);
    EXPECT_EQ(fake_->latencyMs(), 1);
    EXPECT_TRUE(dev_->homed());
    EXPECT_EQ(dev_->state(), State::Open);
    EXPECT_TRUE(dev_->isConnected());
    readOrFail();
    EXPECT_EQ(dev_->flags() & (falcon::kLedGreen | falcon::kLedRed | falcon::kFlagHoming),
              falcon::kLedGreen);
    // AND the loader was entered at 9600 baud with a DTR pulse before the 140000-baud transfer
    const auto &c = fake_->controls();
    const auto at = [&](FtdiRequest r, std::uint16_t v) {
        return std::find(c.begin(), c.end(), std::make_pair(r, v)) - c.begin();
    };
    EXPECT_LT(at(FtdiRequest::BaudRate, kFtdiBaud9600),
              at(FtdiRequest::ModemControl, kFtdiDtrHigh));
    EXPECT_LT(at(FtdiRequest::ModemControl, kFtdiDtrHigh),
              at(FtdiRequest::BaudRate, kFtdiBaud140000));
    EXPECT_LT(at(FtdiRequest::LatencyTimer, 16), at(FtdiRequest::BaudRate, kFtdiBaud140000));
}

TEST_F(FalconDeviceTest, runningFirmwareIsNotUploadedAgain)
{
    FakeFalconSettings fake;
    fake.firmwareAtPowerUp = true;
    make(fake, {});
    openOrFail();
    EXPECT_EQ(fake_->uploads(), 0);
    EXPECT_TRUE(dev_->homed());
}

TEST_F(FalconDeviceTest, missingFirmwareOptionIsAClearError)
{
    make({}, {});
    EXPECT_EQ(codeOf(dev_->open()), Errc::InvalidArgument);
    EXPECT_EQ(dev_->state(), State::Closed);
    EXPECT_FALSE(fake_->present()); // the transport was released
}

TEST_F(FalconDeviceTest, missingUnreadableOrWrongSizeFirmwareFilesAreRefused)
{
    FalconSettings s;
    s.firmwarePath = "/nonexistent/falcon.bin";
    make({}, s);
    EXPECT_EQ(codeOf(dev_->open()), Errc::InvalidArgument);

    s.firmwarePath = "/tmp"; // a directory: opens but cannot be read
    make({}, s);
    EXPECT_EQ(codeOf(dev_->open()), Errc::InvalidArgument);

    const FirmwareFile tiny(10);
    s.firmwarePath = tiny.path();
    make({}, s);
    EXPECT_EQ(codeOf(dev_->open()), Errc::InvalidArgument);
    EXPECT_EQ(fake_->firmwareBytes(), 0u); // nothing was sent

    const FirmwareFile huge(falcon::kFirmwareMaxBytes + 1);
    s.firmwarePath = huge.path();
    make({}, s);
    EXPECT_EQ(codeOf(dev_->open()), Errc::InvalidArgument);
    EXPECT_EQ(dev_->state(), State::Closed);
}

TEST_F(FalconDeviceTest, firmwareTheDeviceRejectsFailsOpenWithIo)
{
    // GIVEN a device expecting another image size: the upload echoes fine but the firmware never
    // starts
    FakeFalconSettings fake;
    fake.firmwareSize = 5000;
    FalconSettings s;
    s.firmwarePath = firmware_.path();
    make(fake, s);
    EXPECT_EQ(codeOf(dev_->open()), Errc::Io);
    EXPECT_EQ(dev_->state(), State::Closed);
}

TEST_F(FalconDeviceTest, readsThePositionsTheFakeReports)
{
    makeWithUpload();
    openOrFail();
    // GIVEN grip positions over the inner workspace, visited in a sweep (the FK is warm-started)
    const double h = falcon::kWorkspaceHalfExtent * 0.75;
    double worst = 0.0;
    for (double x : {-h, 0.0, h})
        for (double y : {-h, -h / 3, h / 2, h})
            for (double z : {-h, 0.0, h}) {
                const Vec3 p{x, y, z};
                ASSERT_TRUE(fake_->setGripPosition(p));
                const hal::HapticState s = readOrFail();
                worst = std::max(worst, hal::norm(s.position - p));
                EXPECT_NEAR(s.position.x, x, 0.05e-3);
                EXPECT_NEAR(s.position.y, y, 0.05e-3);
                EXPECT_NEAR(s.position.z, z, 0.05e-3);
            }
    std::printf("Driver position error over 36 poses (encoder quantisation): %.3g m; FK mean "
                "%.2f, max %d iterations\n",
                worst,
                static_cast<double>(dev_->stats().fkIterations) /
                    static_cast<double>(dev_->stats().exchanges),
                dev_->stats().fkMaxIterations);
    EXPECT_EQ(dev_->stats().fkFailures, 0u);
}

TEST_F(FalconDeviceTest, positionsOutsideTheBoxAreClampedToIt)
{
    makeWithUpload();
    openOrFail();
    ASSERT_TRUE(fake_->setGripPosition({0.043, 0.0, 0.0})); // reachable, beyond the box
    const hal::HapticState s = readOrFail();
    EXPECT_DOUBLE_EQ(s.position.x, falcon::kWorkspaceHalfExtent);
}

TEST_F(FalconDeviceTest, buttonsAndTimestampsAreReported)
{
    makeWithUpload();
    openOrFail();
    fake_->setButtons(0x05);
    const platform::TimePoint before = clock_.now();
    const hal::HapticState s = readOrFail();
    EXPECT_EQ(s.buttons, 0x05u);
    EXPECT_GE(s.time, before);
    EXPECT_LE(s.time, clock_.now());
}

TEST_F(FalconDeviceTest, commandedForceIsWhatTheFakeDecodesThroughItsOwnJacobian)
{
    makeWithUpload();
    openOrFail();
    for (const Vec3 &p : {Vec3{}, Vec3{0.02, -0.01, 0.015}, Vec3{-0.025, 0.025, -0.02}}) {
        ASSERT_TRUE(fake_->setGripPosition(p));
        readOrFail();
        for (const Vec3 &f : {Vec3{0.0, 0.0, 3.0}, Vec3{-2.0, 1.0, 0.5}, Vec3{0.0, -4.0, 0.0}}) {
            // WHEN commanding f  AND  the next exchange carries it to the device
            ASSERT_TRUE(dev_->commandForce(f));
            readOrFail();
            // THEN the force the fake computes from the motor commands is f (within one count)
            const Vec3 out = fake_->outputForce();
            EXPECT_NEAR(out.x, f.x, 0.02) << p.x << ' ' << p.y << ' ' << p.z;
            EXPECT_NEAR(out.y, f.y, 0.02);
            EXPECT_NEAR(out.z, f.z, 0.02);
            EXPECT_EQ(dev_->outputForce(), f);
        }
    }
}

TEST_F(FalconDeviceTest, forceIsClampedToMaxForceKeepingItsDirection)
{
    makeWithUpload();
    openOrFail();
    readOrFail();
    ASSERT_TRUE(dev_->commandForce({30.0, 0.0, -40.0})); // 50 N
    readOrFail();
    const Vec3 out = fake_->outputForce();
    EXPECT_NEAR(hal::norm(out), kFalconMaxForce, 0.03);
    EXPECT_NEAR(out.x / hal::norm(out), 0.6, 0.005);
    EXPECT_NEAR(out.z / hal::norm(out), -0.8, 0.005);
}

TEST_F(FalconDeviceTest, forceBeyondTheMotorRangeIsScaledDownKeepingItsDirection)
{
    // GIVEN the grip in a corner of the workspace and a force along an axis that needs more than
    // the command limit there (found by trying the corners and axes)
    makeWithUpload();
    openOrFail();
    const double h = falcon::kWorkspaceHalfExtent;
    Vec3 corner;
    Vec3 force;
    double most = 0.0;
    for (double x : {-h, h})
        for (double y : {-h, h})
            for (double z : {-h, h})
                for (const Vec3 &f : {Vec3{8.5, 0, 0}, Vec3{-8.5, 0, 0}, Vec3{0, 8.5, 0},
                                      Vec3{0, -8.5, 0}, Vec3{0, 0, 8.5}, Vec3{0, 0, -8.5}}) {
                    falcon::JointAngles th{};
                    Vec3 tau;
                    ASSERT_TRUE(falcon::inverseKinematics({x, y, z}, th));
                    ASSERT_TRUE(falcon::jointTorques(th, {x, y, z}, f, tau));
                    const double need =
                        std::max({std::abs(tau.x), std::abs(tau.y), std::abs(tau.z)}) *
                        falcon::kCountsPerNewtonMetre;
                    if (need > most) {
                        most = need;
                        corner = {x, y, z};
                        force = f;
                    }
                }
    ASSERT_GT(most, falcon::kMotorCommandLimit);
    ASSERT_TRUE(fake_->setGripPosition(corner));
    readOrFail();
    // WHEN commanding it
    ASSERT_TRUE(dev_->commandForce(force));
    readOrFail();
    // THEN the largest command is at the limit, the force keeps its direction at the size the
    // limit allows, and the driver reports the force it outputs
    const falcon::MotorCommands &m = fake_->lastCommand().motors;
    EXPECT_EQ(std::max({std::abs(m[0]), std::abs(m[1]), std::abs(m[2])}),
              falcon::kMotorCommandLimit);
    const Vec3 out = fake_->outputForce();
    const Vec3 want = force * (falcon::kMotorCommandLimit / most);
    EXPECT_NEAR(out.x, want.x, 0.02);
    EXPECT_NEAR(out.y, want.y, 0.02);
    EXPECT_NEAR(out.z, want.z, 0.02);
    // (the driver's pose comes from whole encoder counts, within 0.05 mm of the grip's)
    EXPECT_NEAR(hal::norm(dev_->outputForce() - want), 0.0, 0.005);
    EXPECT_EQ(dev_->stats().rangeClamps, 1u);
}

TEST_F(FalconDeviceTest, nonFiniteForceOutputsZero)
{
    makeWithUpload();
    openOrFail();
    readOrFail();
    ASSERT_TRUE(dev_->commandForce({1.0, 2.0, 0.0}));
    EXPECT_EQ(codeOf(dev_->commandForce({std::nan(""), 0.0, 0.0})), Errc::InvalidArgument);
    readOrFail();
    EXPECT_EQ(fake_->lastCommand().motors, (falcon::MotorCommands{0, 0, 0}));
    EXPECT_EQ(dev_->outputForce(), Vec3{});
    EXPECT_TRUE(dev_->isConnected());
}

TEST_F(FalconDeviceTest, noForceUntilHomed)
{
    // GIVEN a device that homes only after 50 packets, and a driver waiting for 5 at open()
    FakeFalconSettings fake;
    fake.homingPackets = 50;
    FalconSettings s;
    s.firmwarePath = firmware_.path();
    s.homingPackets = 5;
    make(fake, s);
    openOrFail();
    EXPECT_FALSE(dev_->homed());
    // WHEN commanding a force before homing  THEN zero goes out, with the homing flag and red LED
    ASSERT_TRUE(dev_->commandForce({0.0, 0.0, 2.0}));
    readOrFail();
    EXPECT_EQ(fake_->lastCommand().motors, (falcon::MotorCommands{0, 0, 0}));
    EXPECT_EQ(fake_->lastCommand().flags & (falcon::kFlagHoming | falcon::kLedRed),
              falcon::kFlagHoming | falcon::kLedRed);
    // AND once the fake homes, forces flow and the LED turns green
    for (int i = 0; i < 60 && !dev_->homed(); ++i)
        readOrFail();
    ASSERT_TRUE(dev_->homed());
    ASSERT_TRUE(dev_->commandForce({0.0, 0.0, 2.0}));
    readOrFail();
    EXPECT_NEAR(fake_->outputForce().z, 2.0, 0.02);
    EXPECT_EQ(fake_->lastCommand().flags & (falcon::kLedGreen | falcon::kLedRed | falcon::kLedBlue),
              falcon::kLedGreen | falcon::kLedBlue);
}

TEST_F(FalconDeviceTest, unplugGivesNoDeviceZeroForceAndReconnectsThroughCloseOpen)
{
    makeWithUpload();
    openOrFail();
    readOrFail();
    ASSERT_TRUE(dev_->commandForce({0.0, 3.0, 0.0}));
    // WHEN the Falcon is unplugged
    fake_->unplug();
    hal::HapticState s;
    EXPECT_EQ(codeOf(dev_->read(s)), Errc::NoDevice);
    EXPECT_EQ(dev_->state(), State::Disconnected);
    EXPECT_EQ(codeOf(dev_->commandForce({0.0, 3.0, 0.0})), Errc::NoDevice);
    EXPECT_EQ(dev_->outputForce(), Vec3{});
    EXPECT_EQ(dev_->motorCommands(), (falcon::MotorCommands{0, 0, 0}));
    // AND while it is away open() fails with NoDevice
    dev_->close();
    EXPECT_EQ(codeOf(dev_->open()), Errc::NoDevice);
    // WHEN plugged back in (powered up without firmware)  THEN close/open uploads it again
    fake_->replug();
    openOrFail();
    EXPECT_EQ(fake_->uploads(), 2); // the replugged device lost its firmware
    readOrFail();
    ASSERT_TRUE(dev_->commandForce({0.0, 3.0, 0.0}));
    readOrFail();
    EXPECT_NEAR(fake_->outputForce().y, 3.0, 0.02);
}

TEST_F(FalconDeviceTest, silenceTimesOutAndTheDeviceStaysOpen)
{
    makeWithUpload();
    openOrFail();
    fake_->setSilent(true);
    hal::HapticState s;
    EXPECT_EQ(codeOf(dev_->read(s)), Errc::Timeout);
    EXPECT_EQ(dev_->state(), State::Open);
    fake_->setSilent(false);
    readOrFail();
    EXPECT_GE(dev_->stats().timeouts, 1u);
}

TEST_F(FalconDeviceTest, corruptPacketIsATimeoutAndTheNextReadRecovers)
{
    makeWithUpload();
    openOrFail();
    ASSERT_TRUE(fake_->setGripPosition({0.01, 0.0, 0.0}));
    fake_->corruptNext(1);
    hal::HapticState s;
    EXPECT_EQ(codeOf(dev_->read(s)), Errc::Timeout);
    EXPECT_EQ(dev_->stats().framingErrors, 1u);
    s = readOrFail();
    EXPECT_NEAR(s.position.x, 0.01, 0.05e-3);
}

TEST_F(FalconDeviceTest, closeSendsZeroForceAndReleasesTheDevice)
{
    makeWithUpload();
    openOrFail();
    readOrFail();
    ASSERT_TRUE(dev_->commandForce({1.0, 0.0, 0.0}));
    readOrFail();
    EXPECT_NE(fake_->lastCommand().motors, (falcon::MotorCommands{0, 0, 0}));
    dev_->close();
    EXPECT_EQ(fake_->lastCommand().motors, (falcon::MotorCommands{0, 0, 0}));
    EXPECT_EQ(fake_->lastCommand().flags, 0); // LEDs off
    EXPECT_FALSE(fake_->present());
    EXPECT_EQ(dev_->state(), State::Closed);
    hal::HapticState s;
    EXPECT_EQ(codeOf(dev_->read(s)), Errc::InvalidState);
}

TEST_F(FalconDeviceTest, readAndCommandDoNotAllocate)
{
    makeWithUpload();
    openOrFail();
    hal::HapticState s;
    const std::uint64_t exchanges = dev_->stats().exchanges;
    const testing::AllocationCounter allocations;
    for (int i = 0; i < 1000; ++i) {
        (void)fake_->setGripPosition({0.01 * std::sin(i * 0.01), 0.0, 0.005});
        (void)dev_->read(s);
        (void)dev_->commandForce({0.0, 0.001 * i, 1.0});
        (void)dev_->isConnected();
        (void)dev_->state();
    }
    EXPECT_EQ(allocations.count(), 0u);
    EXPECT_EQ(dev_->stats().exchanges - exchanges, 1000u);
}

TEST(FalconBackendTest, emulatedBackendIsCreatedByName)
{
    platform::ManualClock clock;
    hal::BackendConfig cfg;
    cfg.clock = &clock;
    cfg.options = hal::OptionList("emulate=1,max_force=5");
    auto dev = createHapticDevice("falcon", cfg);
    ASSERT_TRUE(dev) << dev.error().what;
    EXPECT_EQ((*dev)->capabilities().maxForce, 5.0);
    EXPECT_EQ((*dev)->capabilities().servoRateHz, 1000.0);
    ASSERT_TRUE((*dev)->open());
    hal::HapticState s;
    EXPECT_TRUE((*dev)->read(s));
}

TEST(FalconBackendTest, badOptionsAreRefused)
{
    hal::BackendConfig cfg;
    for (const char *opts : {"emulate=1,colour=red", "emulate=1,max_force=20", "emulate=maybe",
                             "emulate=1,max_force=-1", "emulate=1,firmware="}) {
        cfg.options = hal::OptionList(opts);
        auto dev = FalconHapticDevice::create(cfg);
        EXPECT_FALSE(dev) << opts;
        if (!dev) {
            EXPECT_EQ(dev.error().code, Errc::InvalidArgument) << opts;
        }
    }
}

TEST(FalconBackendTest, withoutADeviceTheFactoryReportsNoDevice)
{
    auto present = LibusbTransport::probe(kFalconVendorId, kFalconProductId);
    if (present && *present)
        GTEST_SKIP() << "A Novint Falcon is connected";
    auto dev = FalconHapticDevice::create({});
    ASSERT_FALSE(dev);
    EXPECT_EQ(dev.error().code, Errc::NoDevice);
}

TEST(FalconBackendTest, aPlayerThatWaitsForItsFalconGetsOneThatOpensWhenPluggedIn)
{
    // hal::BackendConfig::awaitDevice (`play --idle`): no Falcon at the start is not a failure;
    // the device says it is awaited, and its open() reports NoDevice until one is plugged in (the
    // haptic task's supervisor retries it).
    auto present = LibusbTransport::probe(kFalconVendorId, kFalconProductId);
    if (present && *present)
        GTEST_SKIP() << "A Novint Falcon is connected";
    hal::BackendConfig cfg;
    cfg.awaitDevice = true;
    auto dev = FalconHapticDevice::create(cfg);
    ASSERT_TRUE(dev) << dev.error().what;
    EXPECT_TRUE((*dev)->awaitingDevice());
    EXPECT_FALSE((*dev)->isConnected());
    EXPECT_EQ((*dev)->capabilities().maxForce, kFalconMaxForce) << "its capabilities are known";
    EXPECT_EQ(codeOf((*dev)->open()), Errc::NoDevice);
    EXPECT_TRUE((*dev)->awaitingDevice()) << "still awaited after a try";

    // An emulated Falcon is always there: nothing is awaited.
    cfg.options = hal::OptionList("emulate=1");
    auto emulated = FalconHapticDevice::create(cfg);
    ASSERT_TRUE(emulated);
    EXPECT_FALSE((*emulated)->awaitingDevice());
}

TEST(LibusbTransportTest, withoutTheDeviceEverythingReportsNoDevice)
{
    auto present = LibusbTransport::probe(kFalconVendorId, kFalconProductId);
    if (present && *present)
        GTEST_SKIP() << "A Novint Falcon is connected";
    LibusbTransport usb;
    EXPECT_FALSE(usb.present());
    EXPECT_EQ(codeOf(usb.open(kFalconVendorId, kFalconProductId)), Errc::NoDevice);
    EXPECT_FALSE(usb.present());
    std::uint8_t buf[16] = {};
    EXPECT_EQ(codeOf(usb.exchange(buf, sizeof buf, buf, sizeof buf, std::chrono::milliseconds(1))),
              Errc::NoDevice);
    EXPECT_EQ(codeOf(usb.control(FtdiRequest::LatencyTimer, 1)), Errc::NoDevice);
    usb.close(); // no-op
}

} // namespace
} // namespace depthtouch::drivers
