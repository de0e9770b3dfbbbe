#pragma once
/// \file
/// \brief Test helpers of the receiver: small color + depth clips written with libavformat and
/// libavcodec (no command-line tool needed), and receivers opened on the ffmpeg backends.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "depthtouch/hal/media_source.h"
#include "depthtouch/receiver/receiver.h"
#include "test_support.h"

namespace depthtouch::receivertest {

/// One video stream of a test clip.
struct ClipStream {
    bool enabled = true;
    std::string title;             ///< Empty: no title tag.
    bool gray = false;             ///< 4:0:0 depth content (pix_fmt gray) instead of yuv420p.
    int width = 64;                ///< Pixels.
    int height = 48;               ///< Pixels.
    int fps = 30;                  ///< Frame rate; the stream time base is 1/fps.
    int frames = 10;               ///< Frames to encode.
    std::vector<std::int64_t> pts; ///< Optional PTS of each frame in 1/fps units (default: index).
    std::string encoder = "libx264";  ///< libavcodec encoder name: libx264, ffv1, mpeg4...
    bool lossless = false;            ///< libx264 at qp 0 (depth round-trips bit-exact).
    int bframes = 0;                  ///< B-frames (decoders then hold frames back).
    int texture = 0;                  ///< Amplitude of a moving noise texture (0: smooth pattern).
    std::string preset = "ultrafast"; ///< libx264 preset.
    std::vector<std::pair<std::string, std::string>> metadata; ///< Extra stream tags.
};

/// A clip: a color and a depth stream (either may be disabled), in this order.
struct Clip {
    ClipStream color;
    ClipStream depth;
    std::string format; ///< libavformat muxer; empty: from the file extension.
    int gop = 10;       ///< Keyframe interval.

    /// The docs/architecture.md §4 layout: titled color (yuv420p H.264) + depth (gray H.264) with
    /// metadata.
    static Clip standard(int width = 64, int height = 48, int frames = 10, int fps = 30);
};

/// Writes \a clip to \a path. \return an empty string on success, else what failed.
std::string writeClip(const std::string &path, const Clip &clip);

/// The sample value of the depth test pattern at (x, y) of frame \a frame.
std::uint8_t depthPattern(int x, int y, int frame) noexcept;

/// Receiver on the ffmpeg source and ffmpeg decoders (`threads` slice threads per decoder).
/// Defined in open_ffmpeg.cpp (links dt_drivers).
Result<std::unique_ptr<receiver::Receiver>>
openFfmpeg(const std::string &path, const receiver::ReceiverConfig &cfg = {}, int threads = 1);

} // namespace depthtouch::receivertest
