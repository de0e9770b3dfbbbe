#pragma once
/// \file
/// \brief Depth frames as the haptic renderer sees them: the scene layer's types
/// (depthtouch/scene/depth_frame.h, docs/architecture.md §3) under the haptics namespace, where the
/// renderer and its callers name them.
///
/// Thread-safety: value types; a view does not own its pixels (the caller keeps them alive).

#include "depthtouch/scene/depth_frame.h"

namespace depthtouch::haptics {

using scene::bytesPerSample;
using scene::DepthFrameView;
using scene::maxSampleValue;
using scene::SampleFormat;
using scene::SceneBox;

} // namespace depthtouch::haptics
