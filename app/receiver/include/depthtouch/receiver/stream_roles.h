#pragma once
/// \file
/// \brief Which video stream of a 3D video is the color video, which the depth video and which the
/// optional material track (per-pixel haptic material on the depth grid, scene/material.h).
///
/// Rules, in order (docs/architecture.md §4): the stream title `color` / `depth` / `material`
/// (case-insensitive; an MP4 handler name counts as a title); then the depth metadata tags (a
/// stream with depth_near / depth_far / depth_mapping / depth_bits of its own when not every stream
/// carries them); then a gray pixel format (gray, gray10, gray16: depth); the first remaining
/// stream is color and, when color is known, the next remaining one is depth (stream order,
/// reported). With color and depth both known and no stream titled `material`, the next remaining
/// untitled stream that decodes as RGB 4:4:4 (hal::PixelFormat::Rgb24, e.g. H.264 gbrp) is the
/// material track (stream order, reported). A stream titled `material` is never taken as color or
/// depth. A single stream is depth-only or color-only: by the caller's preference, else depth when
/// gray and color otherwise (a single stream titled `material` is neither). Further video streams
/// are ignored (reported). Thread-safety: reentrant.

#include <cstdint>
#include <string>
#include <vector>

#include "depthtouch/hal/media_source.h"

namespace depthtouch::receiver {

/// What the caller wants from a single-stream input.
enum class SingleStream : std::uint8_t {
    Auto,  ///< Gray pixel format: depth-only; otherwise color-only.
    Depth, ///< Depth-only (`touch`: a gray H.264 file decodes as 4:2:0 and would look like color).
    Color, ///< Color-only.
};

/// The chosen streams (MediaInfo indices, -1 when absent) and why.
struct StreamRoles {
    int color = -1;
    int depth = -1;
    int material = -1; ///< The material track (scene/material.h); -1 when the input has none.
    /// Why: "title", "MP4 handler name", "MPEG-TS service", "gray pixel format", "stream order"…
    const char *colorReason = "";
    const char *depthReason = "";    ///< The same for depth.
    const char *materialReason = ""; ///< "title", "MP4 handler name" or "stream order".
    std::vector<std::string> notes; ///< Assumptions and ignored streams, one sentence each.
};

/// \return whether \a d carries any depth metadata tag.
bool hasDepthMetadata(const hal::DepthMetadata &d) noexcept;

/// \return the hole threshold (scene::DepthFrameView::holeBelow, docs/architecture.md §3 "Holes")
/// of the depth frames of stream \a si decoded as \a decoded (Gray8, or Gray16 widened by bit
/// replication), in their units: the stream's depth_occupancy in its own bits (the depth_bits tag,
/// else its pixel format), widened as the samples are (depth::widenedThreshold(): the smallest
/// 16-bit value whose source is at or above the threshold), or narrowed to the top byte (the
/// smallest 8-bit value whose source reaches it). 0 when the stream has no depth_occupancy.
std::uint32_t depthHoleBelow(const hal::StreamInfo &si, hal::PixelFormat decoded) noexcept;

/// \return the roles of the streams of \a info (see the file comment); both -1 when it has none.
StreamRoles identifyStreams(const hal::MediaInfo &info, SingleStream single = SingleStream::Auto);

} // namespace depthtouch::receiver
