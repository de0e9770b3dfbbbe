#pragma once
/// \file
/// \brief Small owned depth and colour frames for the renderer tests.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "depthtouch/hal/types.h"
#include "depthtouch/scene/depth_frame.h"

namespace depthtouch::test {

/// A W×H nearness frame of \a Sample codes in format \a Format, filled by \a f(c, r) clamped to
/// the codes \a Sample holds.
template <class Sample, scene::SampleFormat Format> struct DepthFrame {
    int width = 0;
    int height = 0;
    std::vector<Sample> samples;

    DepthFrame(int w, int h, const std::function<int(int, int)> &f) : width(w), height(h)
    {
        samples.resize(static_cast<std::size_t>(w * h));
        for (int r = 0; r < h; ++r)
            for (int c = 0; c < w; ++c)
                samples[static_cast<std::size_t>(r * w + c)] = static_cast<Sample>(
                    std::clamp(f(c, r), 0, static_cast<int>(std::numeric_limits<Sample>::max())));
    }
    [[nodiscard]] scene::DepthFrameView view() const
    {
        scene::DepthFrameView v;
        v.data = reinterpret_cast<const std::uint8_t *>(samples.data());
        v.width = width;
        v.height = height;
        v.strideBytes = static_cast<std::size_t>(width) * sizeof(Sample);
        v.format = Format;
        return v;
    }
};

/// A W×H 8-bit nearness frame filled by \a f(c, r).
using Depth8 = DepthFrame<std::uint8_t, scene::SampleFormat::Gray8>;
/// A W×H 16-bit nearness frame filled by \a f(c, r).
using Depth16 = DepthFrame<std::uint16_t, scene::SampleFormat::Gray16>;

/// A W×H yuv420p frame whose pixel (x, y) has Y, U, V = \a f(x, y) (chroma taken at even pixels).
struct Yuv420 {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> y, u, v;

    Yuv420(int w, int h, const std::function<std::array<int, 3>(int, int)> &f) : width(w), height(h)
    {
        const int cw = (w + 1) / 2;
        const int ch = (h + 1) / 2;
        y.resize(static_cast<std::size_t>(w * h));
        u.resize(static_cast<std::size_t>(cw * ch));
        v.resize(static_cast<std::size_t>(cw * ch));
        for (int r = 0; r < h; ++r)
            for (int c = 0; c < w; ++c) {
                const auto p = f(c, r);
                y[static_cast<std::size_t>(r * w + c)] = static_cast<std::uint8_t>(p[0]);
                if (r % 2 == 0 && c % 2 == 0) {
                    u[static_cast<std::size_t>((r / 2) * cw + c / 2)] =
                        static_cast<std::uint8_t>(p[1]);
                    v[static_cast<std::size_t>((r / 2) * cw + c / 2)] =
                        static_cast<std::uint8_t>(p[2]);
                }
            }
    }
    [[nodiscard]] hal::ImageView view()
    {
        hal::ImageView img;
        img.width = width;
        img.height = height;
        img.format = hal::PixelFormat::Yuv420p;
        img.planes[0] = {y.data(), width};
        img.planes[1] = {u.data(), (width + 1) / 2};
        img.planes[2] = {v.data(), (width + 1) / 2};
        return img;
    }
};

} // namespace depthtouch::test
