#pragma once
/// \file
/// \brief The depth metadata of an MPEG-TS or HLS output as timed ID3: a data stream (stream type
/// 0x15, metadata format "ID3 ", ISO/IEC 13818-1 §2.6.58-2.6.61) whose packets are an ID3v2.4 tag
/// of one TXXX frame per tag (key as the description, UTF-8), as HLS carries timed metadata
/// (Apple, "Timed Metadata for HTTP Live Streaming"). A tag goes out with the first key frame of
/// the output's first stream (color) and again with each later one, so a receiver that tunes in
/// at a key frame finds it within the same GOP. MPEG-TS has no free container tags; the service
/// name, which a TV shows as the channel's name, says only "DepthTouch".
///
/// Thread-safety: as Muxer (one thread).

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "media_libav.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::media {

/// See the file comment.
class TimedMetadata {
public:
    /// \brief Adds the data stream to \a fmt, after the streams already there (their indices stay).
    /// \return the writer; Errc::OutOfResources when the stream cannot be made.
    static Result<TimedMetadata> add(AVFormatContext &fmt,
                                     const std::vector<std::pair<std::string, std::string>> &tags);

    /// \brief When \a pkt (about to be written, its timestamps in its stream's time base) is a
    /// key frame of stream 0, \return the tag's packet to write before it (at the same time), else
    /// nullptr. \pre the header is written. The packet is this object's until the next call.
    AVPacket *packetBefore(const AVFormatContext &fmt, const AVPacket &pkt);

private:
    TimedMetadata() = default;
    int stream_ = -1;
    std::vector<std::uint8_t> tag_;
    std::int64_t lastPts_ = AV_NOPTS_VALUE; ///< Of the last tag written (data stream's time base).
    av::PacketPtr packet_;
};

} // namespace depthtouch::media
