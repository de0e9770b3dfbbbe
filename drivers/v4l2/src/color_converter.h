#pragma once
/// \file
/// \brief Conversion of a captured color buffer (YUYV or MJPEG) into a hal Rgb24 image, private to
/// drivers/v4l2. Two implementations, chosen by CMake: libavcodec + libswscale when the FFmpeg
/// feature is built (color_converter_ffmpeg.cpp), none otherwise (color_converter_none.cpp).
/// Thread-safety: thread-bound. Not real-time safe.

#include <cstddef>
#include <cstdint>
#include <memory>

#include "depthtouch/hal/types.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers::v4l2 {

/// \brief Converts one V4L2 format at one size into Rgb24.
class ColorConverter {
public:
    virtual ~ColorConverter() = default;

    /// \brief Converts one buffer.
    /// \param[in] data The buffer; \a bytes payload bytes (bytesused).
    /// \param[in] bytesPerLine Row stride of uncompressed formats.
    /// \param[in] dst Rgb24 image of the converter's size (allocated by the caller).
    /// \return Io when the buffer cannot be decoded (damaged JPEG).
    virtual Result<void> convert(const std::uint8_t *data, std::size_t bytes, int bytesPerLine,
                                 const hal::ImageView &dst) noexcept = 0;

protected:
    ColorConverter() = default;
    DT_DISABLE_COPY_AND_MOVE(ColorConverter)
};

/// \return whether V4L2 format \a fourcc can be converted to Rgb24 in this build.
bool canConvertToRgb(std::uint32_t fourcc) noexcept;

/// \return a converter of \a fourcc at \a width × \a height into Rgb24. Errors: NotSupported
/// (format unknown, or the build has no FFmpeg), OutOfResources.
Result<std::unique_ptr<ColorConverter>> makeColorConverter(std::uint32_t fourcc, int width,
                                                           int height);

} // namespace depthtouch::drivers::v4l2
