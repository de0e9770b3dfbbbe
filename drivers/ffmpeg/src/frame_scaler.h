#pragma once
/// \file
/// \brief Decoded frames of another size than their stream's, scaled to it: a stream whose
/// pictures change size part-way (a spliced broadcast, another rendition of an HLS ladder) plays
/// on at the size the session was set up for instead of losing every frame after the change.
/// Thread-safety: thread-bound (the decoder's caller). Allocates when the decoded size changes.

#include <cstdint>
#include <vector>

#include "depthtouch/av/av_handles.h"
#include "depthtouch/hal/types.h"
#include "depthtouch/platform/result.h"

extern "C" {
#include <libavutil/frame.h>
}

namespace depthtouch::drivers::ffmpeg {

/// \brief copyFrame() for a decoded frame of any size: the frame is converted at its own size
/// into a scratch image of the target's format (copyFrame()'s exact paths: luma as is, 10-bit
/// widened), then scaled to the target's size by libswscale in that format (no range
/// conversion): nearest-neighbour for depth and material codes, whose samples must stay codes that
/// were coded (an average of an object's edge and its backdrop is a surface nobody filmed),
/// bilinear for color.
class FrameScaler {
public:
    /// \brief Copies \a src into \a dst (caller-allocated, its own size and format), scaling when
    /// the sizes differ. \param nearest nearest-neighbour (depth, material), else bilinear.
    /// \return copyFrame()'s errors; OutOfResources when the scratch image cannot be allocated;
    /// NotSupported when libswscale has no scaler for the format.
    Result<void> copy(const AVFrame &src, const hal::ImageView &dst, bool nearest) noexcept;

private:
    Result<void> allocate(hal::PixelFormat format, int width, int height) noexcept;

    av::SwsPtr convert_; ///< copyFrame()'s context, at the decoded size.
    av::SwsPtr scale_;   ///< The scaler from the scratch image to the target.
    std::vector<std::uint8_t> bytes_;
    hal::ImageView scratch_;
};

} // namespace depthtouch::drivers::ffmpeg
