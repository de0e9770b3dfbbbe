/// \file
/// \brief hal::applyDepthTag(): the one reader of DepthTouch's depth tags (docs/architecture.md
/// §3), shared by the FFmpeg media source and the GStreamer elements.

#include <gtest/gtest.h>

#include "depthtouch/hal/depth_tags.h"

namespace depthtouch::hal {
namespace {

// Each of the five tags lands in its field, the key in any case; the values as `encode` writes
// them (docs/architecture.md §3).
TEST(DepthTagsTest, eachTagFillsItsField)
{
    DepthMetadata md;
    EXPECT_TRUE(applyDepthTag("depth_near", "0.5", md));
    EXPECT_TRUE(applyDepthTag("DEPTH_FAR", "4.25", md));
    EXPECT_TRUE(applyDepthTag("Depth_Mapping", "inverse", md));
    EXPECT_TRUE(applyDepthTag("depth_bits", "10", md));
    EXPECT_TRUE(applyDepthTag("depth_occupancy", "96", md));
    EXPECT_DOUBLE_EQ(md.nearMetres, 0.5);
    EXPECT_DOUBLE_EQ(md.farMetres, 4.25);
    EXPECT_EQ(md.mapping, "inverse");
    EXPECT_EQ(md.bits, 10);
    EXPECT_EQ(md.occupancy, 96u);
    EXPECT_EQ(kDepthTagNames.size(), 5u);
}

// The ends of the ranges are in them: 1 and 16 bits, occupancy 1 and 65535.
TEST(DepthTagsTest, theRangesIncludeTheirEnds)
{
    DepthMetadata md;
    EXPECT_TRUE(applyDepthTag("depth_bits", "1", md));
    EXPECT_EQ(md.bits, 1);
    EXPECT_TRUE(applyDepthTag("depth_bits", "16", md));
    EXPECT_EQ(md.bits, 16);
    EXPECT_TRUE(applyDepthTag("depth_occupancy", "1", md));
    EXPECT_EQ(md.occupancy, 1u);
    EXPECT_TRUE(applyDepthTag("depth_occupancy", "65535", md));
    EXPECT_EQ(md.occupancy, 65535u);
}

// Nonsense is refused and leaves what was read: a plane that is not a positive finite distance,
// bits outside 1..16, an occupancy that is not a whole number in 1..65535, an empty or absent
// value, another tag.
TEST(DepthTagsTest, nonsenseLeavesTheMetadataAsItWas)
{
    DepthMetadata md;
    md.nearMetres = 0.5;
    md.farMetres = 4.0;
    md.mapping = "inverse";
    md.bits = 8;
    md.occupancy = 24;
    const DepthMetadata before = md;
    for (const char *v : {"-1", "0", "inf", "nan", "metres", ""}) {
        EXPECT_FALSE(applyDepthTag("depth_near", v, md)) << v;
        EXPECT_FALSE(applyDepthTag("depth_far", v, md)) << v;
    }
    EXPECT_FALSE(applyDepthTag("depth_bits", "17", md));
    EXPECT_FALSE(applyDepthTag("depth_bits", "0", md));
    EXPECT_FALSE(applyDepthTag("depth_occupancy", "1.5", md));
    EXPECT_FALSE(applyDepthTag("depth_occupancy", "65536", md));
    EXPECT_FALSE(applyDepthTag("depth_mapping", "", md));
    EXPECT_FALSE(applyDepthTag("depth_mapping", nullptr, md));
    EXPECT_FALSE(applyDepthTag("title", "depth", md));
    EXPECT_FALSE(applyDepthTag(nullptr, "1", md));
    EXPECT_DOUBLE_EQ(md.nearMetres, before.nearMetres);
    EXPECT_DOUBLE_EQ(md.farMetres, before.farMetres);
    EXPECT_EQ(md.mapping, before.mapping);
    EXPECT_EQ(md.bits, before.bits);
    EXPECT_EQ(md.occupancy, before.occupancy);
}

} // namespace
} // namespace depthtouch::hal
