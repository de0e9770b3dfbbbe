/// \file
/// \brief The ideal fingertip (ball_ideal.h): where a ball of the fingertip's radius rests on a
/// height field and the force of its god-object, against the geometry worked out by hand: a
/// table, a step's edge, keys whose gaps are narrower than the ball, holes.

#include <cmath>
#include <cstdio>
#include <functional>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "app/haptics/synthetic.h"
#include "depthtouch/haptics/ball_ideal.h"
#include "depthtouch/haptics/feel.h"

namespace depthtouch::haptics::bench {
namespace {

using test::OwnedFrame;

constexpr SceneBox kBox{};
constexpr int kW = 640; ///< As the feel bench's scenes: the grid spacing is 0.156 mm.
constexpr int kH = 480;
constexpr double kTable = -0.005;   ///< m
constexpr double kR = 0.0015;       ///< The default fingertip radius in the default box, m.
constexpr double kK = 800.0;        ///< N/m, the default stiffness.
constexpr double kQuantum = 1.2e-6; ///< A 16-bit sample's step over the 0.04 m box, m (rounded).

/// The spacing of a kW-wide grid over kBox, m.
double spacing()
{
    return kBox.width / (kW - 1);
}

/// A 16-bit still frame of \a z, and a field over it.
struct Field {
    OwnedFrame frame;
    HeightField field{kBox};
    explicit Field(const std::function<double(double, double)> &z)
        : frame(test::makeFrame(kBox, kW, kH, 0.0, z))
    {
        EXPECT_TRUE(field.setFrames(frame.view(), nullptr));
    }
};

// On a flat table the ball rests on it; pressed 2 mm in, its force is the point's: k·2 mm straight
// up, as the point's god-object (nearestSurface(), feel.h) gives.
TEST(BallIdealTest, onAFlatTableTheBallIsThePoint)
{
    const Field f([](double, double) { return kTable; });
    EXPECT_NEAR(ballRestHeight(f.field, 0.001, -0.002, kR), kTable, kQuantum);
    const glm::dvec3 hip{0.001, -0.002, kTable - 0.002};
    const glm::dvec3 ball = ballIdealPenalty(f.field, hip, kR, kK);
    glm::dvec3 nearest{};
    nearestSurface([&f](double x, double y) { return f.field.heightAt(x, y); }, hip, 0.002,
                   &nearest);
    const glm::dvec3 point = kK * (nearest - hip);
    EXPECT_NEAR(ball.z, kK * 0.002, kK * kQuantum);
    EXPECT_NEAR(glm::length(ball - point), 0.0, kK * kQuantum);
    EXPECT_NEAR(std::hypot(ball.x, ball.y), 0.0, 1e-9);
    // Above the table: no force.
    EXPECT_EQ(glm::length(ballIdealPenalty(f.field, hip + glm::dvec3(0, 0, 0.0021), kR, kK)), 0.0);
}

// Beside a step 1 mm tall (under r) the ball's lowest point a distance d from the top's edge
// rests on that edge at H − (r − √(r² − d²)) (the sphere's cap), and on the floor once d ≥ r
// would put it lower. The edge is a column of vertices; the point lies on a vertex row, so d is
// measured to a vertex.
TEST(BallIdealTest, besideALowStepTheBallRestsOnItsEdgeByItsCap)
{
    const double s = spacing();
    const double edge = test::sampleX(kBox, kW, 300); // the step's last column of vertices
    const double step = 0.001;
    const Field f([&](double x, double) { return x <= edge + 0.5 * s ? kTable + step : kTable; });
    const double y = test::sampleY(kBox, kW, kH, 200);
    for (const double d : {0.0, 0.25 * kR, 0.5 * kR, 0.75 * kR}) {
        const double x = edge + std::round(d / s) * s; // on the floor side, on a vertex
        const double dv = x - edge;
        const double expected = std::max(kTable, kTable + step + std::sqrt(kR * kR - dv * dv) - kR);
        EXPECT_NEAR(ballRestHeight(f.field, x, y, kR), expected, 2 * kQuantum) << "d " << dv;
    }
    // Farther than r from the edge the floor holds the ball.
    EXPECT_NEAR(ballRestHeight(f.field, edge + 1.2 * kR, y, kR), kTable, kQuantum);
}

// Inside a step 10 mm tall, 8 mm under its top, the ball's way out is sideways past the edge by
// r (where it clears the edge's corner): 1 mm from the edge that is 2.5 mm, inside the search's
// 2r, and the force is sideways at k·2.5 mm; 2 mm from it, 3.5 mm, beyond 2r: straight up at
// k·8 mm (ball_ideal.h).
TEST(BallIdealTest, insideATallStepTheWayOutIsSidewaysWithinTwoRadii)
{
    const double s = spacing();
    const double edge = test::sampleX(kBox, kW, 300);
    const double top = kTable + 0.010;
    const Field f([&](double x, double) { return x <= edge + 0.5 * s ? top : kTable; });
    const double y = test::sampleY(kBox, kW, kH, 200);
    const glm::dvec3 near{edge - 0.001, y, top - 0.008};
    const glm::dvec3 sideways = ballIdealPenalty(f.field, near, kR, kK);
    EXPECT_NEAR(sideways.x, kK * (0.001 + kR), kK * 0.1e-3);
    EXPECT_NEAR(sideways.z, 0.0, kK * 0.1e-3);
    const glm::dvec3 far{edge - 0.002, y, top - 0.008};
    const glm::dvec3 up = ballIdealPenalty(f.field, far, kR, kK);
    EXPECT_NEAR(up.z, kK * 0.008, kK * kQuantum);
    EXPECT_NEAR(std::hypot(up.x, up.y), 0.0, 1e-9);
}

// Keys whose gaps are one sample wide and 3.6 mm deep (a keyboard seen at 640 × 480): a ball of
// radius r sags over a gap by the cap over one sample (8 µm), so pressed 2 mm under the tops it
// is pushed straight up at k·(2 mm − sag), over a gap as over a key. A point there is in free
// space (no force), and one sample on, inside the key, its nearest surface is the gap's side: it
// is pushed sideways, and far less.
TEST(BallIdealTest, keysWithGapsNarrowerThanTheBallHoldItUp)
{
    const double s = spacing();
    const double top = kTable;
    const double pitch = 9 * s; // 1.4 mm, as the bench's keyboard
    const auto keys = [&](double x, double) {
        const double phase = std::fmod(x + 10.0 * pitch, pitch);
        return phase < s ? top - 0.0036 : top; // one vertex column in each pitch
    };
    const Field f(keys);
    // A gap's column: the one vertex column whose phase falls in the gap.
    double gap = 0.0;
    for (int c = 300; c < 320; ++c)
        if (keys(test::sampleX(kBox, kW, c), 0.0) < top - 0.001) {
            gap = test::sampleX(kBox, kW, c);
            break;
        }
    ASSERT_NE(gap, 0.0);
    const double y = test::sampleY(kBox, kW, kH, 200);
    const glm::dvec3 hip{gap, y, top - 0.002};
    const double rest = ballRestHeight(f.field, hip.x, hip.y, kR);
    const double sag = kR - std::sqrt(kR * kR - s * s); // held on the next vertices either side
    std::printf("ball over the gap: %.1f um under the tops (sag by hand %.1f um)\n",
                (top - rest) * 1e6, sag * 1e6);
    EXPECT_NEAR(rest, top - sag, kQuantum);
    const glm::dvec3 ball = ballIdealPenalty(f.field, hip, kR, kK);
    EXPECT_NEAR(ball.z, kK * (0.002 - sag), 0.02);
    EXPECT_LT(std::hypot(ball.x, ball.y), 0.05 * ball.z);
    EXPECT_LT(f.field.heightAt(hip.x, hip.y), hip.z); // the point is free over the gap
    const glm::dvec3 onKey = hip + glm::dvec3(s, 0.0, 0.0);
    const glm::dvec3 ballOnKey = ballIdealPenalty(f.field, onKey, kR, kK);
    EXPECT_NEAR(ballOnKey.z, kK * 0.002, 0.02);
    glm::dvec3 nearest{};
    nearestSurface([&f](double x, double yy) { return f.field.heightAt(x, yy); }, onKey,
                   f.field.heightAt(onKey.x, onKey.y) - onKey.z, &nearest);
    const glm::dvec3 point = kK * (nearest - onKey);
    std::printf("on the key one sample on: the point's force (%.2f, %.2f, %.2f) N, the ball's "
                "(%.2f, %.2f, %.2f) N\n",
                point.x, point.y, point.z, ballOnKey.x, ballOnKey.y, ballOnKey.z);
    EXPECT_GT(std::hypot(point.x, point.y), 2.0 * std::fabs(point.z));
    EXPECT_LT(glm::length(point), 0.25 * glm::length(ballOnKey));
}

// A hole is nothing measured: it holds no ball up (a hole's vertices lie 1 m under the box, and
// their cliff is no support), and where everything within r is a hole there is no rest height.
TEST(BallIdealTest, holesHoldNoBallUp)
{
    const double s = spacing();
    Field f([](double, double) { return kTable; });
    // Samples of the table's left half under 1 are holes; the rest is a table 1 mm higher.
    f.frame.setHoleBelow(1);
    for (int r = 0; r < kH; ++r)
        for (int c = 0; c < kW; ++c)
            f.frame.set(
                c, r, c < 320 ? 0u : test::toNearness(kBox, SampleFormat::Gray16, kTable + 0.001));
    ASSERT_TRUE(f.field.setFrames(f.frame.view(), nullptr));
    const double y = test::sampleY(kBox, kW, kH, 200);
    const double firstMeasured = test::sampleX(kBox, kW, 320);
    EXPECT_TRUE(std::isnan(ballRestHeight(f.field, firstMeasured - 2.0 * kR, y, kR)));
    // Half a radius into the hole, the measured edge holds it by its cap only.
    const double x = firstMeasured - std::round(0.5 * kR / s) * s;
    const double d = firstMeasured - x;
    EXPECT_NEAR(ballRestHeight(f.field, x, y, kR), kTable + 0.001 + std::sqrt(kR * kR - d * d) - kR,
                2 * kQuantum);
    EXPECT_EQ(glm::length(ballIdealPenalty(f.field, {firstMeasured - 2.0 * kR, y, -0.019}, kR, kK)),
              0.0);
}

} // namespace
} // namespace depthtouch::haptics::bench
