#include "depthtouch/haptics/collision.h"

#include <cmath>
#include <random>
#include <utility>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "app/haptics/crossing_agreement.h"
#include "app/haptics/synthetic.h"

namespace depthtouch::haptics {
namespace {

using test::countAgreement;
using test::CrossingAgreement;
using test::makeFrame;

constexpr SceneBox kBox{0.10, 0.04};

double bumpy(double x, double y)
{
    return 0.006 * std::sin(90.0 * x) * std::cos(70.0 * y) + 0.004 * std::sin(200.0 * x + 3.0 * y);
}

TEST(CollisionTest, verticalSegmentHitsAFlatPlaneAtItsHeight)
{
    // GIVEN a flat surface at z ≈ 1 mm
    const auto f = makeFrame(kBox, 9, 7, 0.0, [](double, double) { return 0.001; });
    HeightField hf(kBox);
    ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
    const double z = hf.vertexZ(0, 0);
    // WHEN a segment goes straight down through it
    const Crossing c = firstCrossing(hf, {0.013, -0.004, 0.010}, {0.013, -0.004, -0.010});
    // THEN it hits at the plane height, at the expected parameter
    ASSERT_TRUE(c.hit);
    EXPECT_NEAR(c.point.z, z, 1e-15);
    EXPECT_NEAR(c.t, (0.010 - z) / 0.020, 1e-12);
    EXPECT_NEAR(c.point.x, 0.013, 1e-15);
}

TEST(CollisionTest, segmentsAboveInsideOrOutsideDoNotCollide)
{
    const auto f = makeFrame(kBox, 9, 7, 0.0, [](double, double) { return 0.0; });
    HeightField hf(kBox);
    ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
    // above the surface
    EXPECT_FALSE(firstCrossing(hf, {-0.04, 0.02, 0.001}, {0.04, -0.02, 0.0005}).hit);
    // starting inside and going deeper (the proxy-graph failure of Fig. 5: no collision)
    EXPECT_FALSE(firstCrossing(hf, {0.0, 0.0, -0.001}, {0.01, 0.0, -0.005}).hit);
    // outside the box's x–y extent
    EXPECT_FALSE(firstCrossing(hf, {0.2, 0.0, 0.01}, {0.3, 0.0, -0.01}).hit);
    // leaving the surface upward is not a collision
    EXPECT_FALSE(firstCrossing(hf, {-0.02, 0.0, -0.001}, {0.02, 0.0, 0.001}).hit);
    // but the same segment the other way is, in the middle
    const Crossing c = firstCrossing(hf, {0.02, 0.0, 0.001}, {-0.02, 0.0, -0.001});
    ASSERT_TRUE(c.hit);
    EXPECT_NEAR(c.t, 0.5, 1e-3);
}

TEST(CollisionTest, cellsBelowTheSegmentAreSkipped)
{
    // GIVEN a long segment well above a bumpy surface
    const auto f = makeFrame(kBox, 41, 31, 0.0, bumpy);
    HeightField hf(kBox);
    ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
    const Crossing c = firstCrossing(hf, {-0.049, 0.03, 0.019}, {0.049, -0.03, 0.018});
    // THEN it walks every cell it crosses but tests no triangle
    EXPECT_FALSE(c.hit);
    EXPECT_GT(c.cellsVisited, 40);
    EXPECT_EQ(c.cellsTested, 0);
}

TEST(CollisionTest, toleranceScalesWithThePixelSpacing)
{
    // GIVEN a 720-sample-wide frame: 0.14 mm triangles
    const auto f = makeFrame(kBox, 720, 8, 0.0, bumpy);
    HeightField hf(kBox);
    ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
    const glm::dvec3 v = hf.vertex(333, 4);
    // WHEN a vertical segment from 10 nm above a vertex ends 10 nm below it
    const Crossing c =
        firstCrossing(hf, v + glm::dvec3(0.0, 0.0, 1e-8), v + glm::dvec3(0, 0, -1e-8));
    // THEN the crossing is found, on the surface
    ASSERT_TRUE(c.hit);
    EXPECT_NEAR(c.point.z, v.z, 1e-15);
    EXPECT_NEAR(c.t, 0.5, 1e-6);
    // AND one that stays 10 nm above a sloped stretch does not collide
    const glm::dvec3 w = hf.vertex(334, 4);
    EXPECT_FALSE(firstCrossing(hf, v + glm::dvec3(0, 0, 1e-8), w + glm::dvec3(0, 0, 1e-8)).hit);
}

TEST(CollisionTest, agreesWithBruteForceOnRandomSegments)
{
    // GIVEN a bumpy 16-bit surface and the brute-force reference
    const auto f = makeFrame(kBox, 33, 25, 0.0, bumpy);
    HeightField hf(kBox);
    ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
    std::uniform_real_distribution<double> ux(-0.05, 0.05);
    std::uniform_real_distribution<double> uy(-0.037, 0.037);
    std::uniform_real_distribution<double> uz(-0.012, 0.012);
    std::uniform_real_distribution<double> step(-0.006, 0.006);
    const auto segment = [&](int i, std::mt19937_64 &rng) {
        const glm::dvec3 a(ux(rng), uy(rng), uz(rng));
        const glm::dvec3 b = (i % 2) ? glm::dvec3(ux(rng), uy(rng), uz(rng))
                                     : a + glm::dvec3(step(rng), step(rng), step(rng));
        return std::pair{a, b};
    };
    const CrossingAgreement n = countAgreement(
        7, 4000, segment, [&](auto a, auto b) { return firstCrossing(hf, a, b); },
        [&](auto a, auto b) { return firstCrossingBruteForce(hf, a, b); },
        [](const Crossing &fast, const Crossing &ref, glm::dvec3 a, glm::dvec3 b) {
            const bool same = fast.hit == ref.hit &&
                              (!fast.hit || std::fabs(fast.t - ref.t) * glm::length(b - a) < 1e-9);
            return !same;
        });
    // THEN both find the same first crossing (and the test does exercise hits)
    EXPECT_EQ(n.mismatches, 0);
    EXPECT_GT(n.hits, 1000);
}

} // namespace
} // namespace depthtouch::haptics
