#pragma once
/// \file
/// \brief Test helpers: depth frames of analytic surfaces for the haptic task tests.

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <vector>

#include "depthtouch/haptic_task/depth_handoff.h"
#include "depthtouch/haptics/depth_frame.h"

namespace depthtouch::haptic_task::test {

/// Nearness (16-bit) of height \a z, m, in a box of depth \a boxDepth.
inline std::uint16_t nearness16(double z, double boxDepth = 0.04)
{
    const double v = std::round((z / boxDepth + 0.5) * 65535.0);
    return static_cast<std::uint16_t>(std::fmin(std::fmax(v, 0.0), 65535.0));
}

/// Height (m) that nearness \a v decodes to.
inline double heightOf(std::uint16_t v, double boxDepth = 0.04)
{
    return (static_cast<double>(v) / 65535.0 - 0.5) * boxDepth;
}

/// A W×H Gray16 frame owning its samples.
struct Frame16 {
    int width = 0;
    int height = 0;
    double pts = 0.0;
    std::vector<std::uint16_t> samples;

    Frame16(int w, int h, double p)
        : width(w), height(h), pts(p), samples(static_cast<std::size_t>(w * h))
    {
    }

    /// Fills z(x, y) sampled on the scene box grid of width \a boxWidth (docs/architecture.md §3).
    void fill(const std::function<double(double, double)> &z, double boxWidth = 0.10)
    {
        const double s = boxWidth / (width - 1);
        for (int r = 0; r < height; ++r)
            for (int c = 0; c < width; ++c)
                samples[static_cast<std::size_t>(r * width + c)] =
                    nearness16(z((c - 0.5 * (width - 1)) * s, (0.5 * (height - 1) - r) * s));
    }
    void fillFlat(double z) { std::fill(samples.begin(), samples.end(), nearness16(z)); }

    [[nodiscard]] scene::DepthFrameView view() const
    {
        return scene::DepthFrameView{reinterpret_cast<const std::uint8_t *>(samples.data()),
                                     width,
                                     height,
                                     static_cast<std::size_t>(width) * 2,
                                     scene::SampleFormat::Gray16,
                                     pts};
    }
};

/// \return true when every sample of \a v equals \a value.
inline bool allSamples(const scene::DepthFrameView &v, std::uint16_t value)
{
    for (int r = 0; r < v.height; ++r)
        for (int c = 0; c < v.width; ++c)
            if (v.sample(c, r) != value)
                return false;
    return true;
}

} // namespace depthtouch::haptic_task::test
