#pragma once
/// \file
/// \brief The chroma format of an H.264 stream, read from its sequence parameter set. libavcodec
/// reports a 4:0:0 (monochrome) stream as yuv420p/yuvj420p (its parser and decoder fill neutral
/// chroma) and has no public field for chroma_format_idc, so the first SPS of the codec
/// parameters' extradata (avcC or Annex B) is read here: only up to chroma_format_idc (ITU-T H.264
/// 7.3.2.1.1). Private to drivers/ffmpeg. Thread-safety: reentrant.

#include <cstddef>
#include <cstdint>

namespace depthtouch::drivers::ffmpeg {

/// \brief Reads chroma_format_idc from the first SPS in \a extradata (an avcC record, or Annex B
/// NAL units with start codes). \return 0 (4:0:0 monochrome), 1 (4:2:0), 2 (4:2:2), 3 (4:4:4); -1
/// when there is no SPS or it is
///         truncated or malformed.
int h264ChromaFormatIdc(const std::uint8_t *extradata, std::size_t size) noexcept;

} // namespace depthtouch::drivers::ffmpeg
