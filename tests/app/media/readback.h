#pragma once
/// \file
/// \brief Test support: reads an encoded file back with libavformat + libavcodec, as ffprobe and a
/// receiver would: container and stream metadata, codec facts, every frame's PTS and samples.

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "depthtouch/media/image.h"

namespace depthtouch::media::test {

/// One decoded stream.
struct StreamReadback {
    std::string codec;   ///< e.g. "h264", "ffv1".
    std::string profile; ///< e.g. "High 4:4:4 Predictive" ("" when none).
    std::string pixFmt;  ///< Decoder output format, e.g. "yuvj420p", "gray16le".
    int width = 0;
    int height = 0;
    std::map<std::string, std::string> tags; ///< Keys lower-cased (MKV writes them upper-case).
    std::vector<double> pts;                 ///< Seconds, in decode output (presentation) order.
    /// Frames: the luma plane as Gray8 (8-bit) / Gray16 (deeper) for gray or depth streams; Rgb24
    /// (libswscale) for color streams.
    std::vector<Image> frames;
};

/// The whole file.
struct FileReadback {
    bool ok = false;
    std::string error;
    std::string format;                      ///< Demuxer name, e.g. "matroska,webm".
    std::map<std::string, std::string> tags; ///< Container tags, keys lower-cased.
    std::vector<StreamReadback> streams;
    int decodeErrors = 0; ///< Packets or frames the decoders refused/flagged.
};

/// Reads \a path; \a colorStreams lists stream indices converted to Rgb24 (others: luma plane).
/// \param[in] keepFrames false: only PTS and metadata (faster).
FileReadback readBack(const std::string &path, std::vector<int> colorStreams = {0},
                      bool keepFrames = true);

/// What expectStream() checks of one stream; an empty codec, pixFmt or profile is not checked.
struct StreamFacts {
    std::string codec = {};
    std::string pixFmt = {};
    std::string profile = {};
    std::vector<std::pair<std::string, std::string>> tags = {}; ///< Key (lower-case) and value.
};

/// Expects (GoogleTest EXPECT_EQ) \a stream's codec facts and tags to be \a want's; a tag of \a
/// want that \a stream lacks throws std::out_of_range (std::map::at).
void expectStream(const StreamReadback &stream, const StreamFacts &want);

/// PSNR (dB) between two same-size Rgb24 or Gray8 images; 99 for identical ones.
double psnr(const Image &a, const Image &b);

} // namespace depthtouch::media::test
