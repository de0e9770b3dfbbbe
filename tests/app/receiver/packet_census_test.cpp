// The stream spans `probe` reports (receiver/packet_census.h): a stream's PTS range plus one frame
// period, to the nanosecond, against the spans worked out here from the packets and the rate.
#include "depthtouch/receiver/packet_census.h"

#include <gtest/gtest.h>

namespace depthtouch::receiver {
namespace {

TEST(PacketCensusTest, aStreamSpansItsPtsRangePlusOneFramePeriodToTheNanosecond)
{
    hal::MediaInfo info;
    info.streams.resize(3);
    info.streams[0].frameRate = {30, 1};       // 33 333 333.3 ns: rounds down
    info.streams[1].frameRate = {30000, 1001}; // 33 366 666.7 ns: rounds up
    info.streams[2].frameRate = {0, 0};        // unknown: no period added
    std::vector<StreamCount> counts(4);
    counts[0].pts = {hal::Pts(66'666'667), hal::Pts(0), hal::Pts(33'333'333)};
    counts[1].pts = {hal::Pts(1'000'000'000), hal::Pts(1'033'366'667)};
    counts[2].pts = {hal::Pts(5), hal::Pts(25)};
    const std::vector<hal::Pts> spans = streamSpans(info, counts);
    ASSERT_EQ(spans.size(), 4u);
    EXPECT_EQ(spans[0].count(), 66'666'667 + 33'333'333); // 100 ms exactly
    EXPECT_EQ(spans[1].count(), 33'366'667 + 33'366'667);
    EXPECT_EQ(spans[2].count(), 20);
    EXPECT_EQ(spans[3].count(), 0) << "a stream without packets";
}

} // namespace
} // namespace depthtouch::receiver
