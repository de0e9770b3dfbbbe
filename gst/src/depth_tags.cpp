/// \file
/// \brief The depth tags of a GStreamer stream: see depth_tags.h.

#include "depth_tags.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <string>

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

/// \return whether \a a equals \a b ignoring ASCII case.
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

/// \return \a text as a positive finite number, else 0 (stream_tags.h's tagDouble()).
double positiveNumber(std::string_view text) noexcept
{
    double v = 0.0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v) || v <= 0.0)
        return 0.0;
    return v;
}

/// \return \a text as a whole number in [lo, hi], else 0.
std::uint32_t wholeNumber(std::string_view text, std::uint32_t lo, std::uint32_t hi) noexcept
{
    std::uint32_t v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || v < lo || v > hi)
        return 0;
    return v;
}

} // namespace

bool applyDepthTag(std::string_view text, hal::DepthMetadata &md) noexcept
{
    const std::size_t eq = text.find('=');
    if (eq == std::string_view::npos)
        return false;
    const std::string_view key = trim(text.substr(0, eq));
    const std::string_view value = trim(text.substr(eq + 1));
    if (equalsNoCase(key, "depth_near") || equalsNoCase(key, "depth_far")) {
        const double v = positiveNumber(value);
        if (v <= 0.0)
            return false;
        (equalsNoCase(key, "depth_near") ? md.nearMetres : md.farMetres) = v;
        return true;
    }
    if (equalsNoCase(key, "depth_mapping")) {
        if (value.empty())
            return false;
        md.mapping = std::string(value);
        return true;
    }
    if (equalsNoCase(key, "depth_bits")) {
        const std::uint32_t bits = wholeNumber(value, 1, 16);
        if (bits == 0)
            return false;
        md.bits = static_cast<int>(bits);
        return true;
    }
    if (equalsNoCase(key, "depth_occupancy")) {
        const std::uint32_t t = wholeNumber(value, 1, 65535);
        if (t == 0)
            return false;
        md.occupancy = t;
        return true;
    }
    return false;
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
