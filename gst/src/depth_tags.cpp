/// \file
/// \brief The depth tags of a GStreamer stream: see depth_tags.h.

#include "depth_tags.h"

#include <cctype>
#include <string>

#include "depthtouch/hal/depth_tags.h"
#include "depthtouch/receiver/stream_roles.h"

namespace depthtouch::gst {

namespace {

/// \return \a s without the spaces around it.
std::string_view trim(std::string_view s) noexcept
{
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())) != 0)
        s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())) != 0)
        s.remove_suffix(1);
    return s;
}

} // namespace

bool applyDepthTag(std::string_view text, hal::DepthMetadata &md) noexcept
{
    const std::size_t eq = text.find('=');
    if (eq == std::string_view::npos)
        return false;
    try {
        const std::string key(trim(text.substr(0, eq)));
        const std::string value(trim(text.substr(eq + 1)));
        return hal::applyDepthTag(key.c_str(), value.c_str(), md);
    } catch (...) { // std::bad_alloc: the tag is not read
        return false;
    }
}

std::uint32_t holeBelowFor(const hal::DepthMetadata &md, scene::SampleFormat format) noexcept
{
    hal::StreamInfo si;
    si.kind = hal::StreamKind::Depth;
    si.depth = md;
    const hal::PixelFormat decoded =
        format == scene::SampleFormat::Gray16 ? hal::PixelFormat::Gray16 : hal::PixelFormat::Gray8;
    si.format = decoded; // the stream's own bits when it has no depth_bits tag
    return receiver::depthHoleBelow(si, decoded);
}

} // namespace depthtouch::gst
