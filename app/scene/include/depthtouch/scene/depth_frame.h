#pragma once
/// \file
/// \brief The scene geometry that the haptic renderer and the stereo renderer share: the scene box
/// a depth frame fills, the storage of a nearness sample, and a borrowed view of a W×H depth frame
/// (docs/architecture.md §3). What is seen and what is touched are one surface because both read it
/// from here.
///
/// Thread-safety: value types; a view does not own its pixels (the caller keeps them alive).

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "depthtouch/platform/result.h"
#include "depthtouch/scene/material.h"

namespace depthtouch::scene {

/// \brief Size of the scene box a depth frame fills (docs/architecture.md §3). Metres.
///
/// The frame's W columns span `width` along x, its H rows span `width·(H−1)/(W−1)` along y, and
/// nearness 0..v_max spans `depth` along z, centred on the origin.
struct SceneBox {
    double width = 0.10; ///< Box width along x, m (> 0).
    double depth = 0.04; ///< Box depth along z, m (> 0).
};

/// \brief Storage of one nearness sample.
enum class SampleFormat : std::uint8_t {
    Gray8,  ///< One byte per sample, v_max = 255.
    Gray16, ///< Two bytes per sample in host byte order, v_max = 65535.
};

/// \return bytes per sample of \a format (1 or 2).
constexpr std::size_t bytesPerSample(SampleFormat format) noexcept
{
    return format == SampleFormat::Gray8 ? 1u : 2u;
}

/// \return v_max of \a format (255 or 65535).
constexpr double maxSampleValue(SampleFormat format) noexcept
{
    return format == SampleFormat::Gray8 ? 255.0 : 65535.0;
}

/// \brief A borrowed W×H nearness image (0 = farthest, v_max = nearest) with its presentation time.
///
/// Row r starts at `data + r·strideBytes`; sample (c, r) is the c-th sample of that row.
/// The view never owns or frees the pixels.
struct DepthFrameView {
    const std::uint8_t *data = nullptr; ///< First byte of row 0; not owned.
    int width = 0;                      ///< W, samples per row (≥ 2).
    int height = 0;                     ///< H, rows (≥ 2).
    std::size_t strideBytes = 0;        ///< Bytes from one row to the next (≥ W·bytesPerSample).
    SampleFormat format = SampleFormat::Gray8; ///< Sample storage.
    double pts = 0.0;                          ///< Presentation time, s.
    /// Per-pixel haptic material on the same W×H grid (material.h); absent (data null) for video
    /// without a material track.
    MaterialView material{};
    /// Occupancy embedded in the depth (docs/architecture.md §3 "Holes"): a sample whose value is
    /// below this is a hole, where the sensor measured nothing. It is free space to the haptic
    /// renderer and is not drawn as a surface. 0 (the default, and every file without the
    /// `depth_occupancy` tag): every sample was measured. In the frame's own sample units.
    std::uint32_t holeBelow = 0;

    /// \return the code of the far plane (nearness 0) of a frame with holes, in its sample units:
    /// 2·holeBelow, since measured nearness is coded above a guard band as wide as the threshold
    /// (depth/occupancy.h: `first = 2·threshold`); 0 without holes. The surface spans the codes
    /// farCode()..v_max (SurfaceMapping, HeightField), so a scene has the same depth with or
    /// without its holes kept.
    [[nodiscard]] std::uint32_t farCode() const noexcept { return 2u * holeBelow; }

    /// \return true when sample (c, r) was measured (not a hole). \pre 0 ≤ c < W, 0 ≤ r < H.
    [[nodiscard]] bool measured(int c, int r) const noexcept { return sample(c, r) >= holeBelow; }

    /// \brief Checks the shape: data present, W, H ≥ 2, stride large enough, finite PTS, and a
    /// material's stride (when present) at least 3·W.
    /// \return Errc::InvalidArgument with a static message when malformed.
    [[nodiscard]] Result<void> validate() const noexcept;

    /// \return the raw sample value at column \a c, row \a r. \pre 0 ≤ c < W, 0 ≤ r < H.
    [[nodiscard]] std::uint32_t sample(int c, int r) const noexcept
    {
        const std::uint8_t *p = data + static_cast<std::size_t>(r) * strideBytes +
                                static_cast<std::size_t>(c) * bytesPerSample(format);
        if (format == SampleFormat::Gray8)
            return *p;
        std::uint16_t v;
        std::memcpy(&v, p, sizeof v);
        return v;
    }
};

} // namespace depthtouch::scene
