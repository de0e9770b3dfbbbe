#pragma once
/// \file
/// \brief Which stream of an input file `depthtouch encode` reads in each role (color, depth,
/// material), found as `play` and `probe` find them: the file opened by the ffmpeg media source
/// (drivers::createMediaSource("ffmpeg")), its streams named by receiver::identifyStreams() (an
/// MKV title, an MP4 handler name, DepthTouch's MPEG-TS timed metadata and stream order, depth
/// tags, a gray pixel format), and the depth stream's tags as that source reads them (a DepthTouch
/// MPEG-TS file carries them in its timed metadata, not as stream tags). So a DepthTouch file in
/// any container play reads is transcoded from its own depth stream, with its planes, holes and
/// material track (docs/making-content.md "Holes"). Private to app/cli. Thread-safety: reentrant.

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "depthtouch/hal/media_source.h"
#include "depthtouch/receiver/stream_roles.h"

namespace depthtouch::cli {

/// \brief The streams of one input file by role, as play identifies them.
struct InputStreams {
    /// Container stream numbers (hal::StreamInfo::containerIndex, for
    /// media::SourceOptions::streamIndex) of the color, depth and material streams; -1: none.
    int color = -1;
    int depth = -1;
    int material = -1;
    /// The depth stream as play reads it (pixel format, depth tags); meaningful when depth >= 0.
    hal::StreamInfo depthStream;

    /// \return whether the depth stream carries depth tags (receiver::hasDepthMetadata(): a
    /// DepthTouch file, whose samples are nearness codes with its own hole threshold).
    [[nodiscard]] bool depthTouch() const noexcept;
    /// \return the container stream number of \a role ("color", "depth" or "material"); -1 when
    /// the file has no stream in that role (or another role is asked).
    [[nodiscard]] int streamOf(std::string_view role) const noexcept;
    /// \return the depth stream's tags as text, keys lower-case (depth_near, depth_far in metres,
    /// depth_mapping, depth_bits, depth_occupancy: those it has; none for a file that is no
    /// DepthTouch file), for media::SourceOptions::tags.
    [[nodiscard]] std::vector<std::pair<std::string, std::string>> depthTags() const;
};

/// \return the streams of input \a spec by role when it is a regular file the ffmpeg media source
/// opens (\a single: what a file of one video stream is, receiver::SingleStream); nullopt for any
/// other input (a URL or FIFO, which cannot be read twice; an image sequence; `v4l2:` and
/// `synthetic:` specs) and for a file that source cannot open (encode's own open reports why).
std::optional<InputStreams> identifyInputStreams(const std::string &spec,
                                                 receiver::SingleStream single);

} // namespace depthtouch::cli
