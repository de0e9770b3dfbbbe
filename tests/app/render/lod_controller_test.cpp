/// \file
/// \brief LodController: the block budget follows the draw times to the target, holds through a
/// stall, grows back when drawing is fast, and never leaves its range (a simulated renderer whose
/// draw time is affine in the blocks drawn, as llvmpipe's is in the triangles).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "depthtouch/render/lod_controller.h"

using namespace depthtouch::render;

namespace {

/// A scene that needs \a needed blocks at full tolerance, drawn in fixed + perBlock × blocks s;
/// the mesh of frame n is made with the budget chosen after frame n − 1 (made a frame ahead).
struct SimulatedRenderer {
    std::size_t needed;
    double fixedS;
    double perBlockS;
    std::size_t lastBudget;

    MeshStats mesh(std::size_t budget) const
    {
        MeshStats s;
        s.blocks = static_cast<int>(std::min(needed, budget));
        s.budgetLimited = budget < needed;
        return s;
    }
    double seconds(const MeshStats &m) const { return fixedS + perBlockS * m.blocks; }
};

LodOptions options(double target)
{
    LodOptions o;
    o.targetSeconds = target;
    return o;
}

} // namespace

TEST(LodControllerTest, slowRendererSettlesUnderTheTargetWithoutOscillating)
{
    // GIVEN a scene of 12 000 blocks drawn in 5 ms + 2.5 µs a block (35 ms) and a 25 ms target
    SimulatedRenderer r{12000, 0.005, 2.5e-6, 0};
    LodController lod(options(0.025));
    std::size_t madeWith = lod.budget();
    int over = 0;
    int changes = 0;
    std::size_t last = lod.budget();
    for (int frame = 0; frame < 600; ++frame) {
        const MeshStats m = r.mesh(madeWith);
        madeWith = lod.budget(); // the next mesh is made before this frame's time is known
        const std::size_t b = lod.update(r.seconds(m), m);
        if (frame >= 100) {
            over += r.seconds(m) > 0.025 ? 1 : 0;
            changes += b != last ? 1 : 0;
        }
        last = b;
    }
    // THEN it draws as many blocks as fit: the budget within the 8 000 that fit and not far under
    EXPECT_LE(lod.budget(), 8000u);
    EXPECT_GE(lod.budget(), static_cast<std::size_t>(8000 * 0.8 / 1.15));
    // and once settled no frame is over the target, and the budget is not hunting
    EXPECT_EQ(over, 0);
    EXPECT_LE(changes, 2);
}

TEST(LodControllerTest, startsCoarseAndGrowsToTheFullMeshWhenDrawingIsFast)
{
    // GIVEN a fast renderer (12 000 blocks in 5 ms)
    SimulatedRenderer r{12000, 0.002, 0.25e-6, 0};
    LodController lod(options(0.025));
    EXPECT_LT(lod.budget(), r.needed) << "the first frames are drawn under a budget";
    std::size_t madeWith = lod.budget();
    for (int frame = 0; frame < 200; ++frame) {
        const MeshStats m = r.mesh(madeWith);
        madeWith = lod.budget();
        lod.update(r.seconds(m), m);
    }
    // THEN the budget no longer limits the mesh: the full tolerance is drawn
    EXPECT_FALSE(r.mesh(lod.budget()).budgetLimited);
    // and it stops growing once it does not limit (no wind-up): it is at most one step past
    EXPECT_LE(lod.budget(),
              static_cast<std::size_t>(std::ceil(static_cast<double>(r.needed) * 1.15)) + 1);
}

TEST(LodControllerTest, aSingleStallDoesNotMoveTheBudget)
{
    SimulatedRenderer r{12000, 0.005, 2.5e-6, 0};
    LodController lod(options(0.025));
    std::size_t madeWith = lod.budget();
    for (int frame = 0; frame < 300; ++frame) {
        const MeshStats m = r.mesh(madeWith);
        madeWith = lod.budget();
        lod.update(r.seconds(m), m);
    }
    const std::size_t settled = lod.budget();
    // WHEN one frame takes 200 ms (the host stalled), then drawing goes on as before
    const MeshStats m = r.mesh(settled);
    lod.update(0.200, m);
    for (int frame = 0; frame < 3; ++frame)
        lod.update(r.seconds(m), m);
    // THEN the median ignores it
    EXPECT_EQ(lod.budget(), settled);
}

TEST(LodControllerTest, aHeavierSceneIsFollowedDownAndNeverBelowTheFloor)
{
    LodOptions o = options(0.020);
    o.minBlocks = 700;
    LodController lod(o);
    // GIVEN blocks so dear (40 µs each) that even the floor's 700 take 28 ms + 5 ms fixed
    SimulatedRenderer r{50000, 0.005, 40e-6, 0};
    for (int frame = 0; frame < 100; ++frame) {
        const MeshStats m = r.mesh(lod.budget());
        lod.update(r.seconds(m), m);
        ASSERT_GE(lod.budget(), 700u);
    }
    // THEN the budget rests on the floor
    EXPECT_EQ(lod.budget(), 700u);
    // and nonsense times (a clock fault) change nothing
    const MeshStats m = r.mesh(lod.budget());
    lod.update(std::nan(""), m);
    lod.update(-1.0, m);
    EXPECT_EQ(lod.budget(), 700u);
}
