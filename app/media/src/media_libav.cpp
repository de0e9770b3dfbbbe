/// \file
/// \brief Shared libav helpers of dt_media (see media_libav.h).

#include "media_libav.h"

#include <cstdlib>
#include <mutex>

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Media)

namespace depthtouch::media::detail {

void quietFfmpegLog() noexcept
{
    static std::once_flag once;
    std::call_once(once, [] {
        av_log_set_level(std::getenv("DT_LOG") != nullptr ? AV_LOG_ERROR : AV_LOG_FATAL);
    });
}

Result<void> openAudioInput(const std::string &url, InputContextPtr &in, int &index,
                            const char *notOpened, const char *noStreams)
{
    AVFormatContext *ctx = nullptr;
    if (avformat_open_input(&ctx, url.c_str(), nullptr, nullptr) < 0)
        return unexpected(Errc::InvalidArgument, notOpened);
    in.reset(ctx);
    if (avformat_find_stream_info(ctx, nullptr) < 0)
        return unexpected(Errc::InvalidArgument, noStreams);
    index = av_find_best_stream(ctx, AVMEDIA_TYPE_AUDIO, -1, -1, nullptr, 0);
    return ok();
}

void discardOtherStreams(AVFormatContext &ctx, int keep) noexcept
{
    for (unsigned i = 0; i < ctx.nb_streams; ++i)
        if (static_cast<int>(i) != keep)
            ctx.streams[i]->discard = AVDISCARD_ALL;
}

std::string audioDescription(const AVCodecParameters &par)
{
    return std::string(avcodec_get_name(par.codec_id)) + " " + std::to_string(par.sample_rate) +
           " Hz " + std::to_string(par.ch_layout.nb_channels) + " ch";
}

PixelFormat nativeLayout(AVPixelFormat f) noexcept
{
    const AVPixFmtDescriptor *d = av_pix_fmt_desc_get(f);
    if (d == nullptr)
        return PixelFormat::Rgb24;
    const bool hasAlpha = (d->flags & AV_PIX_FMT_FLAG_ALPHA) != 0;
    const bool gray = (d->flags & (AV_PIX_FMT_FLAG_PAL | AV_PIX_FMT_FLAG_RGB)) == 0 &&
                      d->nb_components == (hasAlpha ? 2 : 1);
    if (!gray)
        return PixelFormat::Rgb24;
    return d->comp[0].depth > 8 ? PixelFormat::Gray16 : PixelFormat::Gray8;
}

AVPixelFormat toAvFormat(PixelFormat f) noexcept
{
    switch (f) {
    case PixelFormat::Gray8:
        return AV_PIX_FMT_GRAY8;
    case PixelFormat::Gray16:
        return AV_PIX_FMT_GRAY16; // native byte order
    case PixelFormat::Rgb24:
        return AV_PIX_FMT_RGB24;
    }
    return AV_PIX_FMT_NONE;
}

Result<void> Scaler::convert(const AVFrame &src, std::uint8_t *const dstData[4],
                             const int dstStride[4], AVPixelFormat dstFmt, int dstW, int dstH)
{
    bool full = false;
    const AVPixelFormat srcFmt = dejpeg(static_cast<AVPixelFormat>(src.format), full);
    full = full || src.color_range == AVCOL_RANGE_JPEG;
    if (!sws_ || src.width != srcW_ || src.height != srcH_ || srcFmt != srcFmt_ ||
        full != srcFull_ || dstW != dstW_ || dstH != dstH_ || dstFmt != dstFmt_) {
        const bool sameSize = src.width == dstW && src.height == dstH;
        // Same size: SWS_POINT only selects the cheapest unscaled path; BITEXACT + ACCURATE_RND
        // keep it deterministic across CPUs. Resizing: bicubic.
        const int flags = (sameSize ? SWS_POINT : SWS_BICUBIC) | SWS_BITEXACT | SWS_ACCURATE_RND;
        sws_.reset(sws_getContext(src.width, src.height, srcFmt, dstW, dstH, dstFmt, flags, nullptr,
                                  nullptr, nullptr));
        if (!sws_) {
            DT_LOG(Media, Warning, "Failed to convert %s %dx%d to %s %dx%d",
                   av_get_pix_fmt_name(srcFmt), src.width, src.height, av_get_pix_fmt_name(dstFmt),
                   dstW, dstH);
            return unexpected(Errc::NotSupported, "No pixel format conversion for this frame");
        }
        if (full)
            setSwsRanges(sws_.get(), 1);
        srcW_ = src.width;
        srcH_ = src.height;
        srcFmt_ = srcFmt;
        srcFull_ = full;
        dstW_ = dstW;
        dstH_ = dstH;
        dstFmt_ = dstFmt;
    }
    const int lines =
        sws_scale(sws_.get(), src.data, src.linesize, 0, src.height, dstData, dstStride);
    if (lines != dstH)
        return unexpected(Errc::InvalidArgument, "Failed to convert the frame's pixel format");
    return ok();
}

} // namespace depthtouch::media::detail
