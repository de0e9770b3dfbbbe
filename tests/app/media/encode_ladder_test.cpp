/// \file
/// \brief The sender's HLS rendition ladder (`encode --renditions`): each rendition's media
/// playlist carries color, depth and material at its own size with the pair's PTS, and the
/// multivariant playlist names them with RESOLUTION and with BANDWIDTH and AVERAGE-BANDWIDTH that
/// this test works out itself from the segment files and the EXTINF durations, by RFC 8216
/// §4.3.4.2's rule (the peak over runs of segments lasting 0.5 to 1.5 target durations).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "depthtouch/media/encode_job.h"
#include "encode_sources.h"
#include "readback.h"

using namespace depthtouch;
using namespace depthtouch::media;
namespace fs = std::filesystem;

namespace {

using test::EncodeTest;
using test::TestSource;

/// A media playlist's segments: file names and EXTINF durations (s).
struct Segments {
    std::vector<std::string> names;
    std::vector<double> seconds;
};

Segments readMediaPlaylist(const fs::path &path)
{
    Segments s;
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("#EXTINF:", 0) == 0)
            s.seconds.push_back(std::stod(line.substr(8)));
        else if (!line.empty() && line[0] != '#')
            s.names.push_back(line);
    }
    return s;
}

/// The figures a multivariant playlist line gives, by attribute name.
std::string attribute(const std::string &line, const std::string &name)
{
    const std::size_t at = line.find(name + "=");
    if (at == std::string::npos)
        return {};
    const std::size_t from = at + name.size() + 1;
    return line.substr(from, line.find(',', from) - from);
}

/// GIVEN color, 8-bit nearness and material codes, 4.5 s at 10 frames/s WHEN encoded to HLS
/// with renditions 48, 32 and 16 pixels high THEN each rendition's playlist holds the three
/// streams at its size (the aspect kept, widths even) with the same PTS, and the multivariant
/// playlist lists them tallest first with the rates of their segment files.
TEST_F(EncodeTest, renditionLadderCarriesEveryStreamAtEachSizeWithMeasuredRates)
{
    constexpr int kFrames = 45;
    constexpr double kFps = 10.0;
    TestSource color = test::colorSource(kFrames, kFps);
    TestSource depthSrc = test::nearness8Source(kFrames, kFps);
    TestSource material([](int i) { return test::makeColor(i / 10); }, kFrames, kFps,
                        PixelFormat::Rgb24);
    EncodeOptions o = fastOptions(path("show.m3u8"));
    o.renditions = {48, 32, 16};
    auto s = encodeStreams(color, depthSrc, &material, o);
    ASSERT_TRUE(s) << s.error().what;

    const struct {
        int width, height;
        const char *uri;
    } want[] = {{64, 48, "show_48p.m3u8"}, {42, 32, "show_32p.m3u8"}, {22, 16, "show_16p.m3u8"}};
    std::ifstream master(path("show.m3u8"));
    std::vector<std::string> lines;
    for (std::string line; std::getline(master, line);)
        lines.push_back(line);
    ASSERT_EQ(s->renditions.size(), 3u);
    std::size_t found = 0;
    for (std::size_t i = 0; i + 1 < lines.size(); ++i) {
        if (lines[i].rfind("#EXT-X-STREAM-INF:", 0) != 0)
            continue;
        ASSERT_LT(found, 3u);
        const auto &w = want[found];
        EXPECT_EQ(lines[i + 1], w.uri);
        EXPECT_EQ(attribute(lines[i], "RESOLUTION"),
                  std::to_string(w.width) + "x" + std::to_string(w.height));

        // The rates, from the files: 2 s segments (a key frame every 2 s), the last 0.5 s.
        const Segments seg = readMediaPlaylist(path(w.uri));
        ASSERT_EQ(seg.names.size(), 3u) << w.uri;
        std::vector<double> bits;
        double total = 0.0;
        for (const std::string &name : seg.names) {
            bits.push_back(8.0 * static_cast<double>(fs::file_size(path(name))));
            total += bits.back();
        }
        const double target = 2.0;
        double peak = 0.0;
        for (std::size_t a = 0; a < bits.size(); ++a)
            for (std::size_t b = a; b < bits.size(); ++b) {
                double sum = 0.0, span = 0.0;
                for (std::size_t k = a; k <= b; ++k) {
                    sum += bits[k];
                    span += seg.seconds[k];
                }
                if (span >= 0.5 * target && span <= 1.5 * target)
                    peak = std::max(peak, sum / span);
            }
        const double average = total / (seg.seconds[0] + seg.seconds[1] + seg.seconds[2]);
        EXPECT_NEAR(std::stod(attribute(lines[i], "BANDWIDTH")), peak, 0.01 * peak) << w.uri;
        EXPECT_NEAR(std::stod(attribute(lines[i], "AVERAGE-BANDWIDTH")), average, 0.01 * average)
            << w.uri;
        EXPECT_EQ(s->renditions[found].peakBitRate, std::stoll(attribute(lines[i], "BANDWIDTH")));

        // The streams at the rendition's size, every pair at one PTS.
        const auto rb = test::readBack(path(w.uri), {0, 2}, false);
        ASSERT_TRUE(rb.ok) << rb.error;
        ASSERT_GE(rb.streams.size(), 3u) << w.uri;
        for (std::size_t k = 0; k < 3; ++k) {
            EXPECT_EQ(rb.streams[k].width, w.width) << w.uri << " stream " << k;
            EXPECT_EQ(rb.streams[k].height, w.height) << w.uri << " stream " << k;
            EXPECT_EQ(rb.streams[k].pts.size(), static_cast<std::size_t>(kFrames));
        }
        EXPECT_EQ(rb.streams[0].pts, rb.streams[1].pts) << w.uri;
        EXPECT_EQ(rb.streams[0].pts, rb.streams[2].pts) << w.uri;
        ++found;
    }
    EXPECT_EQ(found, 3u);
}

/// GIVEN a ladder for a file that is not HLS, heights not tallest first, or a rendition taller
/// than the picture THEN the encode is refused and leaves nothing behind.
TEST_F(EncodeTest, badRenditionsAreRefusedAndLeaveNoFile)
{
    const struct {
        const char *output;
        std::vector<int> heights;
    } cases[] = {{"a.mkv", {48, 32}},  {"b.m3u8", {32, 48}}, {"c.m3u8", {48, 48}},
                 {"d.m3u8", {96, 48}}, {"e.m3u8", {47}},     {"f.m3u8", {48, 8}}};
    for (const auto &c : cases) {
        TestSource color = test::colorSource(5);
        TestSource depthSrc = test::nearness8Source(5);
        EncodeOptions o = fastOptions(path(c.output));
        o.renditions = c.heights;
        auto s = encodeStreams(color, depthSrc, o);
        ASSERT_FALSE(s) << c.output;
        EXPECT_EQ(s.error().code, Errc::InvalidArgument) << c.output;
    }
    EXPECT_TRUE(files().empty()) << "an encode that was refused left " << files().front();
}

} // namespace
