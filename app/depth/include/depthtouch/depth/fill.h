#pragma once
/// \file
/// \brief Filling invalid depth samples (holes) from their valid neighbours, before encoding.
///
/// Method: **push-pull (pyramid) interpolation** (Gortler et al., "The Lumigraph", 1996, §3.4):
///  - pull: build a pyramid by halving the grid; each coarse cell holds the mean of the valid
///  samples in
///    its 2×2 children (a cell with no valid child stays empty); repeat until a level has no empty
///    cell;
///  - push: from the coarsest level down, each empty cell takes the bilinear interpolation of the
///  (complete)
///    level above; cells with data keep it.
/// Valid samples are never changed. Each filled value is a convex combination of valid samples, so
/// it lies within [min, max] of the valid data: a hole is never set to the far plane (0) unless
/// every valid sample is 0, and a hole inside a region of constant depth gets exactly that depth.
/// Large holes get smooth, coarse-scale values; holes of any size and shape are filled in O(W·H).
/// Kinect "shadow" holes beside a foreground edge receive a blend of foreground and background
/// depth, not the background alone.
///
/// Paper §V.B (holes and noise of depth-camera data). Thread-safety: reentrant.

#include <cstddef>
#include <cstdint>

#include "depthtouch/depth/plane.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::depth {

/// \brief Fills every sample of \a nearness whose \a valid flag is 0 (push-pull, see the file
/// comment). \param[in,out] nearness W×H nearness levels (any unit works: the fill is unit-free)
/// \param[in] valid W×H flags, 1 = measured, 0 = hole
/// \return the number of filled samples; Errc::InvalidArgument when the sizes differ or the plane
/// is empty,
///         Errc::InvalidArgument when no sample is valid (nothing to fill from; \a nearness
///         unchanged).
Result<std::size_t> fillInvalid(Plane<float> &nearness, const Plane<std::uint8_t> &valid);

} // namespace depthtouch::depth
