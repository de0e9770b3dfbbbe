#pragma once
/// \file
/// \brief The tags of an FFmpeg input's streams that DepthTouch reads: where the depth tags are
/// found (their values are read by hal/depth_tags.h), stream roles, and the MPEG-TS service name
/// of files written before the timed metadata stream (timed_metadata_reader.h). Thread-safety:
/// pure functions.

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

} // namespace depthtouch::drivers
