#pragma once
/// \file
/// \brief The depth metadata of a DepthTouch MPEG-TS input from its timed ID3 stream (the sender's
/// side: app/media/src/timed_metadata.h): the tags of the first ID3 packet, read ahead of the
/// first frames at open. Files written before that stream existed carry the tags in the service
/// name instead (ffmpeg_media_source.cpp reads both).
///
/// Thread-safety: the caller's thread (the media source's).

#include <cstdint>
#include <deque>
#include <functional>

extern "C" {
#include <libavformat/avformat.h>
}

#include "depthtouch/av/av_handles.h"

namespace depthtouch::drivers {

/// Packets read ahead of the ID3 tag, delivered before anything else is read.
using PendingPackets = std::deque<av::PacketPtr>;

/// \brief When \a fmt has a timed ID3 stream (AV_CODEC_ID_TIMED_ID3), reads packets until its
/// first one, at most \a maxPackets; every other packet read goes to the back of \a pending.
/// \a beforeRead runs before each av_read_frame() (the I/O deadline).
/// \return the TXXX frames of that tag as a dictionary (description → text; the caller frees it
/// with av_dict_free), or nullptr: no such stream, no tag within \a maxPackets, a read error (it
/// comes again at the next read) or a tag without TXXX frames.
AVDictionary *readTimedMetadata(AVFormatContext &fmt, PendingPackets &pending, int maxPackets,
                                const std::function<void()> &beforeRead);

/// \return the TXXX frames of the ID3v2 tag in \a data (\a size bytes) as a dictionary, or
/// nullptr (not an ID3v2 tag, or no TXXX frame). TagLib reads the tag.
AVDictionary *textTagsOfId3(const std::uint8_t *data, int size);

} // namespace depthtouch::drivers
