#pragma once
/// \file
/// \brief Kinematics of the Novint Falcon, a delta-type parallel robot: encoder counts to motor-arm
/// angles, closed-form inverse kinematics, iterative forward kinematics, the Jacobian and the
/// force → motor-torque map through its transpose.
///
/// Model: R. E. Stamper's analysis of a three-arm parallel manipulator (PhD thesis 97-4, University
/// of Maryland), with the Falcon's dimensions, arm angles, encoder scale and motor command scale of
/// the libnifalcon project (FalconGeometry.h and FalconKinematicStamper.cpp of its current
/// release). Arm i (i = 0, 1, 2) sits at angle phi_i = 105°, −15°, −135° around the z axis (120°
/// apart, turned 15° from 90°, −30°, −150°: libnifalcon's "offset of each axis from the desk
/// plane"). In arm i's frame a point p of the base frame has coordinates
///   u = cos(phi_i)·x + sin(phi_i)·y − r,   v = −sin(phi_i)·x + cos(phi_i)·y − s,   w = z,
/// and the grip closes the chain when, with theta3 = acos((v + f)/b) (the parallelogram's tilt)
/// and L = d + e + b·sin(theta3) (its reach in the u-w plane),
///   g_i(theta_i, p) = (u + c − a·cos(theta_i))² + (w − a·sin(theta_i))² − L² = 0,
/// theta_i being the motor arm's angle (libnifalcon's theta1). a is the motor (upper) arm, b the
/// parallelogram (lower) arm.
///
/// Frames: the base frame is libnifalcon's kinematic frame: origin at the centre of the three motor
/// axes, x right, y up, z toward the user, metres. The device frame of hal::HapticDevice is the
/// base frame moved by kWorkspaceCentreZ along z (same axes), so the device-frame origin is the
/// workspace centre: device p is libnifalcon's (p.x, p.y, p.z + 0.110). Every function here takes
/// and returns device-frame positions. Angles in radians, torques in N·m at the arm joint, forces
/// in newtons.
///
/// Forces: tau = Jᵀ·F with J = ∂p/∂theta, the exact derivative of the closure equations.
/// libnifalcon computes tau the same way, but the z column of its ∂theta/∂p has sin²(theta2) where
/// the derivative of its own inverse kinematics has sin(theta2)·sin(theta3) (theta2, theta3 as in
/// its FalconKinematicStamper), so its forces with a z component differ from these (along z at the
/// workspace centre, libnifalcon's torques are 1.34 times these).
///
/// Thread-safety: pure functions, reentrant; real-time safe (no allocation, no lock, no exception).

#include <array>
#include <cstdint>

#include "depthtouch/hal/types.h"

namespace depthtouch::drivers::falcon {

/// \name Geometry (metres), libnifalcon's FalconGeometry (Stamper's notation)
///@{
inline constexpr double kArmA = 0.060;    ///< Motor (upper) arm length.
inline constexpr double kArmB = 0.1025;   ///< Parallelogram (lower) arm length.
inline constexpr double kArmC = 0.01443;  ///< Offset of the parallelogram along u.
inline constexpr double kArmD = 0.01125;  ///< Half-width of the parallelogram, elbow side.
inline constexpr double kArmE = 0.01125;  ///< Half-width of the parallelogram, grip side.
inline constexpr double kArmF = -0.025;   ///< Offset of the parallelogram along v.
inline constexpr double kArmS = -0.02309; ///< Offset of the motor axis along v.
inline constexpr double kArmR = 0.0400;   ///< Offset of the motor axis along u (from the centre).
inline constexpr double kPi = 3.14159265358979323846;
/// Turn of the arms from 90°, −30°, −150°, radians (15°).
inline constexpr double kArmOffset = kPi / 12.0;
/// Arm angles around z, radians (105°, −15°, −135°).
inline constexpr std::array<double, 3> kArmPhi = {kPi / 2.0 + kArmOffset, -kPi / 6.0 + kArmOffset,
                                                  -5.0 * kPi / 6.0 + kArmOffset};
///@}

/// \name Encoders and drive
///@{
inline constexpr int kEncoderSlots = 320;         ///< Slots on the encoder wheel (×4 quadrature).
inline constexpr double kShaftDiameter = 0.01425; ///< Motor capstan diameter, metres.
inline constexpr double kArmDrumDiameter = 0.110; ///< Arm drum diameter, metres.
/// Gear ratio of the cable drive: arm torque = kGearRatio × motor torque.
inline constexpr double kGearRatio = kArmDrumDiameter / kShaftDiameter;
/// Arm angle per encoder count, radians.
inline constexpr double kRadiansPerCount = 2.0 * kPi / (4.0 * kEncoderSlots) / kGearRatio;
/// Arm angle at encoder count 0 once homed, radians (35°).
inline constexpr double kThetaAtZeroCount = 35.0 * kPi / 180.0;
///@}

/// \name Workspace (device frame)
///@{
/// z of the workspace centre in the base frame, metres. Every point of a 90 mm cube centred here is
/// within the three arms' reach (the largest such cube, 91 mm, is centred 1 mm further out).
inline constexpr double kWorkspaceCentreZ = 0.110;
/// Half the edge of the cubic workspace reported in the capabilities, metres (an 80 mm cube, inside
/// the reachable one).
inline constexpr double kWorkspaceHalfExtent = 0.040;
///@}

/// \name Motor commands
///@{
/// Largest motor command magnitude the driver sends: the driver's bound (the firmware takes any
/// signed 16-bit value), 0.82 N·m at an arm joint. 8.5 N along any axis fits over the inner half of
/// the workspace (at most 6314 counts a motor; 4482 at the centre); toward the corners of the 80 mm
/// cube a force that does not fit is scaled down keeping its direction (torquesToCommands()).
inline constexpr int kMotorCommandLimit = 8192;
/// Motor command counts per N·m of arm-joint torque (libnifalcon's torque → command scale). A
/// positive joint torque is a negative command (the firmware's sign convention, as in libnifalcon):
/// a push along −z (away from the user) is a positive command on each motor.
inline constexpr double kCountsPerNewtonMetre = 10000.0;
///@}

using JointAngles = std::array<double, 3>; ///< Motor arm angles theta_i, radians.
using EncoderCounts = std::array<std::int16_t, 3>;
using MotorCommands = std::array<std::int16_t, 3>;

/// \brief A 3×3 matrix, row-major: m[row][col].
struct Mat3 {
    std::array<std::array<double, 3>, 3> m{};
    [[nodiscard]] hal::Vec3 operator*(const hal::Vec3 &v) const noexcept;
    [[nodiscard]] Mat3 transposed() const noexcept;
};

/// \return the arm angle of an encoder count, radians: kThetaAtZeroCount + count·kRadiansPerCount.
[[nodiscard]] double encoderToAngle(std::int16_t count) noexcept;
/// \return the encoder count nearest to arm angle \a theta (radians), saturated to int16.
[[nodiscard]] std::int16_t angleToEncoder(double theta) noexcept;

/// \brief Closed-form inverse kinematics: the motor arm angles that put the grip at \a p.
/// \param[in] p Device frame, metres.
/// \param[out] theta Radians; written only on success.
/// \return false when \a p is out of reach of an arm (theta untouched).
[[nodiscard]] bool inverseKinematics(const hal::Vec3 &p, JointAngles &theta) noexcept;

/// \brief Result of forwardKinematics().
struct ForwardResult {
    bool converged = false; ///< The step fell below the tolerance within the iteration limit.
    int iterations = 0;     ///< Newton iterations taken.
};

/// \brief Iterative forward kinematics: Newton's method on the three closure equations g_i = 0 in
/// the three unknowns of p, in double precision, warm-started from \a p (pass the previous
/// position; the workspace centre when there is none).
/// \param[in] theta Motor arm angles, radians.
/// \param[in,out] p In: the start point, device frame, metres. Out: the grip position.
/// \param[in] toleranceM Stop when a Newton step is shorter than this, metres.
/// \param[in] maxIterations Give up after this many steps (p is then the last iterate).
[[nodiscard]] ForwardResult forwardKinematics(const JointAngles &theta, hal::Vec3 &p,
                                              double toleranceM = 1e-10,
                                              int maxIterations = 20) noexcept;

/// \brief The Jacobian J = ∂p/∂theta at a consistent pose (theta, p), from implicit
/// differentiation of the closure equations: J = −(∂g/∂p)⁻¹·(∂g/∂theta).
/// \param[out] j Metres per radian; row = device axis x, y, z, column = arm.
/// \return false at a singular pose (j untouched).
[[nodiscard]] bool jacobian(const JointAngles &theta, const hal::Vec3 &p, Mat3 &j) noexcept;

/// \brief Arm-joint torques that output force \a force at the grip: tau = Jᵀ·F (virtual work).
/// \return N·m per arm; false at a singular pose.
[[nodiscard]] bool jointTorques(const JointAngles &theta, const hal::Vec3 &p,
                                const hal::Vec3 &force, hal::Vec3 &tau) noexcept;

/// \brief Motor commands for joint torques \a tau: −tau·kCountsPerNewtonMetre, rounded. When a
/// command would exceed kMotorCommandLimit all three are scaled down by the same factor, so the
/// output force keeps its direction.
/// \return the factor applied (1 when nothing was clamped, in (0, 1) otherwise).
double torquesToCommands(const hal::Vec3 &tau, MotorCommands &commands) noexcept;

/// \return the joint torques a motor command outputs, N·m (inverse of torquesToCommands() before
/// rounding).
[[nodiscard]] hal::Vec3 commandsToTorques(const MotorCommands &commands) noexcept;

} // namespace depthtouch::drivers::falcon
