#pragma once
/// \file
/// \brief Whether one variant of an HLS multivariant input can stand in for another under the
/// same stream numbers (rendition_switch.h): the receiver's decoders are opened once, for the
/// streams of the variant read at open, and go on decoding whatever packets come under those
/// numbers. A variant whose video stream has another codec (HEVC depth for H.264 depth), another
/// pixel format (planes) or bit depth, or out-of-band parameter sets (avcC/hvcC extradata) that
/// differ, cannot: its packets would not decode (every picture a decode error, the depth surface
/// frozen). Sizes may differ: the decoder scales pictures to the stream's size (frame_scaler.h).
/// Sound: codec, sample rate and channels. Streams are matched by kind and order within their
/// program, as the switch maps them.
/// Thread-safety: reentrant (reads \a ctx only).

#include <string>

extern "C" {
#include <libavutil/avutil.h>
}

struct AVFormatContext;
struct AVProgram;

namespace depthtouch::drivers::ffmpeg {

/// \return the libav index of the \a ordinal-th stream of \a type in program \a p, or -1.
int streamOfKind(const AVFormatContext &ctx, const AVProgram &p, AVMediaType type, int ordinal);

/// \brief Compares program \a other of \a ctx with program \a playing (indices into
/// ctx.programs), stream by stream (video and sound, by kind and order).
/// \return "" when \a other's streams decode with the decoders opened for \a playing's; else
/// why not, for a log line (e.g. "its video stream 1 is hevc gray 8-bit where the playing
/// rendition's is h264 yuv420p 8-bit").
std::string renditionMismatch(const AVFormatContext &ctx, int playing, int other);

} // namespace depthtouch::drivers::ffmpeg
