#pragma once
/// \file
/// \brief Synthetic depth videos for the haptic tests: frames sampled from analytic surfaces z(x,
/// y, t) in the scene box (docs/architecture.md §3), stored as 16-bit (or 8-bit) nearness.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <vector>

#include "depthtouch/haptics/depth_frame.h"

namespace depthtouch::haptics::test {

/// An owned frame with a view on it.
class OwnedFrame {
public:
    OwnedFrame() = default;
    OwnedFrame(int w, int h, SampleFormat format, double pts, std::size_t padBytes = 0)
        : w_(w), h_(h), format_(format), pts_(pts),
          stride_(static_cast<std::size_t>(w) * bytesPerSample(format) + padBytes),
          bytes_(stride_ * static_cast<std::size_t>(h), 0)
    {
    }
    void set(int c, int r, std::uint32_t v)
    {
        std::uint8_t *p = bytes_.data() + static_cast<std::size_t>(r) * stride_ +
                          static_cast<std::size_t>(c) * bytesPerSample(format_);
        if (format_ == SampleFormat::Gray8) {
            *p = static_cast<std::uint8_t>(v);
        } else {
            const auto s = static_cast<std::uint16_t>(v);
            std::memcpy(p, &s, 2);
        }
    }
    /// Samples below \a v are holes (DepthFrameView::holeBelow).
    void setHoleBelow(std::uint32_t v) { holeBelow_ = v; }
    [[nodiscard]] DepthFrameView view() const
    {
        DepthFrameView v{bytes_.data(), w_, h_, stride_, format_, pts_};
        v.holeBelow = holeBelow_;
        return v;
    }
    [[nodiscard]] int width() const { return w_; }
    [[nodiscard]] int height() const { return h_; }

private:
    int w_ = 0;
    int h_ = 0;
    SampleFormat format_ = SampleFormat::Gray16;
    double pts_ = 0.0;
    std::size_t stride_ = 0;
    std::uint32_t holeBelow_ = 0;
    std::vector<std::uint8_t> bytes_;
};

/// x, y (m) of sample (c, r) in a W×H frame over \a box (docs/architecture.md §3).
inline double sampleX(const SceneBox &box, int w, int c)
{
    return (c - 0.5 * (w - 1)) * box.width / (w - 1);
}
inline double sampleY(const SceneBox &box, int w, int h, int r)
{
    return (0.5 * (h - 1) - r) * box.width / (w - 1);
}

/// Quantises height \a z (m) to nearness.
inline std::uint32_t toNearness(const SceneBox &box, SampleFormat format, double z)
{
    const double vmax = maxSampleValue(format);
    const double v = std::round((z / box.depth + 0.5) * vmax);
    return static_cast<std::uint32_t>(std::clamp(v, 0.0, vmax));
}

/// Height (m) that a nearness sample decodes to.
inline double fromNearness(const SceneBox &box, SampleFormat format, std::uint32_t v)
{
    return (static_cast<double>(v) / maxSampleValue(format) - 0.5) * box.depth;
}

/// Samples the surface \a z(x, y) (m) into a frame.
inline OwnedFrame makeFrame(const SceneBox &box, int w, int h, double pts,
                            const std::function<double(double, double)> &z,
                            SampleFormat format = SampleFormat::Gray16, std::size_t padBytes = 0)
{
    OwnedFrame f(w, h, format, pts, padBytes);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c)
            f.set(c, r, toNearness(box, format, z(sampleX(box, w, c), sampleY(box, w, h, r))));
    return f;
}

} // namespace depthtouch::haptics::test
