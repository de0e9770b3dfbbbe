/// \file
/// \brief Image helpers (see image.h).

#include "depthtouch/media/image.h"

#include "depthtouch/platform/enum_names.h"

#include <array>
#include <cstring>

namespace depthtouch::media {

const char *pixelFormatName(PixelFormat format) noexcept
{
    static constexpr std::array<const char *, 3> kNames = {"gray8", "gray16", "rgb24"};
    return platform::enumName(format, kNames, "gray8");
}

Image Image::make(int width, int height, PixelFormat format)
{
    Image img;
    img.width = width < 0 ? 0 : width;
    img.height = height < 0 ? 0 : height;
    img.format = format;
    img.stride =
        static_cast<std::size_t>(img.width) * static_cast<std::size_t>(bytesPerPixel(format));
    img.data.assign(img.stride * static_cast<std::size_t>(img.height), 0);
    return img;
}

std::uint16_t Image::sample16(int x, int y) const noexcept
{
    std::uint16_t v = 0;
    std::memcpy(&v, row(y) + 2 * static_cast<std::size_t>(x), sizeof v);
    return v;
}

void Image::setSample16(int x, int y, std::uint16_t value) noexcept
{
    std::memcpy(row(y) + 2 * static_cast<std::size_t>(x), &value, sizeof value);
}

depth::Plane<std::uint16_t> toPlane16(const Image &image)
{
    if (image.format == PixelFormat::Rgb24 || image.empty())
        return {};
    depth::Plane<std::uint16_t> plane(image.width, image.height);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            plane.at(x, y) = image.format == PixelFormat::Gray16
                                 ? image.sample16(x, y)
                                 : image.row(y)[static_cast<std::size_t>(x)];
    return plane;
}

depth::Plane<std::uint8_t> toPlane8(const Image &image)
{
    if (image.format != PixelFormat::Gray8 || image.empty())
        return {};
    depth::Plane<std::uint8_t> plane(image.width, image.height);
    for (int y = 0; y < image.height; ++y)
        std::memcpy(&plane.at(0, y), image.row(y), static_cast<std::size_t>(image.width));
    return plane;
}

namespace {

/// An image of \a format (Gray8 or Gray16, matching T) holding \a plane's samples row by row, in
/// host byte order.
template <class T> Image imageOfPlane(const depth::Plane<T> &plane, PixelFormat format)
{
    Image img = Image::make(plane.width, plane.height, format);
    if (plane.empty())
        return img;
    for (int y = 0; y < plane.height; ++y)
        std::memcpy(img.row(y), &plane.at(0, y), static_cast<std::size_t>(plane.width) * sizeof(T));
    return img;
}

} // namespace

Image fromPlane(const depth::Plane<std::uint16_t> &plane)
{
    return imageOfPlane(plane, PixelFormat::Gray16);
}

Image fromPlane(const depth::Plane<std::uint8_t> &plane)
{
    return imageOfPlane(plane, PixelFormat::Gray8);
}

} // namespace depthtouch::media
