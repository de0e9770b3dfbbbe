#pragma once
/// \file
/// \brief The DRM PRIME frames of libavcodec (AV_PIX_FMT_DRM_PRIME: an AVDRMFrameDescriptor in
/// AVFrame::data[0], as h264_v4l2m2m exports them where the platform supports it) described as a
/// hal::DmaBufImage for zero-copy import by the renderer.
///
/// Thread-safety: pure function. The header names the libavutil type only by declaration.

#include "depthtouch/hal/types.h"
#include "depthtouch/platform/result.h"

struct AVDRMFrameDescriptor;

namespace depthtouch::drivers {

/// \brief Maps a libavutil DRM frame descriptor to the HAL's dma-buf image.
///
/// Accepted layouts (the ones decoders export and the renderer can import or read back):
/// - one layer of DRM_FORMAT_NV12 (2 planes) or DRM_FORMAT_YUV420 (3 planes), the planes in one
///   object or in several;
/// - one layer per plane ("separate layers", as some exporters describe YUV): R8 + GR88 is NV12,
///   R8 + R8 + R8 is YUV420.
///
/// Each plane takes the fd of its object; the modifier is the objects' (every plane must share
/// one). With a linear or implied modifier, every plane must fit its object when the object's size
/// is known (rows of `pitch` bytes, chroma rows rounded up) and `pitch` must hold a row.
/// \param[in] desc The descriptor; its fds are copied, not duplicated (the AVFrame owns them).
/// \param[in] width, height Frame size in pixels (AVFrame::width/height).
/// \return the image. Errors: NotSupported for an unknown layout (a format other than the above,
/// a plane count that does not match the format, other layer combinations, planes with different
/// modifiers); InvalidArgument for an inconsistent descriptor (no object or layer, more than 4
/// objects, layers or planes in all, an object index out of range, a negative fd, a zero pitch, a
/// plane outside its object, a non-positive size).
Result<hal::DmaBufImage> dmaBufFromDrmDescriptor(const AVDRMFrameDescriptor &desc, int width,
                                                 int height) noexcept;

} // namespace depthtouch::drivers
