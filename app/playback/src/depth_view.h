#pragma once
/// \file
/// \brief The one mapping of the player's decoded depth frames (hal::PixelFormat Gray8/Gray16) to
/// the haptics' sample format and frame view, used for the hand-off, the renderer and the prep
/// worker alike.
///
/// Thread-safety: reentrant; no allocation.

#include "depthtouch/hal/types.h"
#include "depthtouch/haptics/depth_frame.h"
#include "depthtouch/receiver/receiver.h"

namespace depthtouch::playback {

/// \return SampleFormat::Gray16 for PixelFormat::Gray16, else SampleFormat::Gray8 (the decoders
/// give depth as Gray8 or Gray16 only).
scene::SampleFormat sampleFormatOf(hal::PixelFormat format) noexcept;

/// \return a view of the decoded depth frame \a f (plane 0, its stride, its hole threshold
/// StoredFrame::holeBelow) with PTS \a pts (s). The view borrows \a f's pixels: keep \a f alive
/// while the view is used.
scene::DepthFrameView depthView(const receiver::StoredFrame &f, double pts) noexcept;

/// \return a view of the material frame \a f (Rgb24 codes, scene/material.h) of a depth frame of
/// \a width × \a height, or an empty view when \a f is null, not Rgb24 or of another size.
/// Borrows \a f's pixels.
scene::MaterialView materialView(const receiver::StoredFrame *f, int width, int height) noexcept;

} // namespace depthtouch::playback
