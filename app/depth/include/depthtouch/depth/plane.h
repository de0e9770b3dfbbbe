#pragma once
/// \file
/// \brief Plane<T>: a plain owning 2-D array of samples, the data type of the depth pipeline.
///
/// Thread-safety: value type; distinct objects may be used from distinct threads, one object from
/// several threads only for reading.

#include <cstddef>
#include <vector>

namespace depthtouch::depth {

/// \brief A W×H grid of samples of type T, row-major, tightly packed (row stride = width samples).
///
/// Sample (column x, row y) is `samples[y·width + x]`, x in [0, width), y in [0, height); row 0 is
/// the top of the image. The unit depends on the use: raw sensor units (e.g. mm) in
/// `Plane<uint16_t>`, nearness levels (0 = far plane, v_max = near plane, docs/architecture.md §3)
/// in `Plane<float>` or `Plane<uint16_t>`, flags (0/1) in `Plane<uint8_t>`.
template <class T> struct Plane {
    int width = 0;
    int height = 0;
    std::vector<T> samples;

    Plane() = default;
    /// Makes a \a w × \a h plane filled with \a fill. \pre w ≥ 0, h ≥ 0.
    Plane(int w, int h, T fill = T{})
        : width(w), height(h),
          samples(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill)
    {
    }

    [[nodiscard]] bool empty() const noexcept { return samples.empty(); }
    /// Number of samples (width·height).
    [[nodiscard]] std::size_t size() const noexcept { return samples.size(); }
    /// Index of sample (x, y). \pre 0 ≤ x < width, 0 ≤ y < height (not checked).
    [[nodiscard]] std::size_t index(int x, int y) const noexcept
    {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
               static_cast<std::size_t>(x);
    }
    /// Sample (x, y). \pre inside the plane (not checked).
    [[nodiscard]] T &at(int x, int y) noexcept { return samples[index(x, y)]; }
    [[nodiscard]] const T &at(int x, int y) const noexcept { return samples[index(x, y)]; }
    /// Sample at (x, y) with coordinates clamped to the plane (replicated border). \pre !empty().
    [[nodiscard]] const T &clamped(int x, int y) const noexcept
    {
        x = x < 0 ? 0 : (x >= width ? width - 1 : x);
        y = y < 0 ? 0 : (y >= height ? height - 1 : y);
        return samples[index(x, y)];
    }
    /// True when both planes have the same width and height.
    template <class U> [[nodiscard]] bool sameSize(const Plane<U> &o) const noexcept
    {
        return width == o.width && height == o.height;
    }
};

} // namespace depthtouch::depth
