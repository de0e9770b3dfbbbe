#include "depthtouch/drivers/usb/falcon_kinematics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>

namespace depthtouch::drivers::falcon {

namespace {

/// One arm's closure equation and its derivatives at (theta, p): value g, ∂g/∂p (device axes) and
/// ∂g/∂theta. See the file comment of falcon_kinematics.h for g.
struct ArmClosure {
    double g = 0.0;
    hal::Vec3 dgdp;
    double dgdtheta = 0.0;
};

/// \return false when the parallelogram cannot reach v (|v + f| ≥ b).
bool armClosure(int arm, double theta, const hal::Vec3 &p, ArmClosure &out) noexcept
{
    const double cphi = std::cos(kArmPhi[static_cast<std::size_t>(arm)]);
    const double sphi = std::sin(kArmPhi[static_cast<std::size_t>(arm)]);
    const double z = p.z + kWorkspaceCentreZ;
    const double u = cphi * p.x + sphi * p.y - kArmR;
    const double v = -sphi * p.x + cphi * p.y - kArmS;
    const double w = z;
    const double cos3 = (v + kArmF) / kArmB;
    if (!(std::abs(cos3) < 1.0))
        return false;
    const double sin3 = std::sqrt(1.0 - cos3 * cos3);
    const double reach = kArmD + kArmE + kArmB * sin3;
    const double du = u + kArmC - kArmA * std::cos(theta);
    const double dw = w - kArmA * std::sin(theta);
    out.g = du * du + dw * dw - reach * reach;
    // d(reach)/dv = b·d(sin3)/dv = −cos3/sin3.
    const double dgdu = 2.0 * du;
    const double dgdv = 2.0 * reach * cos3 / sin3;
    const double dgdw = 2.0 * dw;
    out.dgdp = {dgdu * cphi - dgdv * sphi, dgdu * sphi + dgdv * cphi, dgdw};
    out.dgdtheta = 2.0 * kArmA * (du * std::sin(theta) - dw * std::cos(theta));
    return true;
}

glm::dmat3 toGlm(const Mat3 &a) noexcept
{
    glm::dmat3 g;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            g[c][r] = a.m[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
    return g;
}

Mat3 fromGlm(const glm::dmat3 &g) noexcept
{
    Mat3 a;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            a.m[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)] = g[c][r];
    return a;
}

/// ∂g/∂p (rows = arms) and ∂g/∂theta at (theta, p). \return false when an arm is out of reach.
bool closureDerivatives(const JointAngles &theta, const hal::Vec3 &p, Mat3 &dgdp,
                        hal::Vec3 &g, hal::Vec3 &dgdtheta) noexcept
{
    double gv[3];
    double dt[3];
    for (int i = 0; i < 3; ++i) {
        ArmClosure c;
        if (!armClosure(i, theta[static_cast<std::size_t>(i)], p, c))
            return false;
        auto &row = dgdp.m[static_cast<std::size_t>(i)];
        row = {c.dgdp.x, c.dgdp.y, c.dgdp.z};
        gv[i] = c.g;
        dt[i] = c.dgdtheta;
    }
    g = {gv[0], gv[1], gv[2]};
    dgdtheta = {dt[0], dt[1], dt[2]};
    return true;
}

constexpr double kSingularDeterminant = 1e-18;

} // namespace

hal::Vec3 Mat3::operator*(const hal::Vec3 &v) const noexcept
{
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

Mat3 Mat3::transposed() const noexcept
{
    Mat3 t;
    for (std::size_t r = 0; r < 3; ++r)
        for (std::size_t c = 0; c < 3; ++c)
            t.m[c][r] = m[r][c];
    return t;
}

double encoderToAngle(std::int16_t count) noexcept
{
    return kThetaAtZeroCount + static_cast<double>(count) * kRadiansPerCount;
}

std::int16_t angleToEncoder(double theta) noexcept
{
    const double counts = std::round((theta - kThetaAtZeroCount) / kRadiansPerCount);
    constexpr double kLo = std::numeric_limits<std::int16_t>::min();
    constexpr double kHi = std::numeric_limits<std::int16_t>::max();
    if (!(counts >= kLo))
        return std::numeric_limits<std::int16_t>::min();
    return static_cast<std::int16_t>(std::min(counts, kHi));
}

bool inverseKinematics(const hal::Vec3 &p, JointAngles &theta) noexcept
{
    JointAngles out{};
    for (std::size_t i = 0; i < 3; ++i) {
        const double cphi = std::cos(kArmPhi[i]);
        const double sphi = std::sin(kArmPhi[i]);
        const double u = cphi * p.x + sphi * p.y - kArmR;
        const double v = -sphi * p.x + cphi * p.y - kArmS;
        const double w = p.z + kWorkspaceCentreZ;
        const double cos3 = (v + kArmF) / kArmB;
        if (!(std::abs(cos3) < 1.0))
            return false;
        const double reach = kArmD + kArmE + kArmB * std::sqrt(1.0 - cos3 * cos3);
        // (u + c − a·cosθ)² + (w − a·sinθ)² = reach² is k − 2a(u + c)·cosθ − 2a·w·sinθ = 0; with
        // t = tan(θ/2) it becomes q2·t² + q1·t + q0 = 0. The root taken is the elbow-out branch.
        const double uc = u + kArmC;
        const double k = uc * uc + w * w + kArmA * kArmA - reach * reach;
        const double q2 = k + 2.0 * kArmA * uc;
        const double q1 = -4.0 * kArmA * w;
        const double q0 = k - 2.0 * kArmA * uc;
        const double disc = q1 * q1 - 4.0 * q2 * q0;
        if (!(disc >= 0.0) || q2 == 0.0)
            return false;
        out[i] = 2.0 * std::atan((-q1 - std::sqrt(disc)) / (2.0 * q2));
    }
    theta = out;
    return true;
}

ForwardResult forwardKinematics(const JointAngles &theta, hal::Vec3 &p, double toleranceM,
                                int maxIterations) noexcept
{
    ForwardResult r;
    hal::Vec3 x = p;
    for (r.iterations = 1; r.iterations <= maxIterations; ++r.iterations) {
        Mat3 a;
        hal::Vec3 g;
        hal::Vec3 dgdtheta;
        if (!closureDerivatives(theta, x, a, g, dgdtheta)) {
            // Left the parallelogram's reach: fall back toward the centre and retry.
            x = x * 0.5;
            continue;
        }
        const glm::dmat3 ag = toGlm(a);
        if (std::abs(glm::determinant(ag)) < kSingularDeterminant)
            break;
        const glm::dvec3 step = glm::inverse(ag) * glm::dvec3(g.x, g.y, g.z);
        x -= hal::Vec3{step.x, step.y, step.z};
        if (glm::length(step) < toleranceM) {
            r.converged = hal::isFinite(x);
            break;
        }
    }
    r.iterations = std::min(r.iterations, maxIterations);
    p = x;
    return r;
}

bool jacobian(const JointAngles &theta, const hal::Vec3 &p, Mat3 &j) noexcept
{
    Mat3 a;
    hal::Vec3 g;
    hal::Vec3 dgdtheta;
    if (!closureDerivatives(theta, p, a, g, dgdtheta))
        return false;
    const glm::dmat3 ag = toGlm(a);
    if (std::abs(glm::determinant(ag)) < kSingularDeterminant)
        return false;
    glm::dmat3 b(0.0);
    b[0][0] = -dgdtheta.x;
    b[1][1] = -dgdtheta.y;
    b[2][2] = -dgdtheta.z;
    j = fromGlm(glm::inverse(ag) * b);
    return true;
}

bool jointTorques(const JointAngles &theta, const hal::Vec3 &p, const hal::Vec3 &force,
                  hal::Vec3 &tau) noexcept
{
    Mat3 j;
    if (!jacobian(theta, p, j))
        return false;
    tau = j.transposed() * force;
    return true;
}

double torquesToCommands(const hal::Vec3 &tau, MotorCommands &commands) noexcept
{
    const double raw[3] = {-tau.x * kCountsPerNewtonMetre, -tau.y * kCountsPerNewtonMetre,
                           -tau.z * kCountsPerNewtonMetre};
    const double largest = std::max({std::abs(raw[0]), std::abs(raw[1]), std::abs(raw[2])});
    double factor = 1.0;
    if (!(largest <= kMotorCommandLimit))
        factor = std::isfinite(largest) ? kMotorCommandLimit / largest : 0.0;
    for (std::size_t i = 0; i < 3; ++i) {
        const double c = std::round(raw[i] * factor);
        commands[i] = static_cast<std::int16_t>(
            std::clamp(std::isfinite(c) ? c : 0.0, -double{kMotorCommandLimit},
                       double{kMotorCommandLimit}));
    }
    return factor;
}

hal::Vec3 commandsToTorques(const MotorCommands &commands) noexcept
{
    return {-commands[0] / kCountsPerNewtonMetre, -commands[1] / kCountsPerNewtonMetre,
            -commands[2] / kCountsPerNewtonMetre};
}

} // namespace depthtouch::drivers::falcon
