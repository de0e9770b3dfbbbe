#pragma once
/// \file
/// \brief Metric depth (sensor units, e.g. mm) → nearness levels, and back (docs/architecture.md §3
/// "Metric depth input").
///
/// Nearness v is what the depth stream carries: 0 = far plane, v_max = near plane (255 for 8-bit,
/// 65535 for 16-bit), brighter is nearer. Two mappings from metric depth Z (metres) with planes
/// near < far:
///  - InverseZ (MPEG 3DV): `v = v_max·(1/Z − 1/far)/(1/near − 1/far)`; uniform in disparity, so
///  near
///    objects get more levels;
///  - Linear: `v = v_max·(far − Z)/(far − near)`.
/// Depth outside [near, far] is clamped to v_max or 0. Invalid raw samples (0, or ≥ the sensor's
/// saturation value such as 65535) are flagged, never mapped: fill them with fillInvalid() (fill.h)
/// before encoding.
///
/// Paper: Cha et al., "3D video player system with haptic interaction based on depth image-based
/// representation", §V.A (depth video from a depth camera) and §V.B (its noise and holes).
/// Thread-safety: every function is reentrant (no shared state).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "depthtouch/depth/occupancy.h"
#include "depthtouch/depth/plane.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::depth {

/// \brief How metric depth maps to nearness levels.
enum class DepthMapping : std::uint8_t {
    InverseZ, ///< MPEG 3DV 1/Z mapping (default).
    Linear,   ///< Linear in Z.
};

/// \return "inverse_z" or "linear": the value of the container's `depth_mapping` tag and of
/// `--depth-mapping`.
const char *mappingName(DepthMapping mapping) noexcept;
/// Parses "inverse_z" (also "inverse", "1/z", "mpeg") or "linear".
/// \return the mapping, or Errc::InvalidArgument for any other text.
Result<DepthMapping> parseMapping(std::string_view text) noexcept;

/// \brief The near and far clipping planes in metres. Valid when 0 < nearM < farM.
struct DepthRange {
    double nearM = 0.5;
    double farM = 4.0;
};

/// \brief How raw 16-bit depth samples are to be read.
struct RawDepthFormat {
    /// Metres per raw unit (`--depth-scale`): 0.001 for millimetres (Kinect, 7-Scenes), 0.0002 for
    /// TUM (1/5000 m).
    double metresPerUnit = 0.001;
    /// Raw values ≥ this are invalid (sensor saturation / "no return"). 0 is always invalid.
    std::uint16_t saturation = 65535;

    /// True when \a raw is a measurement (not 0 and below the saturation value).
    [[nodiscard]] constexpr bool isValid(std::uint16_t raw) const noexcept
    {
        return raw != 0 && raw < saturation;
    }
};

/// \brief Metric depth Z (metres) → nearness level in [0, vmax], clamped at the planes.
/// \param[in] zM depth in metres (> 0)
/// \param[in] range near/far planes (metres), 0 < near < far
/// \param[in] vmax nearness of the near plane (255 or 65535)
double metresToNearness(double zM, DepthRange range, DepthMapping mapping, double vmax) noexcept;

/// \brief Inverse of metresToNearness() for v in [0, vmax]: nearness level → metres in [near, far].
double nearnessToMetres(double v, DepthRange range, DepthMapping mapping, double vmax) noexcept;

/// \brief Share of the valid samples a 10 % step of depth (z/1.1, z] must hold to count as part of
/// the scene at the far end (kTailStep): 0.5 %. The scene's surfaces hold more; the far tail of an
/// active-stereo sensor (IR-stereo mismatches and low-texture or distant surfaces, whose disparity
/// noise of a pixel or two spreads them over tens of metres) holds less: on the RealSense clip of
/// ../shared/data 1.8 % of the samples of the first frames read 10..61 m, at most 0.3 % a step.
inline constexpr double kTailDensity = 0.005;
/// Ratio of depth of one step of the far-tail test: 10 %.
inline constexpr double kTailStep = 1.1;

/// \brief The near/far planes of robustRange() with what they were taken from.
struct RangeEstimate {
    DepthRange range{};          ///< The planes (metres).
    double medianM = 0.0;        ///< Median depth of the valid samples.
    double quantileFarM = 0.0;   ///< The highFraction quantile: the far plane before a tail cut.
    double maxM = 0.0;           ///< Farthest valid sample.
    double beyondFraction = 0.0; ///< Share of the valid samples farther than range.farM.
    bool tailCut = false; ///< The far plane was pulled in from quantileFarM (a sparse far tail).
};

/// \brief Near/far planes from the valid data's robust range: the \a lowFraction and \a
/// highFraction quantiles of the valid samples' depth (default 1 % and 99 %), so a few outliers do
/// not waste levels; then a sparse far tail is cut: the far plane is the farthest valid depth z, at
/// most that quantile, whose 10 % step (z/1.1, z] holds at least kTailDensity of the valid samples
/// (sparse far speckles never do, however many metres they spread over).
/// \param[in] raw W×H raw depth (units of \a format.metresPerUnit) \return the range in metres and
/// what it was taken from; a degenerate range (flat scene) is widened to ±1 % around its depth.
///         Errc::InvalidArgument when there is no valid sample or the fractions are not 0 ≤ low <
///         high ≤ 1.
Result<RangeEstimate> estimateRange(const Plane<std::uint16_t> &raw, const RawDepthFormat &format,
                                    double lowFraction = 0.01, double highFraction = 0.99);

/// \brief estimateRange()'s planes.
Result<DepthRange> robustRange(const Plane<std::uint16_t> &raw, const RawDepthFormat &format,
                               double lowFraction = 0.01, double highFraction = 0.99);

/// \brief Options of metricToNearness().
struct ConvertOptions {
    RawDepthFormat raw{};                          ///< Units and invalid values of the input.
    DepthMapping mapping = DepthMapping::InverseZ; ///< `--depth-mapping`.
    double vmax = 255.0;                           ///< Output scale: 255 (8-bit) or 65535 (16-bit).
    std::optional<DepthRange> range; ///< Given `--near/--far`; nullopt → robustRange().
    double lowFraction = 0.01;       ///< Quantiles used when range is nullopt.
    double highFraction = 0.99;
};

/// \brief A depth frame in nearness levels with its validity mask.
struct NearnessFrame {
    Plane<float>
        nearness; ///< W×H nearness levels in [0, vmax]; 0 where invalid (fill before use!).
    Plane<std::uint8_t> valid; ///< W×H: 1 = measured, 0 = invalid (hole).
    DepthRange
        range{}; ///< Planes used (metres): write to the container's depth_near/depth_far tags.
    std::size_t invalidCount = 0; ///< Number of zeros in \a valid.
};

/// \brief Converts raw metric depth to nearness (unfilled).
/// \param[in] raw W×H raw samples (e.g. a 16-bit depth PNG in mm)
/// \return the frame, or Errc::InvalidArgument when the plane is empty, vmax ≤ 0, metresPerUnit ≤
/// 0, the given
///         range is not 0 < near < far, or no sample is valid while the range must be estimated.
Result<NearnessFrame> metricToNearness(const Plane<std::uint16_t> &raw,
                                       const ConvertOptions &options);

/// \brief 8-bit nearness passes through: each sample becomes a float level, every sample valid.
/// The planes are unknown here (they travel with the source): \a range is left at its defaults.
NearnessFrame nearnessFrom8Bit(const Plane<std::uint8_t> &nearness8);

/// \brief Rounds nearness levels to integers in [0, vmax] (the encoder's input).
/// \param[in] vmax 255 or 65535 (values above 65535 are clamped to 65535)
Plane<std::uint16_t> quantize(const Plane<float> &nearness, double vmax);

/// \brief Rounds nearness to the codes of a stream with holes (occupancy.h): a sample whose \a
/// valid flag is 0 becomes 0, a measured level n (clamped to [0, vmax]) becomes
/// round(occupiedLevel(n, vmax, occ)). An empty \a valid means every sample was measured.
/// \param[out] holes the number of hole samples written
/// \pre \a valid is empty or the size of \a nearness; 0 < vmax ≤ 65535.
Plane<std::uint16_t> quantizeOccupied(const Plane<float> &nearness,
                                      const Plane<std::uint8_t> &valid, double vmax,
                                      const Occupancy &occ, std::size_t &holes);

/// \brief One frame of a metric depth clip as nearness levels of another size:
/// metricToNearness() (default options but \a range and \a vmax), holes filled (fillInvalid()),
/// resampled to \a width × \a height (resample(), edge-aware) and rounded (quantize()).
/// \param[in,out] range the planes to convert with, or nullopt for the frame's robust range; set to
/// the planes used, so that the next frame of the clip keeps them.
/// \param[in] vmax 255 (8-bit levels) or 65535 (16-bit)
/// \return the W×H levels (0..vmax), or the error of the first step that failed.
Result<Plane<std::uint16_t>> metricToLevels(const Plane<std::uint16_t> &raw,
                                            std::optional<DepthRange> &range, int width, int height,
                                            double vmax);

/// \return metricToLevels() with vmax 255.
inline Result<Plane<std::uint16_t>> metricToLevels8(const Plane<std::uint16_t> &raw,
                                                    std::optional<DepthRange> &range, int width,
                                                    int height)
{
    return metricToLevels(raw, range, width, height, 255.0);
}

} // namespace depthtouch::depth
