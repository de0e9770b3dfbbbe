#include "depthtouch/hal/types.h"

#include "depthtouch/hal/media_source.h"
#include "depthtouch/hal/video_decoder.h"

namespace depthtouch::hal {

const char *pixelFormatName(PixelFormat format) noexcept
{
    switch (format) {
    case PixelFormat::Unknown:
        return "unknown";
    case PixelFormat::Gray8:
        return "gray8";
    case PixelFormat::Gray10:
        return "gray10";
    case PixelFormat::Gray16:
        return "gray16";
    case PixelFormat::Yuv420p:
        return "yuv420p";
    case PixelFormat::Nv12:
        return "nv12";
    case PixelFormat::Rgb24:
        return "rgb24";
    case PixelFormat::Rgba8:
        return "rgba8";
    case PixelFormat::Yuyv:
        return "yuyv";
    case PixelFormat::Z16:
        return "z16";
    case PixelFormat::Mjpeg:
        return "mjpeg";
    }
    return "unknown";
}

int planeCount(PixelFormat format) noexcept
{
    switch (format) {
    case PixelFormat::Unknown:
        return 0;
    case PixelFormat::Yuv420p:
        return 3;
    case PixelFormat::Nv12:
        return 2;
    case PixelFormat::Gray8:
    case PixelFormat::Gray10:
    case PixelFormat::Gray16:
    case PixelFormat::Rgb24:
    case PixelFormat::Rgba8:
    case PixelFormat::Yuyv:
    case PixelFormat::Z16:
    case PixelFormat::Mjpeg:
        return 1;
    }
    return 0;
}

int bitsPerSample(PixelFormat format) noexcept
{
    switch (format) {
    case PixelFormat::Unknown:
    case PixelFormat::Mjpeg:
        return 0;
    case PixelFormat::Gray10:
        return 10;
    case PixelFormat::Gray16:
    case PixelFormat::Z16:
        return 16;
    case PixelFormat::Gray8:
    case PixelFormat::Yuv420p:
    case PixelFormat::Nv12:
    case PixelFormat::Rgb24:
    case PixelFormat::Rgba8:
    case PixelFormat::Yuyv:
        return 8;
    }
    return 0;
}

PlaneLayout planeLayout(PixelFormat format, int width, int height, int plane) noexcept
{
    if (width <= 0 || height <= 0 || plane < 0 || plane >= planeCount(format))
        return {};
    const int halfWidth = (width + 1) / 2;
    const int halfHeight = (height + 1) / 2;
    switch (format) {
    case PixelFormat::Gray8:
        return {width, height};
    case PixelFormat::Gray10:
    case PixelFormat::Gray16:
    case PixelFormat::Z16:
        return {2 * width, height};
    case PixelFormat::Yuv420p:
        return plane == 0 ? PlaneLayout{width, height} : PlaneLayout{halfWidth, halfHeight};
    case PixelFormat::Nv12:
        return plane == 0 ? PlaneLayout{width, height} : PlaneLayout{2 * halfWidth, halfHeight};
    case PixelFormat::Rgb24:
        return {3 * width, height};
    case PixelFormat::Rgba8:
        return {4 * width, height};
    case PixelFormat::Yuyv:
        return {4 * halfWidth, height};
    case PixelFormat::Unknown:
    case PixelFormat::Mjpeg:
        break;
    }
    return {};
}

std::size_t imageBytes(PixelFormat format, int width, int height) noexcept
{
    std::size_t total = 0;
    for (int p = 0; p < planeCount(format); ++p) {
        const PlaneLayout l = planeLayout(format, width, height, p);
        total += static_cast<std::size_t>(l.rowBytes) * static_cast<std::size_t>(l.rows);
    }
    return total;
}

const char *streamKindName(StreamKind kind) noexcept
{
    return kind == StreamKind::Depth ? "depth" : "color";
}

const char *codecName(CodecId codec) noexcept
{
    switch (codec) {
    case CodecId::Unknown:
        return "unknown";
    case CodecId::H264:
        return "h264";
    case CodecId::Hevc:
        return "hevc";
    case CodecId::Ffv1:
        return "ffv1";
    case CodecId::RawVideo:
        return "rawvideo";
    case CodecId::Mjpeg:
        return "mjpeg";
    case CodecId::Mock:
        return "mock";
    }
    return "unknown";
}

StreamConfig StreamConfig::fromStream(const StreamInfo &stream)
{
    StreamConfig cfg;
    cfg.codec = stream.codec;
    cfg.kind = stream.kind;
    cfg.format = stream.format;
    cfg.width = stream.width;
    cfg.height = stream.height;
    cfg.frameRate = stream.frameRate;
    cfg.extradata = stream.extradata;
    return cfg;
}

} // namespace depthtouch::hal
