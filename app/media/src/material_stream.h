#pragma once
/// \file
/// \brief findMaterialStream(): which video stream of an opened input is the material track
/// (depthtouch/scene/material.h; docs/materials.md), shared by probeMaterialStream() and the
/// frame source that reads `--material`.

#include <string>

extern "C" {
#include <libavformat/avformat.h>
}

namespace depthtouch::media::detail {

/// \brief The index of the material stream of \a fmt: the video stream titled `material`, or
/// with that MP4 handler name, or in MPEG-TS (no titles) the third video stream when it is
/// planar RGB (DepthTouch writes color, depth, material in that order). \a from says which of
/// the three found it ("title", "MP4 handler name", "MPEG-TS order").
/// \return the index, or -1 when the input has no material stream. Thread-safety: pure.
int findMaterialStream(const AVFormatContext &fmt, std::string &from);

/// \brief The number of video streams of \a fmt.
int videoStreamCount(const AVFormatContext &fmt) noexcept;

} // namespace depthtouch::media::detail
