#pragma once
/// \file
/// \brief ImageConverter: changes an Image's layout and size with libswscale, by the rules of
/// readImage() and FrameSource::next(): 16 → 8 bit keeps the high byte, 8 → 16 bit scales by 257,
/// color → gray takes the luma (BT.601), gray → RGB replicates; another size is scaled bicubic.
/// For sources that make their frames themselves (a camera, a synthetic scene) and must honour
/// the layout and size a caller of FrameSource::next() asks.
///
/// Thread-safety: thread-bound (one converter per thread); distinct converters are independent.

#include <memory>

#include "depthtouch/media/image.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::media {

/// \brief A cached libswscale conversion: rebuilt only when the sizes or layouts change.
class ImageConverter {
public:
    ImageConverter();
    ~ImageConverter();
    DT_DISABLE_COPY(ImageConverter)

    /// \brief Converts \a src into a tightly packed image of \a format and \a width × \a height
    /// pixels (0 = the source's own size). Same layout and size: a plain copy.
    /// \return the image. Errors: InvalidArgument (empty or inconsistent \a src, negative size),
    /// NotSupported (libswscale has no such conversion).
    Result<Image> convert(const Image &src, PixelFormat format, int width = 0, int height = 0);

    /// \brief Makes \a image \a format and \a width × \a height pixels (0 or less = its own size)
    /// in place, converting it (convert()) only when it is not so already.
    /// \return nothing, or convert()'s error (\a image unchanged).
    Result<void> conform(Image &image, PixelFormat format, int width = 0, int height = 0);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace depthtouch::media
