#pragma once
/// \file
/// \brief Views of the benchmark's RGB-D frames as the renderer takes them, private to
/// dt_render_bench. Thread-safety: pure functions; the views borrow the frame.

#include "depthtouch/hal/types.h"
#include "depthtouch/render/render_bench.h"
#include "depthtouch/scene/depth_frame.h"

namespace depthtouch::render::bench::detail {

/// \return \a f's nearness as a Gray8 depth frame view (W×H, tightly packed).
inline scene::DepthFrameView depthView(const RgbdFrame &f) noexcept
{
    scene::DepthFrameView v;
    v.data = f.nearness.data();
    v.width = f.width;
    v.height = f.height;
    v.strideBytes = static_cast<std::size_t>(f.width);
    v.format = scene::SampleFormat::Gray8;
    return v;
}

/// \return \a f's colour as a yuv420p image view (planes tightly packed).
inline hal::ImageView colorView(const RgbdFrame &f) noexcept
{
    hal::ImageView img;
    img.width = f.colorWidth;
    img.height = f.colorHeight;
    img.format = hal::PixelFormat::Yuv420p;
    const int cw = (f.colorWidth + 1) / 2;
    img.planes[0] = {const_cast<std::uint8_t *>(f.y.data()), f.colorWidth};
    img.planes[1] = {const_cast<std::uint8_t *>(f.u.data()), cw};
    img.planes[2] = {const_cast<std::uint8_t *>(f.v.data()), cw};
    return img;
}

} // namespace depthtouch::render::bench::detail
