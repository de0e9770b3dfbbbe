// Builds without the FFmpeg feature: no YUYV→RGB conversion and no MJPEG decoding (image
// conversion is left to libswscale and libavcodec). The camera then offers YUYV color as Yuyv only
// and refuses MJPEG.
#include "color_converter.h"

namespace depthtouch::drivers::v4l2 {

bool canConvertToRgb(std::uint32_t /*fourcc*/) noexcept
{
    return false;
}

Result<std::unique_ptr<ColorConverter>> makeColorConverter(std::uint32_t /*fourcc*/, int /*width*/,
                                                           int /*height*/)
{
    return unexpected(Errc::NotSupported,
                      "Color conversion (YUYV to RGB, MJPEG decoding) needs the FFmpeg feature");
}

} // namespace depthtouch::drivers::v4l2
