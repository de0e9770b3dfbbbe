// The Falcon driver against outside reference values from libnifalcon, the open-source Novint
// Falcon driver (FalconKinematicStamper and FalconGeometry of its current release), rather than
// against the driver's own kinematics. All reference positions are in libnifalcon's frame: origin
// at the centre of the three motor axes, x right, y up, z toward the user, metres. The driver's
// device frame has the same axes with its origin at libnifalcon's (0, 0, 0.110)
// (falcon_kinematics.h), so libnifalcon's q is the device's q − (0, 0, 0.110).
//
// Reference values (computed with libnifalcon):
//   IK (0, 0, 0.11) m      → theta = 0.282533199 rad on each arm;
//   IK (0.02, 0, 0.12) m   → theta = (0.514268160, 0.221173629, 0.595672846) rad;
//   getForces: (0, 0, −1) N at (0, 0, 0.11) m → motor commands (323, 323, 323).
// The lateral force values below were computed for this test with libnifalcon's getForces
// formulas in double precision: (1, 0, 0) N and (0, 1, 0) N at (0, 0, 0.11) m give commands
// (−154.877, 527.249, −372.372) and (519.397, −125.571, −393.826) before libnifalcon truncates
// them to integers.
//
// Tolerances: angles 1e-7 rad (libnifalcon's values differ from a double-precision evaluation of
// the same formulas by up to 2.5e-8 rad; one encoder count is 6.4e-4 rad, and a 0.1 mm change of
// an arm dimension moves an angle by about 1e-3 rad). Commands: exact after rounding where the
// reference has three decimals; the z force is explained at libZCorrection().
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>

#include <gtest/gtest.h>

#include "depthtouch/drivers/usb/falcon_haptic_device.h"
#include "depthtouch/drivers/usb/falcon_kinematics.h"
#include "depthtouch/drivers/usb/usb_transport.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {
namespace {

using falcon::JointAngles;
using hal::Vec3;

/// libnifalcon's FalconGeometry.h (metres, degrees), kept here apart from the driver's constants.
namespace lib {
constexpr double a = 0.060;
constexpr double b = 0.1025;
constexpr double c = 0.01443;
constexpr double d = 0.01125;
constexpr double e = 0.01125;
constexpr double f = -0.025;
constexpr double r = 0.0400;
constexpr double s = -0.02309;
constexpr double kWheelSlots = 320.0;
constexpr double kShaftDiameter = 0.01425;
constexpr double kArmDiameter = 0.110;
constexpr double kThetaOffsetDeg = 35.0;
constexpr double kPi = 3.14159265358979323846;

/// The encoder count libnifalcon's getTheta() maps to \a theta (radians), unrounded.
double encoderFor(double theta)
{
    const double degPerCount =
        (kShaftDiameter * kPi / (kWheelSlots * 4.0)) / (kPi * kArmDiameter / 360.0);
    return (theta * 180.0 / kPi - kThetaOffsetDeg) / degPerCount;
}
} // namespace lib

/// libnifalcon's frame → the driver's device frame.
Vec3 fromLib(const Vec3 &q)
{
    return {q.x, q.y, q.z - 0.110};
}

constexpr double kAngleTol = 1e-7;

TEST(FalconReferenceTest, inverseKinematicsAtTheWorkspaceCentreMatchesLibnifalcon)
{
    JointAngles th{};
    ASSERT_TRUE(falcon::inverseKinematics(fromLib({0.0, 0.0, 0.11}), th));
    for (double t : th)
        EXPECT_NEAR(t, 0.282533199, kAngleTol);
}

TEST(FalconReferenceTest, inverseKinematicsOffCentreMatchesLibnifalconArmByArm)
{
    // Off the z axis the three arms differ, so this pins the arm angles around z and the order of
    // the arms as well as the link lengths.
    JointAngles th{};
    ASSERT_TRUE(falcon::inverseKinematics(fromLib({0.02, 0.0, 0.12}), th));
    EXPECT_NEAR(th[0], 0.514268160, kAngleTol);
    EXPECT_NEAR(th[1], 0.221173629, kAngleTol);
    EXPECT_NEAR(th[2], 0.595672846, kAngleTol);
}

TEST(FalconReferenceTest, forwardKinematicsOfLibnifalconsAnglesGivesItsPosition)
{
    JointAngles th{0.514268160, 0.221173629, 0.595672846};
    Vec3 p{};
    ASSERT_TRUE(falcon::forwardKinematics(th, p).converged);
    const Vec3 want = fromLib({0.02, 0.0, 0.12});
    // 1e-7 rad on an arm moves the grip by at most about 0.02 µm.
    EXPECT_NEAR(p.x, want.x, 1e-6);
    EXPECT_NEAR(p.y, want.y, 1e-6);
    EXPECT_NEAR(p.z, want.z, 1e-6);
}

/// The motor commands the driver's force map gives for \a force at libnifalcon's position \a q.
falcon::MotorCommands commandsAt(const Vec3 &q, const Vec3 &force)
{
    const Vec3 p = fromLib(q);
    JointAngles th{};
    EXPECT_TRUE(falcon::inverseKinematics(p, th));
    Vec3 tau;
    EXPECT_TRUE(falcon::jointTorques(th, p, force, tau));
    falcon::MotorCommands cmd{};
    EXPECT_EQ(falcon::torquesToCommands(tau, cmd), 1.0);
    return cmd;
}

/// libnifalcon's getForces for a z force at the centre, corrected for its Jacobian: the z column of
/// its ∂theta/∂p has sin²(theta2) where the derivative of its inverse kinematics has
/// sin(theta2)·sin(theta3). At x = y = 0 every arm has the same angles, so the z row of
/// ∂p/∂theta, and with it every command for a z force, scales by sin(theta2)/sin(theta3).
/// theta2 and theta3 are libnifalcon's, at its reference theta1.
double libZCorrection(double theta1)
{
    const double u = -lib::r; // at x = y = 0: u = −r, v = −s in every arm's frame
    const double v = -lib::s;
    const double theta3 = std::acos((v + lib::f) / lib::b);
    const double reach = lib::d + lib::e + lib::b * std::sin(theta3);
    const double theta2 = std::acos((u + lib::c - lib::a * std::cos(theta1)) / reach);
    return std::sin(theta2) / std::sin(theta3);
}

TEST(FalconReferenceTest, forceAlongZAtTheCentreMatchesLibnifalconsCommandsCorrected)
{
    // GIVEN (0, 0, −1) N at libnifalcon's (0, 0, 0.11): libnifalcon commands 323 on each motor,
    // truncated from a value in [323, 324) that its Jacobian inflates by sin(theta3)/sin(theta2)
    const double k = libZCorrection(0.282533199);
    EXPECT_NEAR(k, 0.7464, 0.001); // the correction is large enough to matter: 323 → 241.8
    const falcon::MotorCommands cmd = commandsAt({0.0, 0.0, 0.11}, {0.0, 0.0, -1.0});
    // THEN each motor gets the same positive command (a push away from the user is a positive
    // command, as in libnifalcon), 323..324 times the correction, rounded
    for (std::int16_t m : cmd) {
        EXPECT_GE(m, 323.0 * k - 0.5);
        EXPECT_LE(m, 324.0 * k + 0.5);
    }
    EXPECT_EQ(cmd[0], cmd[1]);
    EXPECT_EQ(cmd[1], cmd[2]);
    // AND the opposite force gives the opposite commands
    const falcon::MotorCommands back = commandsAt({0.0, 0.0, 0.11}, {0.0, 0.0, 1.0});
    for (std::size_t i = 0; i < 3; ++i)
        EXPECT_EQ(back[i], -cmd[i]);
}

TEST(FalconReferenceTest, lateralForcesAtTheCentreMatchLibnifalcon)
{
    // At x = y = 0 libnifalcon's x and y rows of ∂p/∂theta are exact (they do not depend on the z
    // column), so its commands for lateral forces apply as they are.
    EXPECT_EQ(commandsAt({0.0, 0.0, 0.11}, {1.0, 0.0, 0.0}),
              (falcon::MotorCommands{-155, 527, -372})); // −154.877, 527.249, −372.372
    EXPECT_EQ(commandsAt({0.0, 0.0, 0.11}, {0.0, 1.0, 0.0}),
              (falcon::MotorCommands{519, -126, -394})); // 519.397, −125.571, −393.826
}

// --- The whole driver on a device that reports libnifalcon's encoder counts ---------------------

/// A Falcon with its firmware running and homed, holding fixed encoder counts; it answers each
/// command packet with one status packet and keeps the last motor commands. Packets are built and
/// read here byte by byte as libnifalcon's FalconFirmwareNovintSDK does ('<', 12 nibbles of three
/// little-endian 16-bit values as 'A' + nibble, 'A' + flags or status, 'A', '>').
class ReferenceFalcon final : public UsbTransport {
public:
    explicit ReferenceFalcon(const std::array<std::int16_t, 3> &encoders) : encoders_(encoders) {}
    Result<void> open(std::uint16_t, std::uint16_t) override
    {
        open_ = true;
        return ok();
    }
    void close() noexcept override { open_ = false; }
    bool present() const noexcept override { return open_; }
    Result<void> control(FtdiRequest, std::uint16_t) override { return ok(); }
    Result<std::size_t> write(const std::uint8_t *, std::size_t size, platform::Duration) override
    {
        return size;
    }
    Result<std::size_t> read(std::uint8_t *, std::size_t, platform::Duration) override
    {
        return std::size_t{0};
    }
    Result<std::size_t> exchange(const std::uint8_t *out, std::size_t outSize, std::uint8_t *in,
                                 std::size_t inCapacity, platform::Duration) noexcept override
    {
        if (outSize == 16 && out[0] == '<' && out[15] == '>')
            for (std::size_t i = 0; i < 3; ++i) {
                unsigned v = 0;
                for (std::size_t n = 0; n < 4; ++n)
                    v |= static_cast<unsigned>((out[1 + 4 * i + n] - 0x41) & 0x0f) << (4 * n);
                motors_[i] = static_cast<std::int16_t>(static_cast<std::uint16_t>(v));
            }
        if (inCapacity < 16)
            return unexpected(Errc::Io, "buffer too small");
        in[0] = '<';
        for (std::size_t i = 0; i < 3; ++i) {
            const auto v = static_cast<std::uint16_t>(encoders_[i]);
            for (std::size_t n = 0; n < 4; ++n)
                in[1 + 4 * i + n] = static_cast<std::uint8_t>(0x41 + ((v >> (4 * n)) & 0x0f));
        }
        in[13] = 0x41 + (0x07 << 4); // three motors homed, no button
        in[14] = 0x41;
        in[15] = '>';
        return std::size_t{16};
    }
    [[nodiscard]] const std::array<std::int16_t, 3> &motors() const { return motors_; }

private:
    std::array<std::int16_t, 3> encoders_;
    std::array<std::int16_t, 3> motors_{};
    bool open_ = false;
};

/// libnifalcon's encoder counts for arm angles \a theta, rounded to whole counts.
std::array<std::int16_t, 3> encodersFor(const std::array<double, 3> &theta)
{
    std::array<std::int16_t, 3> e{};
    for (std::size_t i = 0; i < 3; ++i)
        e[i] = static_cast<std::int16_t>(std::lround(lib::encoderFor(theta[i])));
    return e;
}

struct DriverOnReference {
    explicit DriverOnReference(const std::array<std::int16_t, 3> &encoders)
    {
        auto t = std::make_unique<ReferenceFalcon>(encoders);
        device = t.get();
        FalconSettings s;
        s.homingPackets = 1;
        driver = std::make_unique<FalconHapticDevice>(clock, std::move(t), s);
    }
    platform::ManualClock clock{platform::ManualClock::Mode::AutoAdvance};
    ReferenceFalcon *device = nullptr;
    std::unique_ptr<FalconHapticDevice> driver;
};

TEST(FalconReferenceTest, driverReportsLibnifalconsPositionForItsEncoderCounts)
{
    // GIVEN a device whose encoders read libnifalcon's angles for (0.02, 0, 0.12), in whole counts
    DriverOnReference rig(encodersFor({0.514268160, 0.221173629, 0.595672846}));
    ASSERT_TRUE(rig.driver->open());
    hal::HapticState st;
    ASSERT_TRUE(rig.driver->read(st));
    // THEN the driver reports that position in its frame, within the encoder resolution (half a
    // count on every arm moves the grip by less than 0.05 mm here)
    const Vec3 want = fromLib({0.02, 0.0, 0.12});
    EXPECT_NEAR(st.position.x, want.x, 0.05e-3);
    EXPECT_NEAR(st.position.y, want.y, 0.05e-3);
    EXPECT_NEAR(st.position.z, want.z, 0.05e-3);
}

TEST(FalconReferenceTest, driverSendsTheReferenceCommandsForAForceAtTheCentre)
{
    // GIVEN a device at libnifalcon's (0, 0, 0.11)
    DriverOnReference rig(encodersFor({0.282533199, 0.282533199, 0.282533199}));
    ASSERT_TRUE(rig.driver->open());
    hal::HapticState st;
    ASSERT_TRUE(rig.driver->read(st));
    // WHEN commanding 1 N away from the user, then 1 N to the right
    ASSERT_TRUE(rig.driver->commandForce({0.0, 0.0, -1.0}));
    ASSERT_TRUE(rig.driver->read(st));
    const std::array<std::int16_t, 3> z = rig.device->motors();
    ASSERT_TRUE(rig.driver->commandForce({1.0, 0.0, 0.0}));
    ASSERT_TRUE(rig.driver->read(st));
    const std::array<std::int16_t, 3> x = rig.device->motors();
    // THEN the packets carry libnifalcon's commands (z corrected as above; the encoder rounding
    // moves the pose by under 0.05 mm, which changes a command by under half a count)
    const double k = libZCorrection(0.282533199);
    for (std::int16_t m : z) {
        EXPECT_GE(m, 323.0 * k - 1.0);
        EXPECT_LE(m, 324.0 * k + 1.0);
    }
    EXPECT_NEAR(x[0], -154.877, 1.0);
    EXPECT_NEAR(x[1], 527.249, 1.0);
    EXPECT_NEAR(x[2], -372.372, 1.0);
}

} // namespace
} // namespace depthtouch::drivers
