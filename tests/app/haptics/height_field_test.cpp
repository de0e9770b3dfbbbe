#include "depthtouch/haptics/height_field.h"

#include <cmath>

#include <gtest/gtest.h>

#include "app/haptics/synthetic.h"
#include "depthtouch/scene/surface_mapping.h"

namespace depthtouch::haptics {
namespace {

using test::makeFrame;
using test::OwnedFrame;

TEST(HeightFieldTest, verticesFollowDesignMapping)
{
    // GIVEN an 8-bit 5×3 frame with a padded stride and known samples
    const SceneBox box{0.10, 0.04};
    OwnedFrame f(5, 3, SampleFormat::Gray8, 0.0, /*padBytes=*/3);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 5; ++c)
            f.set(c, r, static_cast<std::uint32_t>(c * 50 + r));
    HeightField hf(box);
    ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
    // THEN x = (c − (W−1)/2)·s, y = ((H−1)/2 − r)·s, z = (v/255 − 0.5)·depth
    const double s = 0.10 / 4;
    EXPECT_DOUBLE_EQ(hf.spacing(), s);
    const glm::dvec3 v = hf.vertex(4, 0);
    EXPECT_DOUBLE_EQ(v.x, 2 * s);
    EXPECT_DOUBLE_EQ(v.y, 1 * s);
    EXPECT_DOUBLE_EQ(v.z, (200.0 / 255.0 - 0.5) * 0.04);
    EXPECT_DOUBLE_EQ(hf.vertex(0, 2).y, -s);
    EXPECT_DOUBLE_EQ(hf.vertex(0, 2).z, (2.0 / 255.0 - 0.5) * 0.04);
    // AND the height at a vertex is the vertex height
    EXPECT_NEAR(hf.heightAt(v.x, v.y), v.z, 1e-15);
}

TEST(HeightFieldTest, aHeightIsMeasuredUnlessAHolesVertexWeighsInItByAThousandth)
{
    const SceneBox box{0.10, 0.04};
    const HeightField hf(box);
    const double back = -0.5 * box.depth;
    // A hole's vertex lies holeDrop() (1 m) under the back of the box.
    EXPECT_DOUBLE_EQ(hf.holeZ(), back - HeightField::holeDrop());
    EXPECT_TRUE(hf.measured(0.0));
    EXPECT_TRUE(hf.measured(back)); // the deepest measured height
    EXPECT_FALSE(hf.measured(hf.holeZ()));
    // Interpolated between a vertex at the back and a hole's vertex, at a hole's weight w.
    const auto blend = [&](double w) { return (1.0 - w) * back + w * hf.holeZ(); };
    EXPECT_TRUE(hf.measured(blend(0.0005)));
    EXPECT_FALSE(hf.measured(blend(0.002)));
    // Off the grid is not measured, and not a hole either (finger_hole.cpp tells them apart).
    EXPECT_FALSE(hf.measured(std::nan("")));
}

TEST(HeightFieldTest, triangulationUsesTheDiagonalFromTopLeftToBottomRight)
{
    // GIVEN a single cell with only vertex (c+1, r) raised
    const SceneBox box{0.10, 0.04};
    OwnedFrame f(2, 2, SampleFormat::Gray16, 0.0);
    f.set(1, 0, 65535);
    HeightField hf(box);
    ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
    const double lowZ = -0.02;
    // THEN the centre of the cell lies on the diagonal (c,r)–(c+1,r+1), both ends low
    EXPECT_NEAR(hf.heightAt(0.0, 0.0), lowZ, 1e-15);
    // AND the upper-right half (toward (c+1, r)) is raised, the lower-left half is flat
    EXPECT_GT(hf.heightAt(0.03, 0.03), lowZ + 0.01);
    EXPECT_NEAR(hf.heightAt(-0.03, -0.03), lowZ, 1e-15);
    EXPECT_EQ(hf.triangleAt(0.03, 0.03).upper, 0);
    EXPECT_EQ(hf.triangleAt(-0.03, -0.03).upper, 1);
}

TEST(HeightFieldTest, interpolatesBetweenFramesByHapticTime)
{
    // GIVEN frame i at z = −5 mm (t = 1 s) and frame i+1 at z = +3 mm (t = 1.1 s)
    const SceneBox box{};
    const OwnedFrame a = makeFrame(box, 4, 4, 1.0, [](double, double) { return -0.005; });
    const OwnedFrame b = makeFrame(box, 4, 4, 1.1, [](double, double) { return 0.003; });
    HeightField hf(box);
    const DepthFrameView bv = b.view();
    ASSERT_TRUE(hf.setFrames(a.view(), &bv));
    const double za = hf.frameZ(a.view(), 1, 1);
    const double zb = hf.frameZ(bv, 1, 1);
    // WHEN the haptic time is a quarter of the way (Eq. 1)
    hf.setTime(1.025, true);
    EXPECT_NEAR(hf.vertexZ(1, 1), za + 0.25 * (zb - za), 1e-15);
    // AND without interpolation the surface holds frame i
    hf.setTime(1.025, false);
    EXPECT_DOUBLE_EQ(hf.vertexZ(1, 1), za);
    // AND α is clamped outside the frame interval
    hf.setTime(2.0, true);
    EXPECT_DOUBLE_EQ(hf.vertexZ(1, 1), zb);
}

TEST(HeightFieldTest, holdsVerticesThatJumpMoreThanTheCutThreshold)
{
    // GIVEN a 20 mm jump (half the 40 mm box) between frames: above the 10 mm default cut threshold
    const SceneBox box{};
    const OwnedFrame a = makeFrame(box, 3, 3, 0.0, [](double, double) { return -0.01; });
    const OwnedFrame b = makeFrame(box, 3, 3, 0.1, [](double, double) { return 0.01; });
    HeightField hf(box);
    const DepthFrameView bv = b.view();
    ASSERT_TRUE(hf.setFrames(a.view(), &bv));
    hf.setTime(0.05, true);
    EXPECT_NEAR(hf.vertexZ(0, 0), -0.01, 1e-6);
    // WHEN the threshold is raised above the jump THEN it is interpolated
    hf.setCutThreshold(0.05);
    EXPECT_NEAR(hf.vertexZ(0, 0), 0.0, 1e-6);
}

TEST(HeightFieldTest, rejectsMalformedFrames)
{
    const SceneBox box{};
    HeightField hf(box);
    DepthFrameView bad{};
    EXPECT_EQ(hf.setFrames(bad, nullptr).error().code, Errc::InvalidArgument);
    const OwnedFrame a = makeFrame(box, 4, 3, 0.0, [](double, double) { return 0.0; });
    DepthFrameView shortStride = a.view();
    shortStride.strideBytes = 7;
    EXPECT_FALSE(hf.setFrames(shortStride, nullptr));
    const OwnedFrame other = makeFrame(box, 5, 3, 1.0, [](double, double) { return 0.0; });
    const DepthFrameView ov = other.view();
    EXPECT_FALSE(hf.setFrames(a.view(), &ov)); // size differs
    const OwnedFrame same = makeFrame(box, 4, 3, 0.0, [](double, double) { return 0.0; });
    const DepthFrameView sv = same.view();
    EXPECT_FALSE(hf.setFrames(a.view(), &sv)); // PTS does not increase
    EXPECT_FALSE(hf.valid());
    HeightField badBox(SceneBox{0.0, 0.04});
    EXPECT_FALSE(badBox.setFrames(a.view(), nullptr));
}

// The scene layer's mapping (what the stereo renderer draws) is read off the height field (what the
// haptic renderer touches) to the bit: origin and steps from its column, row and sample
// conversions, for both sample formats, odd and even sizes and other boxes.
TEST(HeightFieldTest, theSceneMappingIsTheHeightFieldsToTheBit)
{
    for (const SceneBox box : {SceneBox{}, SceneBox{0.37, 0.11}}) {
        for (const SampleFormat format : {SampleFormat::Gray8, SampleFormat::Gray16}) {
            for (const auto &[w, h] : {std::pair{4, 3}, std::pair{640, 480}, std::pair{719, 485}}) {
                const OwnedFrame f = makeFrame(
                    box, w, h, 0.0, [](double, double) { return 0.0; }, format);
                HeightField hf(box);
                ASSERT_TRUE(hf.setFrames(f.view(), nullptr));
                const auto m = scene::SurfaceMapping::of(box, f.view());
                ASSERT_TRUE(m);
                EXPECT_EQ(m->columns, w);
                EXPECT_EQ(m->rows, h);
                EXPECT_EQ(m->x0, hf.columnToX(0.0));
                EXPECT_EQ(m->dx, hf.columnToX(1.0) - hf.columnToX(0.0));
                EXPECT_EQ(m->y0, hf.rowToY(0.0));
                EXPECT_EQ(m->dy, hf.rowToY(1.0) - hf.rowToY(0.0));
                EXPECT_EQ(m->vmax, maxSampleValue(format));
                // z at nearness 0 and at v_max, through the height field's own sample conversion
                test::OwnedFrame probe(2, 1, format, 0.0);
                probe.set(0, 0, 0);
                probe.set(1, 0, static_cast<std::uint32_t>(maxSampleValue(format)));
                EXPECT_EQ(m->z0, hf.frameZ(probe.view(), 0, 0));
                EXPECT_EQ(m->dz, hf.frameZ(probe.view(), 1, 0) - hf.frameZ(probe.view(), 0, 0));
            }
        }
    }
    const OwnedFrame f = makeFrame(SceneBox{}, 4, 3, 0.0, [](double, double) { return 0.0; });
    EXPECT_FALSE(scene::SurfaceMapping::of(SceneBox{0.0, 0.04}, f.view()));
    EXPECT_FALSE(scene::SurfaceMapping::of(SceneBox{}, DepthFrameView{}));
}

} // namespace
} // namespace depthtouch::haptics
