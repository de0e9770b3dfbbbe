#pragma once
/// \file
/// \brief Occupancy embedded in the depth (docs/architecture.md §3 "Holes"): where the sensor
/// measured nothing, the depth stream carries a hole code under a threshold instead of an invented
/// surface, and measured nearness is lifted above a guard band.
///
/// Convention (as MPEG Immersive Video, ISO/IEC 23090-12, embeds occupancy in its geometry video:
/// a geometry sample under the depth occupancy threshold is unoccupied): a hole is coded 0; a
/// measured nearness level n ∈ [0, v_max] is coded `first + n·(v_max − first)/v_max`; a decoder
/// reads a sample below `threshold` as a hole. `first − threshold` is the guard band that lossy
/// coding's ringing at a hole's border must not cross. The threshold travels in the file as the
/// `depth_occupancy` tag (stream sample units); a file without it has no holes.
///
/// Thread-safety: constexpr value functions.

#include <cstdint>

namespace depthtouch::depth {

/// \brief The hole code's threshold and the lowest measured code of a depth stream.
struct Occupancy {
    std::uint32_t threshold = 0; ///< Samples below this are holes (0: no holes), stream units.
    std::uint32_t first = 0;     ///< The far plane's code (measured nearness 0), stream units.
};

/// \return the occupancy codes of a depth stream of \a bits significant bits (8, 10 or 16);
/// \a lossless: coded without loss (FFV1, x264 qp 0), so one code of guard is enough.
///
/// Lossy H.264 (\a bits 8 or 10): threshold 3/32 of the range (8-bit 24, 10-bit 96), the far plane
/// at twice that (48, 192), the threshold in the middle of the guard band. Measured on two real
/// clips with holes (docs/making-content.md "Holes"), x264 at the default --depth-crf 18: of the
/// 18.4 M samples of rgbd-bonn-crowd (16.5 % holes), 8-bit misreads 15 676 (0.085 %) with the
/// threshold at 16, 6 431 (0.035 %) at 24 and 3 461 (0.019 %) at 32; 10-bit the same at four
/// times the threshold. 24 halves the misreads of 16 for 7 % fewer measured levels; most misreads
/// left are holes of one or two samples that the codec blurs into their surroundings.
constexpr Occupancy occupancyFor(int bits, bool lossless) noexcept
{
    if (lossless)
        return {1u, 2u};
    const std::uint32_t threshold = 3u << (bits - 5);
    return {threshold, 2u * threshold};
}

// scene::DepthFrameView::farCode() reads the far plane's code as twice the threshold.
static_assert(occupancyFor(8, false).first == 2 * occupancyFor(8, false).threshold &&
              occupancyFor(10, false).first == 2 * occupancyFor(10, false).threshold &&
              occupancyFor(16, true).first == 2 * occupancyFor(16, true).threshold);

/// \return the code of measured nearness \a n (levels of 0..\a vmax) under \a occ, same units.
constexpr double occupiedLevel(double n, double vmax, const Occupancy &occ) noexcept
{
    return occ.first + n * (vmax - occ.first) / vmax;
}

/// \return the hole threshold \a threshold of a stream of \a bits significant bits (1..16) in the
/// units of the same samples widened to 16 bits by bit replication (`v << (16 − bits) | …`, as the
/// decoders widen 10-bit depth): the smallest 16-bit value whose \a bits-bit source (its top \a
/// bits bits) is ≥ \a threshold, i.e. `threshold << (16 − bits)`. 0 stays 0 (no holes); \a bits ≥
/// 16 returns \a threshold unchanged.
constexpr std::uint32_t widenedThreshold(std::uint32_t threshold, int bits) noexcept
{
    return bits >= 16 || bits < 1 ? threshold : threshold << (16 - bits);
}

} // namespace depthtouch::depth
