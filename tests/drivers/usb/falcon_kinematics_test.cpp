// Kinematics of the Novint Falcon (drivers/usb/falcon_kinematics.h): IK/FK consistency over the
// workspace, the Jacobian against finite differences of FK, and the force → motor command map
// against values computed here by hand from the geometric constants.
#include "depthtouch/drivers/usb/falcon_kinematics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

namespace depthtouch::drivers::falcon {
namespace {

using hal::Vec3;

constexpr double kTolM = 0.05e-3; // 0.05 mm

/// Calls \a f for every point of an n×n×n grid spanning the capability cube (faces included).
template <class F> void forGrid(int n, F &&f)
{
    const double h = kWorkspaceHalfExtent;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) {
                const double s = 2.0 * h / (n - 1);
                f(Vec3{-h + i * s, -h + j * s, -h + k * s});
            }
}

TEST(FalconKinematicsTest, forwardOfInverseIsIdentityOverTheWorkspace)
{
    // GIVEN an 11×11×11 grid over the workspace cube
    double worstCold = 0.0;
    double worstWarm = 0.0;
    int maxItersCold = 0;
    int maxItersWarm = 0;
    long itersWarm = 0;
    int points = 0;
    forGrid(11, [&](const Vec3 &p) {
        JointAngles th{};
        ASSERT_TRUE(inverseKinematics(p, th)) << p.x << ' ' << p.y << ' ' << p.z;
        // WHEN solving FK from the workspace centre (cold) and from 1 mm away (warm, a servo step)
        Vec3 cold{};
        const ForwardResult rc = forwardKinematics(th, cold);
        Vec3 warm = p + Vec3{0.6e-3, -0.5e-3, 0.5e-3};
        const ForwardResult rw = forwardKinematics(th, warm);
        // THEN both converge to p within 0.05 mm
        ASSERT_TRUE(rc.converged);
        ASSERT_TRUE(rw.converged);
        worstCold = std::max(worstCold, hal::norm(cold - p));
        worstWarm = std::max(worstWarm, hal::norm(warm - p));
        maxItersCold = std::max(maxItersCold, rc.iterations);
        maxItersWarm = std::max(maxItersWarm, rw.iterations);
        itersWarm += rw.iterations;
        ++points;
    });
    EXPECT_LT(worstCold, kTolM);
    EXPECT_LT(worstWarm, kTolM);
    std::printf("FK(IK(p)) over %d points: worst error %.3g m (cold start, max %d iterations), "
                "%.3g m (warm start, max %d, mean %.2f iterations)\n",
                points, worstCold, maxItersCold, worstWarm, maxItersWarm,
                static_cast<double>(itersWarm) / points);
    RecordProperty("fk_max_iterations_warm", maxItersWarm);
}

TEST(FalconKinematicsTest, encoderQuantisationStaysBelowATenthOfAMillimetre)
{
    // GIVEN positions rounded through whole encoder counts  THEN FK lands within the resolution
    double worst = 0.0;
    forGrid(7, [&](const Vec3 &p) {
        JointAngles th{};
        ASSERT_TRUE(inverseKinematics(p, th));
        JointAngles q{};
        for (std::size_t i = 0; i < 3; ++i)
            q[i] = encoderToAngle(angleToEncoder(th[i]));
        Vec3 x{};
        ASSERT_TRUE(forwardKinematics(q, x).converged);
        worst = std::max(worst, hal::norm(x - p));
    });
    EXPECT_LT(worst, 0.1e-3);
    std::printf("Encoder quantisation: worst position error %.3g m\n", worst);
}

TEST(FalconKinematicsTest, encoderAngleRoundTrip)
{
    EXPECT_DOUBLE_EQ(encoderToAngle(0), kThetaAtZeroCount);
    for (int c : {-4000, -1, 0, 1, 1234, 4000})
        EXPECT_EQ(angleToEncoder(encoderToAngle(static_cast<std::int16_t>(c))), c);
    // 1280 counts per motor turn, geared down by the drum: one arm turn is 1280·110/14.25 counts.
    EXPECT_NEAR(encoderToAngle(1000) - encoderToAngle(0),
                1000.0 * 2.0 * kPi / 1280.0 * 14.25 / 110.0, 1e-12);
    EXPECT_EQ(angleToEncoder(1e9), 32767);
    EXPECT_EQ(angleToEncoder(-1e9), -32768);
    EXPECT_EQ(angleToEncoder(std::nan("")), -32768);
}

TEST(FalconKinematicsTest, unreachablePointsAreRefused)
{
    JointAngles th{1.0, 2.0, 3.0};
    EXPECT_FALSE(inverseKinematics({0.5, 0.0, 0.0}, th));
    EXPECT_FALSE(inverseKinematics({0.0, 0.0, 0.3}, th)); // beyond the arms' reach
    EXPECT_EQ(th[0], 1.0); // untouched
}

TEST(FalconKinematicsTest, jacobianMatchesFiniteDifferencesOfForwardKinematics)
{
    double worstRel = 0.0;
    forGrid(5, [&](const Vec3 &p) {
        JointAngles th{};
        ASSERT_TRUE(inverseKinematics(p, th));
        Mat3 j;
        ASSERT_TRUE(jacobian(th, p, j));
        constexpr double kStep = 1e-6; // radians
        for (std::size_t k = 0; k < 3; ++k) {
            JointAngles plus = th;
            JointAngles minus = th;
            plus[k] += kStep;
            minus[k] -= kStep;
            Vec3 pp = p;
            Vec3 pm = p;
            ASSERT_TRUE(forwardKinematics(plus, pp, 1e-14).converged);
            ASSERT_TRUE(forwardKinematics(minus, pm, 1e-14).converged);
            const Vec3 column = (pp - pm) * (1.0 / (2.0 * kStep));
            const Vec3 analytic{j.m[0][k], j.m[1][k], j.m[2][k]};
            worstRel = std::max(worstRel, hal::norm(column - analytic) / hal::norm(column));
        }
    });
    EXPECT_LT(worstRel, 1e-5);
}

// The home pose (device origin): the three arms are symmetric, so each is at the same angle.
// Everything below is computed from the geometric constants alone, without the driver's IK/FK.
struct HomeByHand {
    double theta = 0.0;   // arm angle
    double du = 0.0;      // u + c − a·cosθ
    double dw = 0.0;      // w − a·sinθ
    double reach = 0.0;   // L
    double cos3 = 0.0;    // (v + f)/b
    double dgdtheta = 0.0;
};

HomeByHand homeByHand()
{
    HomeByHand h;
    // At x = y = 0 every arm sees u = −r, v = −s, w = z0.
    const double u = -kArmR;
    const double v = -kArmS;
    const double w = kWorkspaceCentreZ;
    h.cos3 = (v + kArmF) / kArmB;
    h.reach = kArmD + kArmE + kArmB * std::sqrt(1.0 - h.cos3 * h.cos3);
    // Solve (u + c − a·cosθ)² + (w − a·sinθ)² = L² by bisection on [−π/2, π/2] (elbow out:
    // the residual grows with θ there).
    const auto residual = [&](double t) {
        const double x = u + kArmC - kArmA * std::cos(t);
        const double y = w - kArmA * std::sin(t);
        return x * x + y * y - h.reach * h.reach;
    };
    double lo = -kPi / 2.0;
    double hi = kPi / 2.0;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (residual(mid) > 0.0) == (residual(hi) > 0.0) ? hi = mid : lo = mid;
    }
    h.theta = 0.5 * (lo + hi);
    h.du = u + kArmC - kArmA * std::cos(h.theta);
    h.dw = w - kArmA * std::sin(h.theta);
    h.dgdtheta = 2.0 * kArmA * (h.du * std::sin(h.theta) - h.dw * std::cos(h.theta));
    return h;
}

TEST(FalconKinematicsTest, homePoseAnglesMatchTheHandSolution)
{
    const HomeByHand h = homeByHand();
    JointAngles th{};
    ASSERT_TRUE(inverseKinematics({}, th));
    for (double t : th)
        EXPECT_NEAR(t, h.theta, 1e-9);
}

TEST(FalconKinematicsTest, forceAlongZAtHomeMatchesVirtualWorkByHand)
{
    // GIVEN the home pose and a 3 N push along +z
    const HomeByHand h = homeByHand();
    // By symmetry the three arms share the load: each torque is Fz·∂z/∂θ_i, where moving one arm
    // alone moves z by dz = −(∂g_i/∂θ)/(∂g_i/∂z)·dθ restricted to the symmetric direction. With
    // all arms moving together (x = y = 0 stays), g(θ, z) gives dz/dθ = −(∂g/∂θ)/(∂g/∂z), and
    // virtual work Fz·dz = Σ τ_i·dθ = 3·τ·dθ gives τ = Fz·(dz/dθ)/3.
    const double dgdz = 2.0 * h.dw;
    const double dzdtheta = -h.dgdtheta / dgdz;
    const double fz = 3.0;
    const double tauByHand = fz * dzdtheta / 3.0;
    JointAngles th{};
    ASSERT_TRUE(inverseKinematics({}, th));
    Vec3 tau;
    ASSERT_TRUE(jointTorques(th, {}, {0.0, 0.0, fz}, tau));
    EXPECT_NEAR(tau.x, tauByHand, 1e-9);
    EXPECT_NEAR(tau.y, tauByHand, 1e-9);
    EXPECT_NEAR(tau.z, tauByHand, 1e-9);
    // AND the motor commands are −τ·counts-per-N·m, rounded
    MotorCommands cmd{};
    EXPECT_EQ(torquesToCommands(tau, cmd), 1.0);
    const auto expected =
        static_cast<std::int16_t>(std::lround(-tauByHand * kCountsPerNewtonMetre));
    EXPECT_EQ(cmd[0], expected);
    EXPECT_EQ(cmd[1], expected);
    EXPECT_EQ(cmd[2], expected);
    std::printf("Home pose: theta %.4f rad, 3 N along z -> %.5f N*m per arm, command %d\n", h.theta,
                tauByHand, expected);
}

TEST(FalconKinematicsTest, forceAlongXAtHomeMatchesTheJacobianTransposeByHand)
{
    // GIVEN the home pose and 2 N along +x. THEN τ = Jᵀ·F with J = −A⁻¹·B, A = ∂g/∂p, B =
    // diag(∂g_i/∂θ_i), i.e. τ = −B·A⁻ᵀ·F: solve Aᵀ·y = F by Cramer's rule, then τ_i = −B_i·y_i.
    const HomeByHand h = homeByHand();
    const double dgdu = 2.0 * h.du;
    const double sin3 = std::sqrt(1.0 - h.cos3 * h.cos3);
    const double dgdv = 2.0 * h.reach * h.cos3 / sin3;
    const double dgdw = 2.0 * h.dw;
    double a[3][3];
    for (int i = 0; i < 3; ++i) {
        const double c = std::cos(kArmPhi[static_cast<std::size_t>(i)]);
        const double s = std::sin(kArmPhi[static_cast<std::size_t>(i)]);
        a[i][0] = dgdu * c - dgdv * s;
        a[i][1] = dgdu * s + dgdv * c;
        a[i][2] = dgdw;
    }
    // at = Aᵀ
    double at[3][3];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            at[r][c] = a[c][r];
    const auto det = [](const double m[3][3]) {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
               m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    };
    const double f[3] = {2.0, 0.0, 0.0};
    const double d = det(at);
    double y[3];
    for (int k = 0; k < 3; ++k) {
        double m[3][3];
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
                m[r][c] = c == k ? f[r] : at[r][c];
        y[k] = det(m) / d;
    }
    JointAngles th{};
    ASSERT_TRUE(inverseKinematics({}, th));
    Vec3 tau;
    ASSERT_TRUE(jointTorques(th, {}, {2.0, 0.0, 0.0}, tau));
    EXPECT_NEAR(tau.x, -h.dgdtheta * y[0], 1e-9);
    EXPECT_NEAR(tau.y, -h.dgdtheta * y[1], 1e-9);
    EXPECT_NEAR(tau.z, -h.dgdtheta * y[2], 1e-9);
    // A sideways push loads the two lower arms (phi = −15°, −135°) in opposite directions, and
    // they carry most of it (the upper arm, at 105°, is 15° off vertical).
    EXPECT_LT(tau.y * tau.z, 0.0);
    EXPECT_GT(std::abs(tau.y), 2.0 * std::abs(tau.x));
    EXPECT_GT(std::abs(tau.z), 2.0 * std::abs(tau.x));
}

TEST(FalconKinematicsTest, maxForceFitsTheCommandRangeInTheInnerWorkspace)
{
    // The command scale leaves room for the full force in every axis direction over the inner
    // half of the workspace; in the corners a command may be scaled down (direction kept).
    double worstInner = 0.0;
    double worstAll = 0.0;
    forGrid(9, [&](const Vec3 &p) {
        JointAngles th{};
        ASSERT_TRUE(inverseKinematics(p, th));
        const bool inner = std::abs(p.x) <= kWorkspaceHalfExtent / 2 + 1e-12 &&
                           std::abs(p.y) <= kWorkspaceHalfExtent / 2 + 1e-12 &&
                           std::abs(p.z) <= kWorkspaceHalfExtent / 2 + 1e-12;
        for (const Vec3 &dir : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}, Vec3{-1, 0, 0},
                                Vec3{0, -1, 0}, Vec3{0, 0, -1}}) {
            Vec3 tau;
            ASSERT_TRUE(jointTorques(th, p, dir * 8.5, tau));
            const double m = std::max({std::abs(tau.x), std::abs(tau.y), std::abs(tau.z)}) *
                             kCountsPerNewtonMetre;
            worstAll = std::max(worstAll, m);
            if (inner)
                worstInner = std::max(worstInner, m);
        }
    });
    std::printf("8.5 N along an axis needs at most %.0f counts (inner half), %.0f (whole cube); "
                "limit %d\n",
                worstInner, worstAll, kMotorCommandLimit);
    EXPECT_LE(worstInner, kMotorCommandLimit);
}

TEST(FalconKinematicsTest, commandsAreScaledTogetherToFitTheRange)
{
    MotorCommands cmd{};
    const Vec3 tau{2.0, -1.0, 0.5}; // N·m: far beyond the range
    const double factor = torquesToCommands(tau, cmd);
    EXPECT_LT(factor, 1.0);
    EXPECT_EQ(cmd[0], -kMotorCommandLimit);
    EXPECT_NEAR(cmd[1], kMotorCommandLimit / 2.0, 1.0);
    EXPECT_NEAR(cmd[2], -kMotorCommandLimit / 4.0, 1.0);
    const Vec3 back = commandsToTorques(cmd);
    EXPECT_NEAR(back.x, tau.x * factor, 1e-3);
    // Non-finite torques give zero commands.
    EXPECT_EQ(torquesToCommands({std::nan(""), 0.0, 0.0}, cmd), 0.0);
    EXPECT_EQ(cmd, (MotorCommands{0, 0, 0}));
}

} // namespace
} // namespace depthtouch::drivers::falcon
