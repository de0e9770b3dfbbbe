/// \file
/// \brief The functions of types.h: each PixelFormat's name, plane count, bits per sample, plane
/// layout and image size (one table, kFormatTraits, in the enumeration's order), the names of
/// stream kinds and codecs, and StreamConfig::fromStream. Thread-safety: pure functions over
/// constant tables.
#include "depthtouch/hal/types.h"

#include "depthtouch/hal/media_source.h"
#include "depthtouch/hal/video_decoder.h"
#include "depthtouch/platform/enum_names.h"

#include <array>
#include <cstddef>

namespace depthtouch::hal {

namespace {

/// What pixelFormatName(), planeCount() and bitsPerSample() say of one PixelFormat.
struct FormatTraits {
    const char *name;
    int planes;
    int bits; ///< Bits per sample; 0 where there are no samples (Unknown, Mjpeg).
};

/// Every PixelFormat's traits, in the enumeration's order.
constexpr std::array<FormatTraits, 11> kFormatTraits = {{
    {"unknown", 0, 0},
    {"gray8", 1, 8},
    {"gray10", 1, 10},
    {"gray16", 1, 16},
    {"yuv420p", 3, 8},
    {"nv12", 2, 8},
    {"rgb24", 1, 8},
    {"rgba8", 1, 8},
    {"yuyv", 1, 8},
    {"z16", 1, 16},
    {"mjpeg", 1, 0},
}};
static_assert(kFormatTraits.size() == static_cast<std::size_t>(PixelFormat::Mjpeg) + 1);

/// The traits of \a format; those of Unknown for a value outside the enumeration.
constexpr const FormatTraits &formatTraits(PixelFormat format) noexcept
{
    const auto index = static_cast<std::size_t>(format);
    return kFormatTraits[index < kFormatTraits.size() ? index : 0];
}

/// Every CodecId's name, in the enumeration's order.
constexpr std::array<const char *, 7> kCodecNames = {"unknown",  "h264",  "hevc", "ffv1",
                                                     "rawvideo", "mjpeg", "mock"};
static_assert(kCodecNames.size() == static_cast<std::size_t>(CodecId::Mock) + 1);

} // namespace

const char *pixelFormatName(PixelFormat format) noexcept
{
    return formatTraits(format).name;
}

int planeCount(PixelFormat format) noexcept
{
    return formatTraits(format).planes;
}

int bitsPerSample(PixelFormat format) noexcept
{
    return formatTraits(format).bits;
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
    return platform::enumName(codec, kCodecNames, "unknown");
}

StreamConfig StreamConfig::fromStream(const StreamInfo &stream)
{
    return StreamConfig{.codec = stream.codec,
                        .kind = stream.kind,
                        .format = stream.format,
                        .width = stream.width,
                        .height = stream.height,
                        .frameRate = stream.frameRate,
                        .extradata = stream.extradata};
}

} // namespace depthtouch::hal
