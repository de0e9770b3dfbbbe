/// \file
/// \brief The depth frame mapping: see depth_view.h.

#include "depth_view.h"

namespace depthtouch::playback {

scene::SampleFormat sampleFormatOf(hal::PixelFormat format) noexcept
{
    return format == hal::PixelFormat::Gray16 ? scene::SampleFormat::Gray16
                                              : scene::SampleFormat::Gray8;
}

scene::DepthFrameView depthView(const receiver::StoredFrame &f, double pts) noexcept
{
    scene::DepthFrameView v;
    v.data = f.image.planes[0].data;
    v.width = f.image.width;
    v.height = f.image.height;
    v.strideBytes = static_cast<std::size_t>(f.image.planes[0].strideBytes);
    v.format = sampleFormatOf(f.image.format);
    v.pts = pts;
    v.holeBelow = f.holeBelow;
    return v;
}

scene::MaterialView materialView(const receiver::StoredFrame *f, int width, int height) noexcept
{
    if (f == nullptr || f->image.format != hal::PixelFormat::Rgb24 || f->image.width != width ||
        f->image.height != height || f->image.planes[0].data == nullptr)
        return {};
    return {f->image.planes[0].data, static_cast<std::size_t>(f->image.planes[0].strideBytes)};
}

} // namespace depthtouch::playback
