#pragma once
/// \file
/// \brief Depth frames as the haptic renderer sees them: the scene layer's types
/// (depthtouch/scene/depth_frame.h, docs/architecture.md §3), named unqualified inside the haptics
/// namespace. Code outside it spells them `scene::DepthFrameView`, `scene::SceneBox`, … (one name
/// for the borrowed view of a depth frame in every layer).
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
