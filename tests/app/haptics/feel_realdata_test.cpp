/// \file
/// \brief The fingertip renderer (touch's and play's default) on strokes `bench feel` places on
/// the shared real captures, replayed alone: the captures are read, mapped and stroked as
/// `bench feel` does (feel_suite.h, makeFamilyStrokes()). Each case is a stroke that failed a
/// goal of docs/benchmarks.md. Skips without the captures; fails without them where they are
/// required (DT_REQUIRE_SHARED_DATA, CI).

#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/haptics/feel_bench.h"
#include "depthtouch/haptics/feel_scenes.h"
#include "depthtouch/haptics/feel_suite.h"
#include "support/shared_data.h"

namespace depthtouch::haptics::bench {
namespace {

/// The figures of the `finger` setting on the family stroke \a name of the capture scene
/// \a scene ("realsense-lab/8"), printed; empty figures (and a failure) when it cannot be made.
FeelFigures fingerOnCapture(const std::string &scene, const std::string &name)
{
    FeelSuiteOptions o;
    o.data = testing::sharedDataDir();
    o.fifo = false;
    o.scenes = {scene};
    std::vector<FeelScene> scenes;
    std::vector<FeelScene> clean;
    const auto error = loadFeelScenes(o, scenes, clean);
    EXPECT_FALSE(error) << (error ? error->message : "");
    const FeelScene *s = nullptr;
    for (const FeelScene &c : scenes)
        if (c.name == scene)
            s = &c;
    EXPECT_NE(s, nullptr) << scene;
    if (s == nullptr)
        return {};
    std::vector<Stroke> strokes;
    for (Stroke &st : makeFamilyStrokes(*s, FamilyPlan{}))
        if (st.name == name)
            strokes.push_back(std::move(st));
    EXPECT_EQ(strokes.size(), 1u) << name << " is no longer placed on " << scene;
    FeelSetting finger;
    for (const FeelSetting &f : feelSettings({Method::Finger}))
        if (f.name == "finger")
            finger = f;
    auto results = runFeelStrokes(*s, strokes, finger);
    EXPECT_TRUE(results) << (results ? "" : results.error().what);
    if (!results || results->size() != 1u)
        return {};
    const FeelFigures &f = results->front().figures;
    std::printf("finger, %s on %s: pop-through %.0f ms, max %.2f N, %zu trips\n", name.c_str(),
                scene.c_str(), f.popThroughMs, f.maxForce, f.trips);
    return f;
}

// A 6 mm press at 5 cm/s on the near side of an edge of the RealSense lab, 8-bit. The descent of
// the proxy stopped 2.4 mm from the HIP's projection on its plane, fitted on the lower side beside
// the edge; that projection lay on the plane extrapolated under the edge the finger was pressed
// 6 mm into, and the force unloaded to 0.04 N: 12 ms of pop-through (goal ≤ 10 ms). The proxy now
// stays on the patch its plane was fitted to (FingerRenderer::keepOnPatch()).
TEST(FeelRealDataTest, aDeepPressBesideTheLabsEdgeKeepsItsForce)
{
    DT_NEED_SHARED_DATA("rgbd-realsense-lab/depth/00000.png");
    const FeelFigures f = fingerOnCapture("realsense-lab/8", "press 6.0 mm 5 cm/s edge");
    EXPECT_GT(f.maxForce, 1.0); // it pressed
    EXPECT_LE(f.popThroughMs, FeelGoals{}.maxPopThroughMs);
    EXPECT_EQ(f.falseTrips, 0u);
}

} // namespace
} // namespace depthtouch::haptics::bench
