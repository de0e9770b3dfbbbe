#pragma once
/// \file
/// \brief Image: a plain owning picture (8/16-bit gray or RGB) as read and written by image_io.h,
/// and its conversion to and from depth::Plane.
///
/// Thread-safety: value type; distinct objects may be used from distinct threads.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "depthtouch/depth/plane.h"

namespace depthtouch::media {

/// \brief Sample layout of an Image.
enum class PixelFormat : std::uint8_t {
    Gray8,  ///< 1 byte per pixel.
    Gray16, ///< 2 bytes per pixel, native byte order (uint16_t); e.g. depth in mm.
    Rgb24,  ///< 3 bytes per pixel: R, G, B.
};

/// \return bytes per pixel of \a format (1, 2 or 3).
constexpr int bytesPerPixel(PixelFormat format) noexcept
{
    return format == PixelFormat::Gray8 ? 1 : (format == PixelFormat::Gray16 ? 2 : 3);
}
/// \return "gray8", "gray16" or "rgb24".
const char *pixelFormatName(PixelFormat format) noexcept;

/// \brief A W×H picture: row y starts at byte `y·stride` of \a data; `stride ≥
/// width·bytesPerPixel(format)`.
struct Image {
    int width = 0;
    int height = 0;
    PixelFormat format = PixelFormat::Gray8;
    std::size_t stride = 0;         ///< Bytes per row.
    std::vector<std::uint8_t> data; ///< stride·height bytes.

    /// A zero-filled, tightly packed image. \pre width, height ≥ 0.
    static Image make(int width, int height, PixelFormat format);

    [[nodiscard]] bool empty() const noexcept { return width <= 0 || height <= 0 || data.empty(); }
    /// First byte of row \a y. \pre 0 ≤ y < height.
    [[nodiscard]] std::uint8_t *row(int y) noexcept
    {
        return data.data() + static_cast<std::size_t>(y) * stride;
    }
    [[nodiscard]] const std::uint8_t *row(int y) const noexcept
    {
        return data.data() + static_cast<std::size_t>(y) * stride;
    }
    /// Gray16 sample (x, y). \pre format == Gray16, inside the image.
    [[nodiscard]] std::uint16_t sample16(int x, int y) const noexcept;
    /// Sets Gray16 sample (x, y). \pre format == Gray16, inside the image.
    void setSample16(int x, int y, std::uint16_t value) noexcept;
};

/// \brief Gray16 image → plane of uint16 samples (e.g. raw depth in mm). Gray8 samples are widened
/// unchanged (0..255). \return an empty plane for Rgb24.
depth::Plane<std::uint16_t> toPlane16(const Image &image);
/// \brief Gray8 image → plane of bytes (e.g. 8-bit nearness). \return an empty plane unless Gray8.
depth::Plane<std::uint8_t> toPlane8(const Image &image);
/// \brief Plane → Gray16 image.
Image fromPlane(const depth::Plane<std::uint16_t> &plane);
/// \brief Plane → Gray8 image.
Image fromPlane(const depth::Plane<std::uint8_t> &plane);

} // namespace depthtouch::media
