#pragma once
/// \file
/// \brief Image filters and surface measures used by the depth enhancement (paper §V.B).
/// Borders are handled by replicating the edge samples. Thread-safety: reentrant.

#include "depthtouch/depth/plane.h"

namespace depthtouch::depth {

/// \brief Median filter over a (2·radius+1)² square window (paper §V.B step 1: removes impulse
/// noise and speckle while keeping step edges). \param[in] src W×H samples (nearness levels)
/// \param[in] radius window half-size in pixels (0 = copy) \return W×H filtered plane.
Plane<float> medianFilter(const Plane<float> &src, int radius);

/// \brief First-order gradient magnitude by the Sobel operator, normalised to levels per pixel
/// (a ramp rising by g levels per pixel gives g). \return W×H plane.
Plane<float> gradientMagnitude(const Plane<float> &src);

/// \brief 4-neighbour discrete Laplacian `4·v − Σ neighbours` (levels); zero on any plane. \return
/// W×H plane.
Plane<float> laplacian(const Plane<float> &src);

/// \brief Maximum over a (2·radius+1)² window (grey dilation). \return W×H plane.
Plane<float> maxFilter(const Plane<float> &src, int radius);

} // namespace depthtouch::depth
