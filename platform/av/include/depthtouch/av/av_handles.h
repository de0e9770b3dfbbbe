#pragma once
/// \file
/// \brief RAII owners of libav* handles (`std::unique_ptr` with the matching libav free call) and
/// the mapping of the deprecated full-range "J" YUV formats, shared by the code that calls FFmpeg
/// directly: dt_media, dt_driver_ffmpeg and dt_driver_v4l2's color converter (target
/// `dt_av_handles`, docs/architecture.md §2). Header-only; no domain knowledge.
///
/// Thread-safety: reentrant (each owner frees only its own handle; the functions are pure).

#include <memory>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/frame.h>
#include <libavutil/pixfmt.h>
#include <libswscale/swscale.h>
}

namespace depthtouch::av {

/// \brief Closes a demuxer context opened by avformat_open_input() (avformat_close_input).
struct InputContextDeleter {
    void operator()(AVFormatContext *c) const noexcept { avformat_close_input(&c); }
};
/// \brief Frees a codec context (avcodec_free_context).
struct CodecContextDeleter {
    void operator()(AVCodecContext *c) const noexcept { avcodec_free_context(&c); }
};
/// \brief Frees a frame and its references (av_frame_free).
struct FrameDeleter {
    void operator()(AVFrame *f) const noexcept { av_frame_free(&f); }
};
/// \brief Frees a packet and its reference (av_packet_free).
struct PacketDeleter {
    void operator()(AVPacket *p) const noexcept { av_packet_free(&p); }
};
/// \brief Frees a libswscale context (sws_freeContext).
struct SwsDeleter {
    void operator()(SwsContext *s) const noexcept { sws_freeContext(s); }
};

using InputContextPtr = std::unique_ptr<AVFormatContext, InputContextDeleter>;
using CodecContextPtr = std::unique_ptr<AVCodecContext, CodecContextDeleter>;
using FramePtr = std::unique_ptr<AVFrame, FrameDeleter>;
using PacketPtr = std::unique_ptr<AVPacket, PacketDeleter>;
using SwsPtr = std::unique_ptr<SwsContext, SwsDeleter>;

/// \brief The format libswscale should read for \a f: the deprecated full-range "J" YUV formats
/// (yuvj420p, yuvj422p, yuvj444p, yuvj440p, yuvj411p) become their plain twins, whose range is then
/// set on the scaler context instead.
/// \param[in] f a decoded frame's pixel format.
/// \param[out] fullRange true when \a f was a "J" format, false otherwise.
/// \return the plain format, or \a f itself when it is not a "J" format.
inline AVPixelFormat dejpeg(AVPixelFormat f, bool &fullRange) noexcept
{
    fullRange = true;
    switch (f) {
    case AV_PIX_FMT_YUVJ420P:
        return AV_PIX_FMT_YUV420P;
    case AV_PIX_FMT_YUVJ422P:
        return AV_PIX_FMT_YUV422P;
    case AV_PIX_FMT_YUVJ444P:
        return AV_PIX_FMT_YUV444P;
    case AV_PIX_FMT_YUVJ440P:
        return AV_PIX_FMT_YUV440P;
    case AV_PIX_FMT_YUVJ411P:
        return AV_PIX_FMT_YUV411P;
    default:
        fullRange = false;
        return f;
    }
}

/// \brief Sets the input range of the scaler \a s (1: full "JPEG" range, 0: limited "MPEG"
/// range) and, when \a dstRange is 0 or 1, its output range (else the output range stays); the
/// context's other colorspace details stay. Does nothing when libswscale cannot report them.
inline void setSwsRanges(SwsContext *s, int srcRange, int dstRange = -1) noexcept
{
    int *invTable = nullptr;
    int *table = nullptr;
    int oldSrcRange = 0;
    int oldDstRange = 0;
    int brightness = 0;
    int contrast = 0;
    int saturation = 0;
    if (sws_getColorspaceDetails(s, &invTable, &oldSrcRange, &table, &oldDstRange, &brightness,
                                 &contrast, &saturation) >= 0)
        sws_setColorspaceDetails(s, invTable, srcRange, table,
                                 dstRange < 0 ? oldDstRange : dstRange, brightness, contrast,
                                 saturation);
}

} // namespace depthtouch::av
