#pragma once
/// \file
/// \brief The depth stream's metadata in a GStreamer pipeline: DepthTouch's depth tags
/// (docs/architecture.md §4: depth_near, depth_far, depth_mapping, depth_bits, depth_occupancy) as
/// a demuxer hands them on. matroskademux passes a Matroska stream tag it has no GStreamer name for
/// as an extended comment "KEY=value" (GST_TAG_EXTENDED_COMMENT: "DEPTH_NEAR=0.5"), in a
/// GST_EVENT_TAG on the stream's pad, which decoders forward. The values are read by
/// hal::applyDepthTag() (hal/depth_tags.h), as the FFmpeg media source reads them, so a file gives
/// the same hal::DepthMetadata to `play` and to the GStreamer elements.
///
/// Thread-safety: pure functions.

#include <cstdint>
#include <string_view>

#include "depthtouch/hal/media_source.h"
#include "depthtouch/scene/depth_frame.h"

namespace depthtouch::gst {

/// \brief Reads one "key=value" text (an extended comment; the key in any case, spaces around
/// either part ignored) into \a md when the key is one of the depth tags and the value is valid.
/// \return true when \a md took the value.
bool applyDepthTag(std::string_view text, hal::DepthMetadata &md) noexcept;

/// \return the hole threshold (scene::DepthFrameView::holeBelow, docs/architecture.md §3
/// "Holes") of frames of \a format carrying a stream with \a md: its depth_occupancy widened to
/// 16 bits or narrowed to 8 as the receiver does (receiver::depthHoleBelow(), the same function);
/// 0 without depth_occupancy.
std::uint32_t holeBelowFor(const hal::DepthMetadata &md, scene::SampleFormat format) noexcept;

} // namespace depthtouch::gst
