#pragma once
/// \file
/// \brief An HLS rendition ladder (`encode --renditions`): the same picture, depth, material and
/// sound at several sizes, each rendition a media playlist of its own with every stream in its
/// segments, and a multivariant (master) playlist that names them (RFC 8216 §4.3.4.2, Apple's HLS
/// authoring specification), so that a player on a slower link takes a smaller one.
///
/// Why each rendition is a muxer of its own and the multivariant playlist is written here:
/// libavformat's HLS muxer makes a ladder only from `var_stream_map`, which maps video, audio and
/// subtitle streams and refuses the timed ID3 metadata stream that carries the depth tags in
/// MPEG-TS (timed_metadata.h). Its media playlists and segments are still libavformat's.
///
/// Names: the output `dir/show.m3u8` is the multivariant playlist; rendition `H` (its height in
/// pixels) is `dir/show_Hp.m3u8`, its segments `dir/show_HpN.ts` (the HLS muxer's own naming).
///
/// Thread-safety: the encode's thread only.

#include <string>
#include <vector>

#include "depthtouch/platform/result.h"

namespace depthtouch::media::detail {

/// \brief One rendition of the ladder.
struct RenditionPlan {
    int width = 0;        ///< Pixels, even.
    int height = 0;       ///< Pixels, even.
    std::string playlist; ///< Its media playlist's path.
    std::string uri;      ///< The same, relative to the multivariant playlist.
};

/// \brief The renditions of \a heights (pixels, tallest first, as checked by
/// EncodeOptions::validate()) for a picture of \a width × \a height and the multivariant playlist
/// \a master: widths keep the picture's aspect, rounded to even.
/// \return them; Errc::InvalidArgument when a rendition is taller than the picture.
Result<std::vector<RenditionPlan>>
planRenditions(const std::string &master, const std::vector<int> &heights, int width, int height);

/// \brief The peak segment bit rate of RFC 8216 §4.3.4.2 (BANDWIDTH): the largest bit rate of a
/// run of consecutive segments lasting 0.5 to 1.5 target durations.
/// \param[in] bytes each segment's size; \param[in] seconds each one's duration (same length)
/// \param[in] target the target duration (s)
/// \return bits/s; 0 when no run qualifies (no segment yet).
long long peakBitRate(const std::vector<long long> &bytes, const std::vector<double> &seconds,
                      double target);

/// \brief A rendition's figures in the multivariant playlist.
struct RenditionRate {
    long long peak = 0;    ///< BANDWIDTH, bits/s.
    long long average = 0; ///< AVERAGE-BANDWIDTH, bits/s; 0: not written (unknown yet).
};

/// \return the multivariant playlist naming \a plans (tallest first) with \a rates (same length)
/// and the frame rate \a fps: `#EXT-X-INDEPENDENT-SEGMENTS` (every segment starts at a key frame
/// of every stream), then `#EXT-X-STREAM-INF` with BANDWIDTH, AVERAGE-BANDWIDTH when known,
/// RESOLUTION and FRAME-RATE, and the URI.
std::string multivariantPlaylist(const std::vector<RenditionPlan> &plans,
                                 const std::vector<RenditionRate> &rates, double fps);

} // namespace depthtouch::media::detail
