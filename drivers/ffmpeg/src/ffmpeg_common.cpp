#include "ffmpeg_common.h"

#include <cerrno>
#include <cstring>
#include <mutex>
#include <utility>

extern "C" {
#include <libavutil/imgutils.h>
#include <libavutil/log.h>
#include <libavutil/pixdesc.h>
}

namespace depthtouch::drivers::ffmpeg {

void quietLibav() noexcept
{
    static std::once_flag once;
    std::call_once(once, [] { av_log_set_level(AV_LOG_FATAL); });
}

int discardDataStreams(AVFormatContext &ctx) noexcept
{
    int discarded = 0;
    for (unsigned i = 0; i < ctx.nb_streams; ++i) {
        AVStream &st = *ctx.streams[i];
        const AVMediaType type = st.codecpar->codec_type;
        if ((type == AVMEDIA_TYPE_DATA || type == AVMEDIA_TYPE_UNKNOWN) &&
            st.codecpar->codec_id != AV_CODEC_ID_TIMED_ID3) {
            st.discard = AVDISCARD_ALL;
            ++discarded;
        }
    }
    return discarded;
}

Errc errcOf(int err, Errc fallback) noexcept
{
    if (err == AVERROR(ENOENT) || err == AVERROR(ENODEV) || err == AVERROR(ENXIO))
        return Errc::NoDevice;
    if (err == AVERROR(EACCES) || err == AVERROR(EPERM))
        return Errc::PermissionDenied;
    if (err == AVERROR_PROTOCOL_NOT_FOUND || err == AVERROR_DEMUXER_NOT_FOUND ||
        err == AVERROR_DECODER_NOT_FOUND)
        return Errc::NotSupported;
    if (err == AVERROR_INVALIDDATA || err == AVERROR_STREAM_NOT_FOUND)
        return Errc::InvalidArgument;
    if (err == AVERROR(ENOMEM))
        return Errc::OutOfResources;
    if (err == AVERROR_EOF)
        return Errc::EndOfStream;
    if (err == AVERROR_EXIT || err == AVERROR(ETIMEDOUT))
        return Errc::Timeout;
    if (err == AVERROR(EIO))
        return Errc::Io;
    return fallback;
}

namespace {

/// \return the field \a to of the first entry of \a table whose field \a from equals \a key, or
/// \a fallback when none does. Reentrant.
template <class Entry, std::size_t N, class Key, class Value>
constexpr Value lookup(const Entry (&table)[N], Key Entry::*from, Key key, Value Entry::*to,
                       Value fallback) noexcept
{
    for (const Entry &e : table)
        if (e.*from == key)
            return e.*to;
    return fallback;
}

/// A codec's FFmpeg id and HAL id.
using CodecIds = std::pair<AVCodecID, hal::CodecId>;

/// The codecs with an FFmpeg id, both ways (codecOf(), avCodecOf()).
constexpr CodecIds kCodecs[] = {
    {AV_CODEC_ID_H264, hal::CodecId::H264},   {AV_CODEC_ID_HEVC, hal::CodecId::Hevc},
    {AV_CODEC_ID_FFV1, hal::CodecId::Ffv1},   {AV_CODEC_ID_RAWVIDEO, hal::CodecId::RawVideo},
    {AV_CODEC_ID_MJPEG, hal::CodecId::Mjpeg},
};

} // namespace

hal::CodecId codecOf(AVCodecID id) noexcept
{
    return lookup(kCodecs, &CodecIds::first, id, &CodecIds::second, hal::CodecId::Unknown);
}

AVCodecID avCodecOf(hal::CodecId codec) noexcept
{
    return lookup(kCodecs, &CodecIds::second, codec, &CodecIds::first, AV_CODEC_ID_NONE);
}

namespace {

bool isYuvLike(const AVPixFmtDescriptor *d) noexcept
{
    return d != nullptr && (d->flags & AV_PIX_FMT_FLAG_RGB) == 0 &&
           (d->flags & AV_PIX_FMT_FLAG_PAL) == 0 && (d->flags & AV_PIX_FMT_FLAG_BITSTREAM) == 0 &&
           (d->flags & AV_PIX_FMT_FLAG_HWACCEL) == 0 && d->comp[0].plane == 0 &&
           (d->nb_components == 1 || d->comp[1].plane != 0 || d->nb_components == 2);
}

} // namespace

hal::PixelFormat halFormatOf(AVPixelFormat fmt, hal::StreamKind kind) noexcept
{
    switch (fmt) {
    case AV_PIX_FMT_NONE:
        return hal::PixelFormat::Unknown;
    case AV_PIX_FMT_GRAY8:
        return hal::PixelFormat::Gray8;
    case AV_PIX_FMT_GRAY10LE:
    case AV_PIX_FMT_GRAY10BE:
        return hal::PixelFormat::Gray10;
    case AV_PIX_FMT_GRAY16LE:
    case AV_PIX_FMT_GRAY16BE:
        return hal::PixelFormat::Gray16;
    case AV_PIX_FMT_YUV420P:
    case AV_PIX_FMT_YUVJ420P:
        return kind == hal::StreamKind::Depth ? hal::PixelFormat::Gray8 : hal::PixelFormat::Yuv420p;
    case AV_PIX_FMT_RGB24:
        return kind == hal::StreamKind::Depth ? hal::PixelFormat::Gray8 : hal::PixelFormat::Rgb24;
    default:
        break;
    }
    const AVPixFmtDescriptor *d = av_pix_fmt_desc_get(fmt);
    if (kind == hal::StreamKind::Depth)
        return d != nullptr && d->comp[0].depth > 8 ? hal::PixelFormat::Gray16
                                                    : hal::PixelFormat::Gray8;
    return hal::PixelFormat::Rgb24;
}

namespace {

/// A HAL pixel format and its FFmpeg format.
using PixelFormats = std::pair<hal::PixelFormat, AVPixelFormat>;

/// The FFmpeg formats of the HAL formats that have one (avFormatOf()).
constexpr PixelFormats kAvFormats[] = {
    {hal::PixelFormat::Gray8, AV_PIX_FMT_GRAY8},   {hal::PixelFormat::Gray10, AV_PIX_FMT_GRAY10},
    {hal::PixelFormat::Gray16, AV_PIX_FMT_GRAY16}, {hal::PixelFormat::Yuv420p, AV_PIX_FMT_YUV420P},
    {hal::PixelFormat::Nv12, AV_PIX_FMT_NV12},     {hal::PixelFormat::Rgb24, AV_PIX_FMT_RGB24},
    {hal::PixelFormat::Rgba8, AV_PIX_FMT_RGBA},    {hal::PixelFormat::Yuyv, AV_PIX_FMT_YUYV422},
};

} // namespace

AVPixelFormat avFormatOf(hal::PixelFormat format) noexcept
{
    return lookup(kAvFormats, &PixelFormats::first, format, &PixelFormats::second, AV_PIX_FMT_NONE);
}

namespace {

void copyPlane(const AVFrame &src, int srcPlane, const hal::ImageView &dst, int dstPlane) noexcept
{
    const hal::PlaneLayout l = hal::planeLayout(dst.format, dst.width, dst.height, dstPlane);
    const auto &p = dst.planes[static_cast<std::size_t>(dstPlane)];
    av_image_copy_plane(p.data, p.strideBytes, src.data[srcPlane], src.linesize[srcPlane],
                        l.rowBytes, l.rows);
}

void copyGray16Swapped(const AVFrame &src, const hal::ImageView &dst) noexcept
{
    for (int y = 0; y < dst.height; ++y) {
        const std::uint8_t *s = src.data[0] + static_cast<std::ptrdiff_t>(y) * src.linesize[0];
        std::uint8_t *d = dst.row(0, y);
        for (int x = 0; x < dst.width; ++x) {
            const auto i = static_cast<std::size_t>(x) * 2u;
            const std::uint16_t v =
                static_cast<std::uint16_t>((static_cast<unsigned>(s[i]) << 8) | s[i + 1]);
            std::memcpy(d + i, &v, sizeof v);
        }
    }
}

constexpr bool kBigEndianHost = AV_PIX_FMT_GRAY16 == AV_PIX_FMT_GRAY16BE;

/// Luma of 10-bit samples into 16-bit Gray16 with the full range kept: v·65535/1023 by bit
/// replication ((v << 6) | (v >> 4): 0 → 0, 1023 → 65535), byte-swapped when \a swapped. Depth
/// nearness, not video: no limited-range conversion. \a shift: the samples' place in their 16 bits
/// (0, or 6 for P010).
void copyGray10As16(const AVFrame &src, const hal::ImageView &dst, bool swapped, int shift) noexcept
{
    for (int y = 0; y < dst.height; ++y) {
        const std::uint8_t *s = src.data[0] + static_cast<std::ptrdiff_t>(y) * src.linesize[0];
        std::uint8_t *d = dst.row(0, y);
        for (int x = 0; x < dst.width; ++x) {
            const auto i = static_cast<std::size_t>(x) * 2u;
            std::uint16_t raw;
            std::memcpy(&raw, s + i, sizeof raw);
            if (swapped)
                raw = static_cast<std::uint16_t>((raw >> 8) | (raw << 8));
            const unsigned v = (static_cast<unsigned>(raw) >> shift) & 0x3ffu;
            const auto wide = static_cast<std::uint16_t>((v << 6) | (v >> 4));
            std::memcpy(d + i, &wide, sizeof wide);
        }
    }
}

} // namespace

Result<void> copyFrame(const AVFrame &src, const hal::ImageView &dst, av::SwsPtr &sws) noexcept
{
    if (src.width != dst.width || src.height != dst.height)
        return unexpected(Errc::InvalidArgument, "Decoded frame size differs from the stream's");
    const auto fmt = static_cast<AVPixelFormat>(src.format);
    const AVPixFmtDescriptor *d = av_pix_fmt_desc_get(fmt);
    if (d == nullptr)
        return unexpected(Errc::InvalidArgument, "Decoded frame has no pixel format");
    const bool srcBe = (d->flags & AV_PIX_FMT_FLAG_BE) != 0;
    const int srcBytes = (d->comp[0].depth + 7) / 8;
    switch (dst.format) {
    case hal::PixelFormat::Gray8:
        if (isYuvLike(d) && srcBytes == 1) {
            copyPlane(src, 0, dst, 0); // luma as is: no range conversion
            return ok();
        }
        break;
    case hal::PixelFormat::Gray10:
    case hal::PixelFormat::Gray16:
        if (isYuvLike(d) && srcBytes == 2 && d->comp[0].depth == 10 &&
            dst.format == hal::PixelFormat::Gray16) {
            // P010 (a hardware decoder's 10-bit 4:2:0) keeps the samples in the high bits.
            copyGray10As16(src, dst, srcBe != kBigEndianHost, d->comp[0].shift);
            return ok();
        }
        if (isYuvLike(d) && srcBytes == 2 &&
            (dst.format == hal::PixelFormat::Gray16 || d->comp[0].depth == 10)) {
            if (srcBe != kBigEndianHost)
                copyGray16Swapped(src, dst);
            else
                copyPlane(src, 0, dst, 0);
            return ok();
        }
        break;
    case hal::PixelFormat::Yuv420p:
        if (fmt == AV_PIX_FMT_YUV420P || fmt == AV_PIX_FMT_YUVJ420P) {
            for (int p = 0; p < 3; ++p)
                copyPlane(src, p, dst, p);
            return ok();
        }
        break;
    case hal::PixelFormat::Rgb24:
        if (fmt == AV_PIX_FMT_RGB24) {
            copyPlane(src, 0, dst, 0);
            return ok();
        }
        break;
    default:
        break;
    }
    const AVPixelFormat target = avFormatOf(dst.format);
    if (target == AV_PIX_FMT_NONE)
        return unexpected(Errc::NotSupported, "No conversion to the stream's pixel format");
    SwsContext *ctx =
        sws_getCachedContext(sws.release(), src.width, src.height, fmt, dst.width, dst.height,
                             target, SWS_POINT, nullptr, nullptr, nullptr);
    sws.reset(ctx);
    if (ctx == nullptr)
        return unexpected(Errc::NotSupported, "No conversion to the stream's pixel format");
    std::uint8_t *planes[4] = {dst.planes[0].data, dst.planes[1].data, dst.planes[2].data, nullptr};
    int strides[4] = {dst.planes[0].strideBytes, dst.planes[1].strideBytes,
                      dst.planes[2].strideBytes, 0};
    if (sws_scale(ctx, src.data, src.linesize, 0, src.height, planes, strides) <= 0)
        return unexpected(Errc::InvalidArgument, "Pixel format conversion failed");
    return ok();
}

} // namespace depthtouch::drivers::ffmpeg
