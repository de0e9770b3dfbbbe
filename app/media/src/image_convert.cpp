/// \file
/// \brief ImageConverter (see image_convert.h): an Image wrapped in an AVFrame, converted by the
/// shared libswscale helper.

#include "depthtouch/media/image_convert.h"

#include <cstring>
#include <utility>

#include "media_libav.h"

namespace depthtouch::media {

using namespace detail;

struct ImageConverter::Impl {
    Scaler scaler;
};

ImageConverter::ImageConverter() : impl_(std::make_unique<Impl>()) {}

ImageConverter::~ImageConverter() = default;

Result<Image> ImageConverter::convert(const Image &src, PixelFormat format, int width, int height)
{
    const std::size_t rowBytes =
        static_cast<std::size_t>(src.width) * static_cast<std::size_t>(bytesPerPixel(src.format));
    if (src.empty() || src.stride < rowBytes ||
        src.data.size() < src.stride * static_cast<std::size_t>(src.height))
        return unexpected(Errc::InvalidArgument, "Cannot convert an empty or inconsistent image");
    if (width < 0 || height < 0)
        return unexpected(Errc::InvalidArgument, "Image size must not be negative");
    const int w = width > 0 ? width : src.width;
    const int h = height > 0 ? height : src.height;
    Image out = Image::make(w, h, format);
    if (format == src.format && w == src.width && h == src.height) {
        for (int y = 0; y < h; ++y)
            std::memcpy(out.row(y), src.row(y), rowBytes);
        return out;
    }
    // The AVFrame only points at the caller's samples: no libav allocation per call.
    AVFrame frame{};
    frame.width = src.width;
    frame.height = src.height;
    frame.format = toAvFormat(src.format);
    frame.color_range = AVCOL_RANGE_JPEG;
    frame.data[0] = const_cast<std::uint8_t *>(src.data.data()); // read only by libswscale
    frame.linesize[0] = static_cast<int>(src.stride);
    std::uint8_t *dstData[4] = {out.data.data(), nullptr, nullptr, nullptr};
    const int dstStride[4] = {static_cast<int>(out.stride), 0, 0, 0};
    DT_TRY(impl_->scaler.convert(frame, dstData, dstStride, toAvFormat(format), w, h));
    return out;
}

Result<void> ImageConverter::conform(Image &image, PixelFormat format, int width, int height)
{
    if (image.format == format && (width <= 0 || width == image.width) &&
        (height <= 0 || height == image.height))
        return {};
    auto converted = convert(image, format, width, height);
    if (!converted)
        return unexpected(converted.error());
    image = std::move(*converted);
    return {};
}

} // namespace depthtouch::media
