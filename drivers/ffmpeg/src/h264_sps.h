#pragma once
/// \file
/// \brief The chroma format of an H.264 stream, read from its sequence parameter set. libavcodec
/// reports a 4:0:0 (monochrome) stream as yuv420p/yuvj420p (its parser and decoder fill neutral
/// chroma) and has no public field for chroma_format_idc, so the first SPS of the codec
/// parameters' extradata (avcC or Annex B) is read here: only up to chroma_format_idc (ITU-T H.264
/// 7.3.2.1.1); and the pixel format the samples of a stream so read really have. Private to
/// drivers/ffmpeg. Thread-safety: reentrant.

#include <cstddef>
#include <cstdint>

extern "C" {
#include <libavcodec/codec_par.h>
#include <libavutil/pixfmt.h>
}

namespace depthtouch::drivers::ffmpeg {

/// \brief Reads chroma_format_idc from the first SPS in \a extradata (an avcC record, or Annex B
/// NAL units with start codes). \return 0 (4:0:0 monochrome), 1 (4:2:0), 2 (4:2:2), 3 (4:4:4); -1
/// when there is no SPS or it is
///         truncated or malformed.
int h264ChromaFormatIdc(const std::uint8_t *extradata, std::size_t size) noexcept;

/// \return the pixel format a stream's samples really have: an H.264 stream whose SPS says 4:0:0
/// (monochrome) is gray (8, 10 or 16 bits by its luma depth), though libavcodec reports it as
/// yuv(j)420p with neutral chroma; any other stream's own format.
AVPixelFormat samplesFormatOf(const AVCodecParameters &par) noexcept;

/// \return whether \a f is one of libavutil's gray formats (8, 10 or 16 bits, either order).
bool isGray(AVPixelFormat f) noexcept;

} // namespace depthtouch::drivers::ffmpeg
