#pragma once
/// \file
/// \brief The tags of an FFmpeg input's streams that DepthTouch reads: the depth planes, mapping,
/// bits and occupancy, stream roles, and the MPEG-TS service name of files written before the
/// timed metadata stream (timed_metadata_reader.h). Thread-safety: pure functions.

#include <cstdint>

extern "C" {
#include <libavformat/avformat.h>
}

namespace depthtouch::drivers {

/// \return the value of tag \a key (any case) of the stream, else of the container, else of
/// DepthTouch's MPEG-TS tags \a service (its timed metadata, or the service name of older files);
/// nullptr when none has it.
const char *tagOf(const AVStream &st, const AVFormatContext &fmt, const AVDictionary *service,
                  const char *key) noexcept;

/// \return the tags DepthTouch's MPEG-TS muxer wrote into the service name before its timed
/// metadata stream ("key=value;…", service provider "DepthTouch"), parsed with
/// av_dict_parse_string; nullptr for any other input. The caller frees it (av_dict_free).
AVDictionary *serviceTagsOf(const AVFormatContext &fmt) noexcept;

/// \return whether \a text names a stream role DepthTouch writes ("color", "depth" or "material":
/// an MP4 handler name that counts as the stream title).
bool isRoleName(const char *text) noexcept;

/// \return \a text as a positive finite number, else 0 (absent or nonsense).
double tagDouble(const char *text) noexcept;

/// \return the depth_bits tag: 1..16, else 0 (absent or nonsense such as "inf").
int tagBits(const char *text) noexcept;

/// \return the depth_occupancy tag: a whole number 1..65535, else 0 (absent, or not a whole number
/// in range: no holes).
std::uint32_t tagOccupancy(const char *text) noexcept;

} // namespace depthtouch::drivers
