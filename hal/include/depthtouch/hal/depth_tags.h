#pragma once
/// \file
/// \brief DepthTouch's depth tags (docs/architecture.md §3: depth_near, depth_far, depth_mapping,
/// depth_bits, depth_occupancy), read into hal::DepthMetadata by one set of rules for every source
/// that carries them: the FFmpeg media source (container and stream tags, DepthTouch's MPEG-TS
/// metadata) and the GStreamer elements (a demuxer's extended comments), so that a file gives
/// the same metadata to `play` and to a pipeline.
///
/// Thread-safety: pure functions.

#include <array>

#include "depthtouch/hal/media_source.h"

namespace depthtouch::hal {

/// The depth tags' names, as `encode` writes them (lower case; readers compare in any case).
inline constexpr std::array<const char *, 5> kDepthTagNames = {
    "depth_near", "depth_far", "depth_mapping", "depth_bits", "depth_occupancy"};

/// \brief Reads the value \a value of tag \a key (one of kDepthTagNames, in any case) into the
/// field of \a md it names. The rules: depth_near and depth_far a positive finite number (m; a
/// unit after it is ignored, strtod), depth_bits 1..16, depth_occupancy a whole number
/// 1..65535, depth_mapping any non-empty text. \return true when \a md took the value; false, with
/// \a md unchanged, for another key, a null or empty value, or nonsense ("inf", "-1", "1.5"
/// occupancy).
bool applyDepthTag(const char *key, const char *value, DepthMetadata &md) noexcept;

} // namespace depthtouch::hal
