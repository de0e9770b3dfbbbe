#pragma once
/// \file
/// \brief A Kinect-v1-style depth sensor model for synthetic scenes: turns a clean metric depth
/// image into what a structured-light camera delivers (used by `depthtouch bench feel` and the
/// haptic scenario tests).
///
/// Effects, in this order, per frame:
///  1. **flying pixels**: on a silhouette (neighbours whose depths differ by more than
///     `edgeJump`·Z) a pixel takes, with probability `flyingProbability`, a depth between the
///     two sides (uniform in [0.2, 0.8] of the way);
///  2. **temporal flicker**: Gaussian noise on the disparity, σ_Z = `flickerSigma`·Z² m, drawn
///     anew for every pixel and frame;
///  3. **disparity quantisation**: 1/Z is rounded to multiples of `disparityStep` m⁻¹, i.e. a depth
///     step of `disparityStep`·Z² m (2.85e-3·Z²: 2.9 mm at 1 m, 11 mm at 2 m);
///  4. **holes** (0 = no return): the projector shadow left of every near-on-the-right silhouette,
///     `focalPx`·`baseline`·(1/Z_near − 1/Z_far) px wide; 1-px holes on either side of silhouettes
///     with probability `edgeHoleProbability`; a few random 3×3 speckle holes; depth out of
///     [`minRange`, `maxRange`].
/// Output is millimetres (rounded), 0 where invalid: the layout of a Kinect depth PNG, which
/// `depthtouch encode` reads with its default `--depth-scale 0.001`.
///
/// Sources: Khoshelham & Elberink, "Accuracy and resolution of Kinect depth data for indoor mapping
/// applications", Sensors 12 (2012) (σ_Z and the disparity step grow with Z²); Nguyen, Izadi &
/// Lovell, "Modeling Kinect sensor noise for improved 3D reconstruction and tracking", 3DIMPVT 2012
/// (lateral noise and flying pixels at edges). Deterministic: the same image, options, seed and
/// frame index give the same output. Thread-safety: reentrant (no shared state).

#include <cstdint>

#include "depthtouch/depth/plane.h"

namespace depthtouch::haptics::bench {

/// \brief Parameters of the sensor model (defaults: Kinect v1 at 640×480).
struct KinectNoiseOptions {
    double disparityStep = 2.85e-3; ///< Quantisation of 1/Z, m⁻¹ (depth step = this·Z², m).
    double flickerSigma = 1.5e-3;   ///< σ of 1/Z per frame, m⁻¹ (σ_Z = this·Z², m); 0 = off.
    double focalPx = 585.0;         ///< Focal length, px (shadow width).
    double baseline = 0.075; ///< Projector–camera baseline, m (shadow width); 0 = no shadow.
    double edgeJump = 0.03;  ///< Relative depth jump between neighbours that is a silhouette.
    double edgeHoleProbability = 0.4; ///< Per silhouette pixel and frame.
    double flyingProbability = 0.3;   ///< Per silhouette pixel and frame (when not a hole).
    double speckleProbability = 2e-5; ///< Per pixel and frame: seeds a 3×3 random hole.
    double minRange = 0.4;            ///< m: nearer is no return.
    double maxRange = 4.5;            ///< m: farther is no return.
    std::uint64_t seed = 1;           ///< Seed of the random effects.
};

/// \brief Applies the sensor model to one frame.
/// \param clean W×H depth along the optical axis, m (0 or non-finite: no surface, stays 0).
/// \param frameIndex picks this frame's random draws (flicker, holes) from the seed.
/// \return W×H sensor depth, mm (0 = invalid).
depth::Plane<std::uint16_t> applyKinectNoise(const depth::Plane<float> &clean,
                                             const KinectNoiseOptions &options,
                                             std::uint64_t frameIndex);

/// \brief A time-of-flight camera (Azure Kinect NFOV-like). Effects, in this order, per frame:
///  1. **flying pixels**: within `flyingWidth` px of a depth edge (neighbours differing by more
///  than
///     `edgeJump`·Z) a pixel mixes the two sides' returns, with probability `flyingProbability`: a
///     depth anywhere between them (uniform), where a structured-light camera mostly leaves a hole;
///  2. **multipath** near concave edges: light bounced off the neighbouring surface lengthens the
///     path; where the pixel is farther than the mean of its (2·`multipathRadius`+1)² window (a
///     corner, the foot of an object on a table), Z += `multipathGain`·(Z − mean);
///  3. **noise**: Gaussian, σ_Z = `sigma` + `sigmaRelative`·Z, anew every frame;
///  4. **holes** (0): too little light back on dark surfaces (\a dark mask) and saturation on near
///     ones (Z < `saturateRange`), each with probability `darkHoleProbability`; out of range.
/// Source: Tölgyessy et al., "Evaluation of the Azure Kinect and its comparison to Kinect V1 and
/// Kinect V2", Sensors 21 (2021) (σ of a few mm, flying pixels and multipath at edges, invalid
/// pixels on dark and saturated surfaces); the rgbd-azure-kinect-still capture shows all of them.
struct TofNoiseOptions {
    double sigma = 1.0e-3;          ///< m.
    double sigmaRelative = 1.0e-3;  ///< σ grows by this per m of Z.
    double edgeJump = 0.03;         ///< Relative depth jump between neighbours that is an edge.
    int flyingWidth = 2;            ///< px either side of an edge.
    double flyingProbability = 0.6; ///< Per pixel near an edge and frame.
    double multipathGain = 0.3;
    int multipathRadius = 6;           ///< px.
    double saturateRange = 0.5;        ///< m: nearer saturates.
    double darkHoleProbability = 0.85; ///< Per dark or saturated pixel and frame.
    double minRange = 0.25;            ///< m.
    double maxRange = 3.86;            ///< m (NFOV unbinned).
    std::uint64_t seed = 3;
};

/// \brief Applies the time-of-flight model to one frame. \param dark optional W×H mask, 1 where
/// the surface is dark (black print, hair). \return W×H sensor depth, mm (0 = invalid).
depth::Plane<std::uint16_t> applyTofNoise(const depth::Plane<float> &clean,
                                          const TofNoiseOptions &options, std::uint64_t frameIndex,
                                          const depth::Plane<std::uint8_t> *dark = nullptr);

/// \brief An active-stereo camera (RealSense D4xx-like). Effects, in this order, per frame:
///  1. **disparity noise, quantised**: d = f·B/Z, plus Gaussian noise of `subpixelSigma` px,
///     rounded to `subpixelStep` px: depth noise and steps growing with Z² (σ_Z = Z²·σ_d/(f·B));
///  2. **occlusion holes**: left of every near-on-the-right silhouette, f·B·(1/Z_near − 1/Z_far) px
///     wide (the right camera does not see that strip of the background), and 1-px holes on either
///     side of silhouettes with probability `edgeHoleProbability`;
///  3. **speckle outliers**: with probability `outlierProbability` a pixel reads a far wrong depth
///     (uniform in [`outlierNear`, `outlierFar`]: mismatched texture); 3×3 holes with probability
///     `speckleProbability`; depth out of [`minRange`, `maxRange`] is a hole.
/// Source: Intel, "Depth camera D400 series tuning" (RMS error ∝ Z²·subpixel/(f·B)); Giancola et
/// al., "A Survey on 3D Cameras" (2018); the rgbd-realsense-lab capture (holes behind near
/// objects, 5 % of valid pixels beyond 10 m).
struct StereoNoiseOptions {
    double focalPx = 585.0;        ///< px.
    double baseline = 0.050;       ///< m.
    double subpixelSigma = 0.08;   ///< px.
    double subpixelStep = 1.0 / 8; ///< px.
    double edgeJump = 0.03;
    double edgeHoleProbability = 0.3;
    double outlierProbability = 0.01;
    double outlierNear = 6.0; ///< m.
    double outlierFar = 15.0; ///< m.
    double speckleProbability = 5e-5;
    double minRange = 0.2;  ///< m.
    double maxRange = 16.0; ///< m.
    std::uint64_t seed = 5;
};

/// \brief Applies the active-stereo model to one frame. \return W×H sensor depth, mm (0 =
/// invalid).
depth::Plane<std::uint16_t> applyStereoNoise(const depth::Plane<float> &clean,
                                             const StereoNoiseOptions &options,
                                             std::uint64_t frameIndex);

/// \return \a zM rounded to the model's disparity quantisation, m (the depth step at Z is
/// `disparityStep`·Z²). \pre zM > 0.
double quantiseDisparity(double zM, double disparityStep) noexcept;

} // namespace depthtouch::haptics::bench
