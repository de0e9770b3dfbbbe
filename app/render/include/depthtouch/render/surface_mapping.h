#pragma once
/// \file
/// \brief The affine map from a depth sample to the scene box that the renderer draws with: the
/// scene layer's (depthtouch/scene/surface_mapping.h), the same one the haptic renderer touches
/// with.
///
/// Thread-safety: value type.

#include "depthtouch/scene/surface_mapping.h"

namespace depthtouch::render {

using scene::SurfaceMapping;

} // namespace depthtouch::render
