/// \file
/// \brief The feel figures (feel.h) on hand-made rows, the Kinect-style sensor model
/// (depth_noise.h) and the feel bench's scenes and strokes (feel_scenes.h).

#include "depthtouch/haptics/feel.h"

#include <cmath>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "depthtouch/haptics/depth_noise.h"
#include "depthtouch/haptics/feel_scenes.h"

namespace depthtouch::haptics {
namespace {

/// \a n rows 1 ms apart, HIP 2 mm under a surface at z = 0, force 1 N up: a clean press.
std::vector<FeelSample> pressRows(std::size_t n)
{
    std::vector<FeelSample> rows(n);
    for (std::size_t i = 0; i < n; ++i) {
        rows[i].t = 1e-3 * static_cast<double>(i);
        rows[i].hip = {0.0, 0.0, -2e-3};
        rows[i].force = {0.0, 0.0, 1.0};
        rows[i].surfaceZ = 0.0;
    }
    return rows;
}

TEST(FeelTest, CleanPressHasNoFault)
{
    const FeelFigures f = computeFeel(pressRows(100));
    EXPECT_EQ(f.updates, 100u);
    EXPECT_NEAR(f.seconds, 0.1, 1e-12); // 99 steps + the median step for the last row
    EXPECT_EQ(f.trips, 0u);
    EXPECT_EQ(f.popThroughMs, 0.0);
    EXPECT_EQ(f.phantomMs, 0.0);
    EXPECT_EQ(f.spikes, 0u);
    EXPECT_DOUBLE_EQ(f.maxForce, 1.0);
}

TEST(FeelTest, TripsSplitIntoRealCutsAndFalse)
{
    auto rows = pressRows(100);
    for (auto &r : rows)
        r.sliding = true;
    rows[10].released = true;
    rows[20].released = true;
    rows[20].surfaceCut = true;
    rows[30].released = true;
    const FeelFigures f = computeFeel(rows);
    EXPECT_EQ(f.trips, 3u);
    EXPECT_EQ(f.realCutTrips, 1u);
    EXPECT_EQ(f.falseTrips, 2u);
    EXPECT_NEAR(f.falseTripsPerSecond, 2.0 / 0.1, 1e-9);
}

TEST(FeelTest, PopThroughCountsOnlyAfterFirstContact)
{
    auto rows = pressRows(100);
    for (std::size_t i = 0; i < 10; ++i)
        rows[i].force = {}; // inside but no force before any contact: not a pop-through
    for (std::size_t i = 50; i < 60; ++i)
        rows[i].force = {0.0, 0.0, 0.05}; // after contact, 2 mm in, 0.05 N: pop-through
    rows[70].hip.z = -0.5e-3;              // within the margin: not counted
    rows[70].force = {};
    const FeelFigures f = computeFeel(rows);
    EXPECT_NEAR(f.popThroughMs, 10.0, 1e-9);
}

TEST(FeelTest, PhantomForceAboveOrOffTheSurface)
{
    auto rows = pressRows(100);
    for (std::size_t i = 0; i < 5; ++i)
        rows[i].hip.z = 2e-3; // 2 mm above with 1 N: phantom
    rows[5].surfaceZ = std::nan("");
    rows[6].hip.z = 0.5e-3; // within the margin
    rows[7].hip.z = 2e-3;
    rows[7].force = {0.0, 0.0, 0.15}; // under the phantom force threshold
    const FeelFigures f = computeFeel(rows);
    EXPECT_NEAR(f.phantomMs, 6.0, 1e-9);
}

TEST(FeelTest, SpikesOnlyWhileSliding)
{
    auto rows = pressRows(100);
    for (std::size_t i = 40; i < 60; ++i)
        rows[i].sliding = true;
    rows[45].force = {0.0, 0.6, 1.0}; // |ΔF| = 0.6 in and 0.6 out: two spikes while sliding
    rows[80].force = {0.0, 0.0, 3.0}; // a step, but not sliding
    rows[0].sliding = true;            // the first row steps from zero: 1 N is a spike
    const FeelFigures f = computeFeel(rows);
    EXPECT_EQ(f.spikes, 3u);
    EXPECT_NEAR(f.slidingSeconds, 0.021, 1e-9);
    EXPECT_DOUBLE_EQ(f.maxForce, 3.0);
}

TEST(FeelTest, RippleWhileHeld)
{
    auto rows = pressRows(100);
    for (std::size_t i = 0; i < 100; ++i) {
        rows[i].held = i >= 50;
        rows[i].force = {0.0, 0.0, i >= 50 ? (i % 2 ? 1.1 : 0.9) : 5.0};
    }
    const FeelFigures f = computeFeel(rows);
    EXPECT_NEAR(f.rippleRms, 0.1, 1e-9);
    EXPECT_NEAR(f.rippleRelative, 0.1, 1e-9);
}

TEST(FeelTest, UpdatePercentilesAndAccumulate)
{
    auto rows = pressRows(1000);
    for (std::size_t i = 0; i < rows.size(); ++i)
        rows[i].updateSeconds = i == 999 ? 50e-6 : 1e-6;
    const FeelFigures f = computeFeel(rows);
    EXPECT_DOUBLE_EQ(f.updateP50, 1e-6);
    EXPECT_DOUBLE_EQ(f.updateP999, 1e-6); // nearest rank 999 of 1000
    FeelFigures total;
    accumulate(total, f);
    accumulate(total, f);
    EXPECT_EQ(total.updates, 2000u);
    EXPECT_NEAR(total.seconds, 2.0, 1e-9);
    EXPECT_DOUBLE_EQ(total.updateP999, f.updateP999);
}

// --- Sensor model --------------------------------------------------------------------------------

depth::Plane<float> flat(double z, int w = 64, int h = 48)
{
    return depth::Plane<float>(w, h, static_cast<float>(z));
}

TEST(DepthNoiseTest, QuantisationStepGrowsWithZSquared)
{
    bench::KinectNoiseOptions o;
    for (double z : {1.0, 2.0, 3.0}) {
        // Two neighbouring representable depths differ by about 2.85e-3·z².
        const double a = bench::quantiseDisparity(z, o.disparityStep);
        const double b = bench::quantiseDisparity(a * (1.0 + 2.85e-3 * z), o.disparityStep);
        EXPECT_NEAR(b - a, 2.85e-3 * z * z, 0.1 * 2.85e-3 * z * z) << z;
    }
}

TEST(DepthNoiseTest, FlickerIsNonzeroAndScalesWithZSquared)
{
    bench::KinectNoiseOptions o;
    o.speckleProbability = 0.0;
    const auto spread = [&](double z) {
        const auto a = bench::applyKinectNoise(flat(z), o, 0);
        double s = 0.0;
        double s2 = 0.0;
        for (auto v : a.samples) {
            s += v;
            s2 += static_cast<double>(v) * v;
        }
        const double n = static_cast<double>(a.size());
        return std::sqrt(s2 / n - (s / n) * (s / n)) * 1e-3; // m
    };
    const double s1 = spread(1.0);
    const double s2 = spread(2.0);
    EXPECT_GT(s1, 0.5e-3);
    EXPECT_NEAR(s2 / s1, 4.0, 1.2);
    // Frame to frame the same pixel changes.
    const auto f0 = bench::applyKinectNoise(flat(2.0), o, 0);
    const auto f1 = bench::applyKinectNoise(flat(2.0), o, 1);
    EXPECT_NE(f0.samples, f1.samples);
}

TEST(DepthNoiseTest, DeterministicPerSeed)
{
    bench::KinectNoiseOptions o;
    auto z = flat(1.5);
    for (int y = 0; y < z.height; ++y)
        for (int x = 30; x < z.width; ++x)
            z.at(x, y) = 1.0f;
    const auto a = bench::applyKinectNoise(z, o, 3);
    const auto b = bench::applyKinectNoise(z, o, 3);
    EXPECT_EQ(a.samples, b.samples);
    o.seed = 2;
    const auto c = bench::applyKinectNoise(z, o, 3);
    EXPECT_NE(a.samples, c.samples);
}

TEST(DepthNoiseTest, HolesSitAtSilhouettes)
{
    bench::KinectNoiseOptions o;
    o.speckleProbability = 0.0;
    auto z = flat(2.0, 128, 64);
    for (int y = 0; y < z.height; ++y)
        for (int x = 64; x < z.width; ++x)
            z.at(x, y) = 1.0f; // near on the right: a shadow on the far side left of x = 64
    const auto n = bench::applyKinectNoise(z, o, 0);
    std::size_t nearEdge = 0;
    std::size_t elsewhere = 0;
    for (int y = 0; y < n.height; ++y)
        for (int x = 0; x < n.width; ++x)
            if (n.at(x, y) == 0)
                (std::abs(x - 63) <= 25 ? nearEdge : elsewhere)++;
    // Shadow 585·0.075·(1 − 0.5) ≈ 22 px on every row.
    EXPECT_GE(nearEdge, static_cast<std::size_t>(20 * n.height));
    EXPECT_EQ(elsewhere, 0u);
}

// --- Scenes and strokes
// ----------------------------------------------------------------------------

/// The largest rise of the reference along the line over 0.5 mm (a silhouette step), m.
double largestStep(bench::ReferenceSurface &ref, double t, glm::dvec2 a, glm::dvec2 b)
{
    const int n = static_cast<int>(glm::length(b - a) / 0.5e-3);
    double best = 0.0;
    double prev = ref.height(t, a.x, a.y);
    for (int i = 1; i <= n; ++i) {
        const glm::dvec2 p = a + (b - a) * (static_cast<double>(i) / n);
        const double h = ref.height(t, p.x, p.y);
        best = std::max(best, std::fabs(h - prev));
        prev = h;
    }
    return best;
}

/// \a scene without depth noise, \a seconds (s) long, at its default size.
Result<bench::FeelScene> noiselessScene(bench::SyntheticScene scene, double seconds)
{
    bench::SyntheticSceneOptions o;
    o.seconds = seconds;
    o.noisy = false;
    return bench::makeSyntheticScene(scene, o);
}

TEST(FeelScenesTest, HeadSceneIsGray8WithAStepOfThirteenToTwentyMillimetres)
{
    auto s = noiselessScene(bench::SyntheticScene::Head, 0.2);
    ASSERT_TRUE(s) << s.error().what;
    EXPECT_EQ(s->format, SampleFormat::Gray8);
    EXPECT_EQ(s->frameCount(), 6u);
    ASSERT_FALSE(s->crossings.empty());
    bench::ReferenceSurface ref(*s);
    for (const auto &c : s->crossings) {
        const double step = largestStep(ref, 0.1, c.from, c.to);
        EXPECT_GT(step, 13e-3) << c.what;
        EXPECT_LT(step, 20e-3) << c.what;
    }
}

TEST(FeelScenesTest, ForearmIsAboutNineMillimetresWide)
{
    auto s = noiselessScene(bench::SyntheticScene::Forearm, 0.1);
    ASSERT_TRUE(s) << s.error().what;
    ASSERT_FALSE(s->crossings.empty());
    bench::ReferenceSurface ref(*s);
    const auto &c = s->crossings.front();
    const double base = ref.height(0.0, c.from.x, c.from.y);
    double width = 0.0;
    double top = -1.0;
    const int n = 2000;
    for (int i = 0; i <= n; ++i) {
        const glm::dvec2 p = c.from + (c.to - c.from) * (static_cast<double>(i) / n);
        const double h = ref.height(0.0, p.x, p.y);
        top = std::max(top, h - base);
        if (h - base > 5e-3)
            width += glm::length(c.to - c.from) / n;
    }
    EXPECT_NEAR(width, 9e-3, 1.5e-3);
    EXPECT_GT(top, 10e-3);
    const double step = largestStep(ref, 0.0, c.from, c.to);
    EXPECT_GT(step, 8e-3);
    EXPECT_LT(step, 20e-3);
}

TEST(FeelScenesTest, StrokesFollowTheSurfaceAndMarkPhases)
{
    bench::SyntheticSceneOptions o;
    o.seconds = 2.0;
    o.width = 320;
    o.height = 240;
    auto s = bench::makeSyntheticScene(bench::SyntheticScene::Table, o);
    ASSERT_TRUE(s) << s.error().what;
    const auto strokes = bench::makeStrokes(*s);
    ASSERT_GE(strokes.size(), 8u);
    bench::ReferenceSurface ref(*s);
    for (const auto &st : strokes) {
        std::size_t sliding = 0;
        std::size_t held = 0;
        for (const auto &p : st.samples) {
            sliding += p.sliding;
            held += p.held;
            if (p.sliding || p.held) {
                EXPECT_NEAR(p.hip.z, ref.height(p.t, p.hip.x, p.hip.y) + (-st.depth), 1e-9)
                    << st.name;
            }
        }
        EXPECT_GE(held, 400u) << st.name;
        if (st.kind != bench::StrokeKind::Press) {
            EXPECT_GE(sliding, 300u) << st.name;
        }
        EXPECT_GT(
            st.samples.front().hip.z,
            ref.height(st.samples.front().t, st.samples.front().hip.x, st.samples.front().hip.y));
    }
}

} // namespace
} // namespace depthtouch::haptics
