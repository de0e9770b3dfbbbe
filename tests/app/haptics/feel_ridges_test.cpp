/// \file
/// \brief The feel bench's ridges scene (SyntheticScene::Ridges) against its documented layout:
/// a board whose top is narrower than a fingertip, standing over the table as a silhouette, a
/// cable pulled to and fro, and the press appended to makeFamilyStrokes() onto the board's top
/// (FamilyPlan::ridgePress).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "depthtouch/haptics/feel_scenes.h"
#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics {
namespace {

using bench::SyntheticScene;

Result<bench::FeelScene> ridgesScene(double seconds, bool noisy)
{
    bench::SyntheticSceneOptions o;
    o.seconds = seconds;
    o.noisy = noisy;
    return bench::makeSyntheticScene(SyntheticScene::Ridges, o);
}

/// The board's profile along the "ridge" crossing at time \a t, over the table's chord (the line
/// between the reference heights at the crossing's two ends: the table is a plane): how high the
/// top stands over it, and the width of the line within 1 mm of the top, m.
struct Profile {
    double top = -1.0;
    double width = 0.0;
};

Profile profileAcross(bench::ReferenceSurface &ref, const bench::SilhouetteCrossing &c, double t)
{
    constexpr int kSteps = 2000;
    const double from = ref.height(t, c.from.x, c.from.y);
    const double to = ref.height(t, c.to.x, c.to.y);
    std::vector<double> over;
    for (int i = 0; i <= kSteps; ++i) {
        const double u = static_cast<double>(i) / kSteps;
        const glm::dvec2 q = c.from + (c.to - c.from) * u;
        over.push_back(ref.height(t, q.x, q.y) - (from + (to - from) * u));
    }
    Profile p;
    p.top = *std::max_element(over.begin(), over.end());
    const double step = glm::length(c.to - c.from) / kSteps;
    for (const double z : over)
        p.width += z > p.top - 1e-3 ? step : 0.0;
    return p;
}

// The board stands over the table as a silhouette (a step over findSilhouettes()' 3 mm, so the
// families place swipes, circles and traces on it), and its top is narrower than the default
// fingertip: 10 mm of a scene about 1.09 m wide at 1 m, in a box 0.1 m wide, is 0.92 mm, under
// the radius of 1.5 mm (the board's side the camera sees adds a little within 1 mm of the top).
TEST(FeelRidgesTest, theBoardsTopIsNarrowerThanAFingertipAndStandsOverTheTable)
{
    auto s = ridgesScene(0.5, false);
    ASSERT_TRUE(s) << s.error().what;
    EXPECT_EQ(s->name, "synthetic-ridges");
    const auto ridge = std::find_if(s->crossings.begin(), s->crossings.end(),
                                    [](const auto &c) { return c.what == "ridge"; });
    ASSERT_NE(ridge, s->crossings.end());
    bench::ReferenceSurface ref(*s);
    const Profile p = profileAcross(ref, *ridge, 0.25);
    std::printf("top %.2f mm over the table, %.2f mm wide within 1 mm of it\n", p.top * 1e3,
                p.width * 1e3);
    EXPECT_GT(p.top, 3e-3);
    RendererConfig config;
    config.box = s->box;
    const double r = config.fingerRadiusInBox();
    EXPECT_NEAR(r, 1.5e-3, 1e-9);
    EXPECT_LT(p.width, r);
    EXPECT_GT(p.width, 0.4e-3);
    // The crossing's middle is on the top.
    const glm::dvec2 mid = 0.5 * (ridge->from + ridge->to);
    const double chordMid = 0.5 * (ref.height(0.25, ridge->from.x, ridge->from.y) +
                                   ref.height(0.25, ridge->to.x, ridge->to.y));
    EXPECT_GT(ref.height(0.25, mid.x, mid.y) - chordMid, p.top - 1e-3);
}

// The appended press goes 6 mm into the board's top at 5 cm/s, and the cable's motion gives the
// holds and presses that look for moving content a place beside it.
TEST(FeelRidgesTest, theRidgePressIsOnTheTopAndTheMovingCableIsFound)
{
    auto s = ridgesScene(1.5, true);
    ASSERT_TRUE(s) << s.error().what;
    std::vector<std::string> notes;
    const auto strokes = bench::makeFamilyStrokes(*s, {}, &notes);
    for (const auto &n : notes)
        std::printf("note: %s\n", n.c_str());
    const auto press = std::find_if(strokes.begin(), strokes.end(), [](const auto &st) {
        return st.name == "press 6.0 mm 5 cm/s ridge";
    });
    ASSERT_NE(press, strokes.end());
    EXPECT_EQ(press->family, bench::StrokeFamily::Press);
    EXPECT_EQ(press->where, "ridge");
    EXPECT_NEAR(press->depth, 6e-3, 1e-12);
    const auto ridge = std::find_if(s->crossings.begin(), s->crossings.end(),
                                    [](const auto &c) { return c.what == "ridge"; });
    ASSERT_NE(ridge, s->crossings.end());
    bench::ReferenceSurface ref(*s);
    std::size_t deepest = 0;
    for (std::size_t i = 0; i < press->samples.size(); ++i)
        if (press->samples[i].hip.z < press->samples[deepest].hip.z)
            deepest = i;
    const bench::StrokeSample &at = press->samples[deepest];
    const Profile p = profileAcross(ref, *ridge, at.t);
    // Pressed in from the top, not from the table beside it.
    const double top = ref.height(at.t, at.hip.x, at.hip.y);
    EXPECT_NEAR(at.hip.z, top - 6e-3, 0.5e-3);
    const double chordMid = 0.5 * (ref.height(at.t, ridge->from.x, ridge->from.y) +
                                   ref.height(at.t, ridge->to.x, ridge->to.y));
    EXPECT_GT(top - chordMid, p.top - 1e-3);
    const bool moving = std::any_of(strokes.begin(), strokes.end(),
                                    [](const auto &st) { return st.where == "moving"; });
    EXPECT_TRUE(moving);
    const bool swipe = std::any_of(strokes.begin(), strokes.end(), [](const auto &st) {
        return st.family == bench::StrokeFamily::Swipe && st.where == "silhouette";
    });
    EXPECT_TRUE(swipe);
}

} // namespace
} // namespace depthtouch::haptics
