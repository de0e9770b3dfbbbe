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
    double disparityStep = 2.85e-3;  ///< Quantisation of 1/Z, m⁻¹ (depth step = this·Z², m).
    double flickerSigma = 1.5e-3;    ///< σ of 1/Z per frame, m⁻¹ (σ_Z = this·Z², m); 0 = off.
    double focalPx = 585.0;          ///< Focal length, px (shadow width).
    double baseline = 0.075; ///< Projector–camera baseline, m (shadow width); 0 = no shadow.
    double edgeJump = 0.03;  ///< Relative depth jump between neighbours that is a silhouette.
    double edgeHoleProbability = 0.4;   ///< Per silhouette pixel and frame.
    double flyingProbability = 0.3;     ///< Per silhouette pixel and frame (when not a hole).
    double speckleProbability = 2e-5;   ///< Per pixel and frame: seeds a 3×3 random hole.
    double minRange = 0.4;           ///< m: nearer is no return.
    double maxRange = 4.5;           ///< m: farther is no return.
    std::uint64_t seed = 1;          ///< Seed of the random effects.
};

/// \brief Applies the sensor model to one frame.
/// \param clean W×H depth along the optical axis, m (0 or non-finite: no surface, stays 0).
/// \param frameIndex picks this frame's random draws (flicker, holes) from the seed.
/// \return W×H sensor depth, mm (0 = invalid).
depth::Plane<std::uint16_t> applyKinectNoise(const depth::Plane<float> &clean,
                                             const KinectNoiseOptions &options,
                                             std::uint64_t frameIndex);

/// \return \a zM rounded to the model's disparity quantisation, m (the depth step at Z is
/// `disparityStep`·Z²). \pre zM > 0.
double quantiseDisparity(double zM, double disparityStep) noexcept;

} // namespace depthtouch::haptics::bench
