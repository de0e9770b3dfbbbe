#pragma once
/// \file
/// \brief One rendition of an HLS multivariant playlist (`encode --renditions`): libavformat's
/// HLS demuxer lists every variant's streams as a program of their own and fetches the segments
/// of every variant whose streams are not discarded. The media source keeps one variant, by the
/// `rendition` option, and discards the others' streams, so that only its segments are fetched
/// and the stream roles (color, depth, material) are read within it; with `auto` it may change
/// variant while reading (rendition_switch.h).
/// Thread-safety: reentrant (one format context per call).

#include <string_view>
#include <vector>

#include "depthtouch/hal/media_source.h"
#include "depthtouch/platform/result.h"

struct AVFormatContext;

namespace depthtouch::drivers::ffmpeg {

/// \brief Which variant the `rendition` option asks for.
struct RenditionChoice {
    /// 0: the tallest variant (`highest`, the default); -1: the shortest (`lowest`); > 0: the
    /// tallest variant at most this many pixels high, else the shortest.
    int maxHeight = 0;
    /// `auto` (the default): start at the tallest and change with the throughput while reading
    /// (rendition_switch.h).
    bool automatic = false;
};

/// \brief Parses `auto`, `highest`, `lowest` or a height in pixels (1..8192).
/// \return the choice; Errc::InvalidArgument for anything else.
Result<RenditionChoice> parseRenditionChoice(std::string_view text);

/// \brief Keeps one variant of \a ctx when its demuxer is HLS and it lists more than one program:
/// every stream outside the chosen program gets AVDISCARD_ALL. A variant's height is its tallest
/// video stream's; ties go to the higher `variant_bitrate`; a variant without a video stream (its
/// playlist did not answer: libavformat lists it with no streams) is kept only when all are so.
/// Call after avformat_find_stream_info()
/// (the sizes are not known before; it reads the first segment of every variant): from then on
/// the demuxer fetches the kept variant's segments alone.
/// \param[out] renditions every variant, in ctx->programs' order, the kept one marked; cleared
/// when nothing was discarded.
/// \return the chosen program's index in ctx->programs, or -1 when nothing was discarded.
int keepOneVariant(AVFormatContext &ctx, const RenditionChoice &choice,
                   std::vector<hal::RenditionInfo> &renditions);

} // namespace depthtouch::drivers::ffmpeg
