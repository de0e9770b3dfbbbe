#pragma once
/// \file
/// \brief Resampling a depth map to another grid (depth to the color grid, or to `--size`).
///
/// Sample centres are aligned: output sample (x, y) looks at source position
/// `((x + 0.5)·Ws/W − 0.5, (y + 0.5)·Hs/H − 0.5)`.
///  - Nearest: the closest source sample; never invents depths between a foreground and a
///  background
///    ("flying pixels"), blocky when upscaling.
///  - EdgeAware: bilinear interpolation of the 2×2 source neighbours when their range (max − min)
///  is at
///    most \a edgeThreshold levels, otherwise the nearest sample: smooth on surfaces, sharp at
///    depth discontinuities.
/// Resample after fillInvalid() (holes would otherwise leak into their neighbours), or keep the
/// holes with resampleMasked().
/// Thread-safety: reentrant.

#include <cstdint>

#include "depthtouch/depth/plane.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::depth {

enum class ResampleMethod : std::uint8_t { Nearest, EdgeAware };

/// \brief Resamples \a src (Ws×Hs, nearness levels) to \a width × \a height.
/// \param[in] edgeThreshold EdgeAware only: largest 2×2 range (nearness levels) still interpolated
/// \return the W×H plane; Errc::InvalidArgument when \a src is empty or the size is not positive.
Result<Plane<float>> resample(const Plane<float> &src, int width, int height,
                              ResampleMethod method = ResampleMethod::EdgeAware,
                              float edgeThreshold = 4.0f);

/// \brief Resamples measured depth with its holes kept (docs/architecture.md §3 "Holes"): the
/// output mask is the nearest source flag (resampleNearest(), so a hole keeps its shape and size);
/// an output sample that is measured is EdgeAware over the measured ones of its 2×2 source
/// neighbours only (bilinear weights renormalised over them when their range is at most
/// \a edgeThreshold, else the measured neighbour of largest weight), so no hole value blends into
/// measured depth. Output holes are 0.
/// \param[in] src Ws×Hs nearness levels; \param[in] valid Ws×Hs flags (1 measured, 0 hole)
/// \param[out] validOut the W×H flags of the result
/// \return the W×H plane; Errc::InvalidArgument when \a src is empty, \a valid another size or
/// the size is not positive.
Result<Plane<float>> resampleMasked(const Plane<float> &src, const Plane<std::uint8_t> &valid,
                                    int width, int height, float edgeThreshold,
                                    Plane<std::uint8_t> &validOut);

/// \brief Nearest-sample resampling of any plane (e.g. a validity mask). Same alignment as
/// resample(). \pre src non-empty, width > 0, height > 0 (an empty plane is returned otherwise).
template <class T> Plane<T> resampleNearest(const Plane<T> &src, int width, int height)
{
    if (src.empty() || width <= 0 || height <= 0)
        return {};
    Plane<T> out(width, height);
    for (int y = 0; y < height; ++y) {
        const int sy = static_cast<int>((static_cast<double>(y) + 0.5) * src.height / height);
        for (int x = 0; x < width; ++x) {
            const int sx = static_cast<int>((static_cast<double>(x) + 0.5) * src.width / width);
            out.at(x, y) = src.clamped(sx, sy);
        }
    }
    return out;
}

} // namespace depthtouch::depth
