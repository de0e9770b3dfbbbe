/// \file
/// \brief identifyInputStreams(): see encode_inputs.h.

#include "encode_inputs.h"

#include <array>
#include <charconv>
#include <cstddef>
#include <system_error>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/platform/file_access.h"

namespace depthtouch::cli {

namespace {

/// \return \a v as the shortest text that reads back as \a v ("2.26", not "2.2599999999999998").
std::string shortest(double v)
{
    std::array<char, 32> buf{};
    const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    return ec == std::errc{} ? std::string(buf.data(), end) : std::string();
}

} // namespace

bool InputStreams::depthTouch() const noexcept
{
    return depth >= 0 && receiver::hasDepthMetadata(depthStream.depth);
}

int InputStreams::streamOf(std::string_view role) const noexcept
{
    if (role == "color")
        return color;
    if (role == "depth")
        return depth;
    if (role == "material")
        return material;
    return -1;
}

std::vector<std::pair<std::string, std::string>> InputStreams::depthTags() const
{
    std::vector<std::pair<std::string, std::string>> tags;
    if (!depthTouch())
        return tags;
    const hal::DepthMetadata &d = depthStream.depth;
    if (d.nearMetres > 0.0)
        tags.emplace_back("depth_near", shortest(d.nearMetres));
    if (d.farMetres > 0.0)
        tags.emplace_back("depth_far", shortest(d.farMetres));
    if (!d.mapping.empty())
        tags.emplace_back("depth_mapping", d.mapping);
    if (d.bits > 0)
        tags.emplace_back("depth_bits", std::to_string(d.bits));
    if (d.occupancy > 0)
        tags.emplace_back("depth_occupancy", std::to_string(d.occupancy));
    return tags;
}

std::optional<InputStreams> identifyInputStreams(const std::string &spec,
                                                 receiver::SingleStream single)
{
    if (platform::pathKind(spec.c_str()) != platform::PathKind::Regular)
        return std::nullopt;
    auto source = drivers::createMediaSource("ffmpeg", hal::BackendConfig{});
    if (!source || !(*source)->open(spec.c_str()))
        return std::nullopt;
    const hal::MediaInfo &info = (*source)->info();
    const receiver::StreamRoles roles = receiver::identifyStreams(info, single);
    const auto containerIndex = [&info](int halIndex) {
        return halIndex >= 0 ? info.streams[static_cast<std::size_t>(halIndex)].containerIndex : -1;
    };
    InputStreams s;
    s.color = containerIndex(roles.color);
    s.depth = containerIndex(roles.depth);
    s.material = containerIndex(roles.material);
    if (roles.depth >= 0)
        s.depthStream = info.streams[static_cast<std::size_t>(roles.depth)];
    return s;
}

} // namespace depthtouch::cli
