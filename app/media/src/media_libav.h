#pragma once
/// \file
/// \brief Private to dt_media: RAII owners of libav handles and small libav helpers shared by the
/// frame sources, the encoders and the muxer. Thread-safety: reentrant.

#include <cstdint>
#include <memory>
#include <string>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/dict.h>
#include <libavutil/error.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

#include "depthtouch/av/av_handles.h"
#include "depthtouch/media/image.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::media::detail {

// The owners shared with the drivers that call FFmpeg (dt_av_handles).
using av::CodecContextPtr;
using av::dejpeg;
using av::FramePtr;
using av::InputContextPtr;
using av::PacketPtr;
using av::setSwsRanges;
using av::SwsPtr;

struct AvioDeleter {
    void operator()(AVIOContext *io) const noexcept { avio_closep(&io); }
};
struct DictDeleter {
    void operator()(AVDictionary *d) const noexcept { av_dict_free(&d); }
};
using AvioPtr = std::unique_ptr<AVIOContext, AvioDeleter>;

/// FFmpeg's message for \a err (av_err2str is a C compound literal, unusable in C++).
struct AvErrorText {
    char text[AV_ERROR_MAX_STRING_SIZE] = {};
    explicit AvErrorText(int err) noexcept { av_strerror(err, text, sizeof text); }
};

/// The errno behind an AVERROR(errno) code, 0 for FFmpeg's own codes.
inline int errnoOf(int averr) noexcept
{
    return averr < 0 && averr > -4096 ? -averr : 0;
}

/// Keeps FFmpeg's own log quiet (fatal messages only; errors too when DT_LOG is set): our errors
/// carry the message. Idempotent, thread-safe.
void quietFfmpegLog() noexcept;

/// \brief Opens \a url with libavformat (its own format probing, no options), reads the
/// information of its streams and finds its best audio stream.
/// \param[out] in The input, once it opens.
/// \param[out] index Its best audio stream, -1 when it has none.
/// \return Errc::InvalidArgument with the message \a notOpened when it does not open, with
/// \a noStreams when its streams cannot be read (both static strings).
Result<void> openAudioInput(const std::string &url, InputContextPtr &in, int &index,
                            const char *notOpened, const char *noStreams);

/// \brief Sets every stream of \a ctx but \a keep to AVDISCARD_ALL: the demuxer drops their
/// packets.
void discardOtherStreams(AVFormatContext &ctx, int keep) noexcept;

/// \return "<codec> <rate> Hz <channels> ch" of the audio stream \a par, e.g. "aac 48000 Hz 2 ch".
std::string audioDescription(const AVCodecParameters &par);

/// \return the Image layout closest to a decoded frame's format \a f.
PixelFormat nativeLayout(AVPixelFormat f) noexcept;

/// \return the AVPixelFormat of an Image layout (GRAY16 in native byte order).
AVPixelFormat toAvFormat(PixelFormat f) noexcept;

/// \brief A cached libswscale context for one conversion (size and formats); rebuilt when they
/// change. Same-size conversions are bit-exact and deterministic (SWS_BITEXACT | ACCURATE_RND).
class Scaler {
public:
    /// Converts \a src (any format and size, full-range flag honoured) into the caller's buffer
    /// \a dstData / \a dstStride of format \a dstFmt and size \a dstW × \a dstH (bicubic when
    /// the size differs). \return Errc::NotSupported when libswscale has no such conversion,
    /// Errc::InvalidArgument when it fails.
    Result<void> convert(const AVFrame &src, std::uint8_t *const dstData[4], const int dstStride[4],
                         AVPixelFormat dstFmt, int dstW, int dstH);

private:
    SwsPtr sws_;
    int srcW_ = 0, srcH_ = 0, dstW_ = 0, dstH_ = 0;
    AVPixelFormat srcFmt_ = AV_PIX_FMT_NONE, dstFmt_ = AV_PIX_FMT_NONE;
    bool srcFull_ = false;
};

} // namespace depthtouch::media::detail
