#pragma once
/// \file
/// \brief Pieces shared by the FFmpeg media source and decoder: error mapping, codec and
/// pixel-format mapping, and the copy of a decoded AVFrame into a tightly packed hal::ImageView
/// (the RAII owners of the libav* handles are dt_av_handles'). Private to drivers/ffmpeg.
/// Thread-safety: reentrant functions.

#include <memory>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/frame.h>
#include <libavutil/pixfmt.h>
#include <libswscale/swscale.h>
}

#include "depthtouch/av/av_handles.h"
#include "depthtouch/hal/media_source.h"
#include "depthtouch/hal/types.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers::ffmpeg {

/// Lowers libav*'s own console logging to fatal messages once per process (our errors say what
/// failed; a corrupt stream would otherwise print a line per damaged slice).
void quietLibav() noexcept;

/// \brief Discards (AVDISCARD_ALL) the data and unknown streams of \a ctx, but timed ID3
/// metadata (the MPEG-TS tags: timed_metadata_reader.h). Call before avformat_find_stream_info():
/// while it probes the codec of an MPEG-TS private-data PID (stream type 0x06), libavformat holds
/// every packet of the input back until 2 500 packets of that PID or `probesize` bytes came,
/// which a live input with a sparse PID takes minutes to send; the demuxer skips a discarded PID.
/// \return how many streams were discarded.
int discardDataStreams(AVFormatContext &ctx) noexcept;

/// \return the HAL code of a libav* error \a err (AVERROR(...)); \a fallback for the unknown ones.
Errc errcOf(int err, Errc fallback) noexcept;

/// \return the HAL codec of \a id (Unknown when the HAL has no name for it).
hal::CodecId codecOf(AVCodecID id) noexcept;
/// \return the libavcodec id of \a codec (AV_CODEC_ID_NONE for Unknown and Mock).
AVCodecID avCodecOf(hal::CodecId codec) noexcept;

/// \return the HAL format a stream of libav format \a fmt and kind \a kind decodes to: gray
/// formats stay gray (Gray8/Gray10/Gray16), a depth stream in a YUV format is its luma plane
/// (Gray8, or Gray16 when deeper than 8 bits), color is Yuv420p when the stream is 4:2:0 8-bit,
/// else Rgb24. Unknown for AV_PIX_FMT_NONE.
hal::PixelFormat halFormatOf(AVPixelFormat fmt, hal::StreamKind kind) noexcept;
/// \return the native-endian libav format of \a format (AV_PIX_FMT_NONE when it has none).
AVPixelFormat avFormatOf(hal::PixelFormat format) noexcept;

/// \brief Copies \a src into \a dst (allocated by the caller: dst.width/height/format set, planes
/// valid). Gray targets take the first plane as is (luma of YUV, no range conversion, which would
/// corrupt depth); gray16be is byte-swapped; other mismatches go through libswscale (\a sws caches
/// its context). \return InvalidArgument when the sizes differ or the conversion is impossible.
Result<void> copyFrame(const AVFrame &src, const hal::ImageView &dst, av::SwsPtr &sws) noexcept;

} // namespace depthtouch::drivers::ffmpeg
