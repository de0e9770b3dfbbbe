/// \file
/// \brief The HLS rendition ladder's plan and multivariant playlist (see renditions.h).

#include "renditions.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

namespace depthtouch::media::detail {

Result<std::vector<RenditionPlan>>
planRenditions(const std::string &master, const std::vector<int> &heights, int width, int height)
{
    const std::filesystem::path path(master);
    const std::string stem = path.stem().string();
    std::vector<RenditionPlan> plans;
    for (const int h : heights) {
        if (h > height)
            return unexpected(Errc::InvalidArgument,
                              "A rendition is taller than the picture (--renditions)");
        RenditionPlan p;
        p.height = h;
        p.width = 2 * static_cast<int>(std::lround(static_cast<double>(width) * h / height / 2.0));
        if (p.width < 2)
            return unexpected(Errc::InvalidArgument,
                              "A rendition is narrower than 2 pixels (--renditions)");
        p.uri = stem + "_" + std::to_string(h) + "p.m3u8";
        p.playlist = (path.parent_path() / p.uri).string();
        plans.push_back(std::move(p));
    }
    return plans;
}

long long peakBitRate(const std::vector<long long> &bytes, const std::vector<double> &seconds,
                      double target)
{
    double peak = 0.0;
    for (std::size_t i = 0; i < bytes.size() && i < seconds.size(); ++i) {
        double bits = 0.0;
        double span = 0.0;
        for (std::size_t j = i; j < bytes.size() && j < seconds.size(); ++j) {
            bits += 8.0 * static_cast<double>(bytes[j]);
            span += seconds[j];
            if (span > 1.5 * target)
                break;
            if (span >= 0.5 * target && span > 0.0)
                peak = std::max(peak, bits / span);
        }
    }
    return std::llround(peak);
}

std::string multivariantPlaylist(const std::vector<RenditionPlan> &plans,
                                 const std::vector<RenditionRate> &rates, double fps)
{
    std::string text = "#EXTM3U\n#EXT-X-VERSION:3\n#EXT-X-INDEPENDENT-SEGMENTS\n";
    char line[256];
    for (std::size_t i = 0; i < plans.size() && i < rates.size(); ++i) {
        const RenditionPlan &p = plans[i];
        std::snprintf(line, sizeof line, "#EXT-X-STREAM-INF:BANDWIDTH=%lld", rates[i].peak);
        text += line;
        if (rates[i].average > 0) {
            std::snprintf(line, sizeof line, ",AVERAGE-BANDWIDTH=%lld", rates[i].average);
            text += line;
        }
        std::snprintf(line, sizeof line, ",RESOLUTION=%dx%d,FRAME-RATE=%.3f\n", p.width, p.height,
                      fps);
        text += line;
        text += p.uri;
        text += '\n';
    }
    return text;
}

} // namespace depthtouch::media::detail
