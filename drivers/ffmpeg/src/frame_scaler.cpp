#include "frame_scaler.h"

#include <new>

#include "ffmpeg_common.h"

extern "C" {
#include <libswscale/swscale.h>
}

namespace depthtouch::drivers::ffmpeg {

Result<void> FrameScaler::allocate(hal::PixelFormat format, int width, int height) noexcept
{
    if (scratch_.format == format && scratch_.width == width && scratch_.height == height)
        return ok();
    std::size_t total = 0;
    for (int p = 0; p < hal::planeCount(format); ++p) {
        const hal::PlaneLayout l = hal::planeLayout(format, width, height, p);
        total += static_cast<std::size_t>(l.rowBytes) * static_cast<std::size_t>(l.rows);
    }
    if (total == 0)
        return unexpected(Errc::NotSupported, "No scaler for the stream's pixel format");
    try {
        bytes_.resize(total);
    } catch (const std::bad_alloc &) {
        scratch_ = {};
        return unexpected(Errc::OutOfResources, "No memory to scale a frame of another size");
    }
    scratch_ = {};
    scratch_.width = width;
    scratch_.height = height;
    scratch_.format = format;
    std::size_t at = 0;
    for (int p = 0; p < hal::planeCount(format); ++p) {
        const hal::PlaneLayout l = hal::planeLayout(format, width, height, p);
        auto &plane = scratch_.planes[static_cast<std::size_t>(p)];
        plane.data = bytes_.data() + at;
        plane.strideBytes = l.rowBytes;
        at += static_cast<std::size_t>(l.rowBytes) * static_cast<std::size_t>(l.rows);
    }
    return ok();
}

Result<void> FrameScaler::copy(const AVFrame &src, const hal::ImageView &dst, bool nearest) noexcept
{
    if (src.width == dst.width && src.height == dst.height)
        return copyFrame(src, dst, convert_);
    const AVPixelFormat fmt = avFormatOf(dst.format);
    if (fmt == AV_PIX_FMT_NONE || src.width <= 0 || src.height <= 0)
        return unexpected(Errc::NotSupported, "No scaler for the stream's pixel format");
    if (auto a = allocate(dst.format, src.width, src.height); !a)
        return a;
    if (auto c = copyFrame(src, scratch_, convert_); !c)
        return c;
    SwsContext *ctx =
        sws_getCachedContext(scale_.release(), src.width, src.height, fmt, dst.width, dst.height,
                             fmt, nearest ? SWS_POINT : SWS_BILINEAR, nullptr, nullptr, nullptr);
    scale_.reset(ctx);
    if (ctx == nullptr)
        return unexpected(Errc::NotSupported, "No scaler for the stream's pixel format");
    const std::uint8_t *from[4] = {scratch_.planes[0].data, scratch_.planes[1].data,
                                   scratch_.planes[2].data, nullptr};
    const int fromStrides[4] = {scratch_.planes[0].strideBytes, scratch_.planes[1].strideBytes,
                                scratch_.planes[2].strideBytes, 0};
    std::uint8_t *to[4] = {dst.planes[0].data, dst.planes[1].data, dst.planes[2].data, nullptr};
    const int toStrides[4] = {dst.planes[0].strideBytes, dst.planes[1].strideBytes,
                              dst.planes[2].strideBytes, 0};
    if (sws_scale(ctx, from, fromStrides, 0, src.height, to, toStrides) <= 0)
        return unexpected(Errc::InvalidArgument, "Scaling a frame of another size failed");
    return ok();
}

} // namespace depthtouch::drivers::ffmpeg
