#include "depthtouch/receiver/stream_roles.h"

#include <algorithm>
#include <cctype>
#include <string_view>

#include "depthtouch/depth/occupancy.h"

namespace depthtouch::receiver {

namespace {

bool equalsNoCase(std::string_view a, std::string_view b) noexcept
{
    if (a.size() != b.size())
        return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) !=
            std::tolower(static_cast<unsigned char>(b[i])))
            return false;
    return true;
}

bool isGray(hal::PixelFormat f) noexcept
{
    return f == hal::PixelFormat::Gray8 || f == hal::PixelFormat::Gray10 ||
           f == hal::PixelFormat::Gray16 || f == hal::PixelFormat::Z16;
}

/// The material track's title and MP4 handler name (scene::kMaterialTitle; the receiver does not
/// depend on the scene library).
constexpr std::string_view kMaterialTitle = "material";

bool isMaterialTitle(const hal::StreamInfo &s) noexcept
{
    return equalsNoCase(s.title, kMaterialTitle);
}

bool sameMetadata(const hal::DepthMetadata &a, const hal::DepthMetadata &b) noexcept
{
    return a.nearMetres == b.nearMetres && a.farMetres == b.farMetres && a.mapping == b.mapping &&
           a.bits == b.bits;
}

} // namespace

std::uint32_t depthHoleBelow(const hal::StreamInfo &si, hal::PixelFormat decoded) noexcept
{
    const std::uint32_t t = si.depth.occupancy;
    if (t == 0)
        return 0;
    const int bits = si.depth.bits > 0                       ? si.depth.bits
                     : si.format == hal::PixelFormat::Gray10 ? 10
                     : si.format == hal::PixelFormat::Gray16 ? 16
                                                             : 8;
    if (decoded == hal::PixelFormat::Gray16)
        return depth::widenedThreshold(t, bits);
    // Narrowed to 8 bits (the top byte): the smallest 8-bit value whose source reaches t.
    const int drop = std::max(0, bits - 8);
    return std::min<std::uint32_t>(255u, (t + (1u << drop) - 1u) >> drop);
}

bool hasDepthMetadata(const hal::DepthMetadata &d) noexcept
{
    return d.nearMetres > 0.0 || d.farMetres > 0.0 || !d.mapping.empty() || d.bits > 0 ||
           d.occupancy > 0;
}

StreamRoles identifyStreams(const hal::MediaInfo &info, SingleStream single)
{
    StreamRoles r;
    const auto &streams = info.streams;
    const std::size_t n = streams.size();
    if (n == 0)
        return r;
    if (n == 1) {
        const hal::StreamInfo &s = streams[0];
        if (isMaterialTitle(s)) { // materials without depth: nothing to play
            r.material = s.index;
            r.materialReason = *s.titleFrom != '\0' ? s.titleFrom : "title";
            r.notes.push_back("stream 0 is a material track: no color or depth stream");
            return r;
        }
        bool depth = false;
        if (single == SingleStream::Depth)
            depth = true;
        else if (single == SingleStream::Auto)
            depth =
                equalsNoCase(s.title, "depth") || (!equalsNoCase(s.title, "color") &&
                                                   (isGray(s.format) || hasDepthMetadata(s.depth)));
        if (depth) {
            r.depth = s.index;
            r.depthReason = "only stream";
        } else {
            r.color = s.index;
            r.colorReason = "only stream";
        }
        return r;
    }

    std::vector<bool> taken(n, false);
    const auto assign = [&](int &role, const char *&reason, std::size_t i, const char *why) {
        if (role >= 0 || taken[i])
            return;
        role = streams[i].index;
        reason = why;
        taken[i] = true;
    };
    // 1. Titles (an MKV title, an MP4 handler name, DepthTouch's MPEG-TS service). Every stream
    // titled `material` is taken here, so none can become color or depth below.
    for (std::size_t i = 0; i < n; ++i) {
        const char *from = *streams[i].titleFrom != '\0' ? streams[i].titleFrom : "title";
        if (equalsNoCase(streams[i].title, "color") || equalsNoCase(streams[i].title, "colour"))
            assign(r.color, r.colorReason, i, from);
        else if (equalsNoCase(streams[i].title, "depth"))
            assign(r.depth, r.depthReason, i, from);
        else if (isMaterialTitle(streams[i])) {
            if (r.material < 0)
                assign(r.material, r.materialReason, i, from);
            else
                taken[i] = true; // a second material track: ignored below
        }
    }
    // 2. Depth metadata of the stream's own (tags every stream shares are the container's).
    bool allShare = true;
    for (std::size_t i = 1; i < n; ++i)
        allShare = allShare && sameMetadata(streams[i].depth, streams[0].depth);
    if (!allShare)
        for (std::size_t i = 0; i < n; ++i)
            if (hasDepthMetadata(streams[i].depth))
                assign(r.depth, r.depthReason, i, "depth metadata");
    // 3. Gray pixel format.
    for (std::size_t i = 0; i < n; ++i)
        if (isGray(streams[i].format))
            assign(r.depth, r.depthReason, i, "gray pixel format");
    // 4. Stream order.
    for (std::size_t i = 0; i < n; ++i)
        if (!isGray(streams[i].format))
            assign(r.color, r.colorReason, i, "stream order");
    if (r.color >= 0)
        for (std::size_t i = 0; i < n; ++i)
            if (r.depth < 0 && !taken[i]) {
                assign(r.depth, r.depthReason, i, "stream order");
                r.notes.push_back("stream " + std::to_string(streams[i].index) +
                                  " taken as depth by stream order (no title, metadata or gray "
                                  "format says so)");
            }
    // 5. Material by stream order: an untitled RGB 4:4:4 stream after a known color and depth.
    if (r.color >= 0 && r.depth >= 0 && r.material < 0)
        for (std::size_t i = 0; i < n; ++i)
            if (!taken[i] && streams[i].title.empty() &&
                streams[i].format == hal::PixelFormat::Rgb24) {
                assign(r.material, r.materialReason, i, "stream order");
                r.notes.push_back("stream " + std::to_string(streams[i].index) +
                                  " taken as the material track by stream order (RGB 4:4:4 after "
                                  "color and depth, untitled)");
            }
    for (std::size_t i = 0; i < n; ++i)
        if (!taken[i] || (isMaterialTitle(streams[i]) && streams[i].index != r.material))
            r.notes.push_back(
                "stream " + std::to_string(streams[i].index) + " (" +
                (streams[i].title.empty() ? std::string("untitled") : streams[i].title) +
                ") ignored: an extra video stream");
    return r;
}

} // namespace depthtouch::receiver
