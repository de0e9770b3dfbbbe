#pragma once
/// \file
/// \brief Image sequences through the media source: a still-image codec (PNG, JPEG, …) has no
/// video decoder backend, so the source decodes each image itself and delivers it as a tightly
/// packed RawVideo packet (hal::CodecId::RawVideo) of the stream's size and format.
/// Thread-safety: thread-bound (the source's reading thread), like the decoder context passed in.

#include <cstdint>
#include <vector>

#include "ffmpeg_common.h"

namespace depthtouch::drivers::ffmpeg {

/// \return an opened decoder for the still-image stream \a par, or null when libavcodec has none
/// or refuses it.
av::CodecContextPtr openStillImageDecoder(const AVCodecParameters &par) noexcept;

/// \brief Decodes the one image of \a packet with \a dec into \a raw: \a si's format and size,
/// tightly packed (hal::planeLayout()), converted by libswscale (\a sws, cached) when the decoded
/// layout differs. \a frame is scratch.
/// \return Errc::Io when the image does not decode, or is of another size or format than libswscale
/// converts to \a si's.
Result<void> decodeStillImage(AVCodecContext &dec, const AVPacket &packet, AVFrame &frame,
                              const hal::StreamInfo &si, std::vector<std::uint8_t> &raw,
                              av::SwsPtr &sws);

} // namespace depthtouch::drivers::ffmpeg
