#pragma once
/// \file
/// \brief Muxer's state, shared by muxer.cpp (the output) and encoder.cpp (VideoEncoder::create()
/// adds its stream to the muxer's format context and writes its packets through write()).
/// Thread-safety: as Muxer (one thread).

#include <cstdio>
#include <string>

#include "media_libav.h"
#include "hls_files.h"
#include "depthtouch/media/encoder.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Media)

namespace depthtouch::media {

struct Muxer::Impl {
    AVFormatContext *fmt = nullptr;
    Container container = Container::Matroska;
    bool live = false;
    long long muxRate = 0; ///< MuxerOptions::muxRate.
    std::string output;
    std::string finalPath; ///< Where tmpPath is renamed to (the output, or a link's target).
    std::string tmpPath;   ///< Empty for URLs and outputs written in place (devices, FIFOs).
    bool started = false;
    bool finished = false;
    bool hlsFile = false; ///< An HLS file output: its files are tracked by hls.
    HlsFiles hls;

    ~Impl() { close(true); }

    void close(bool removeTmp) noexcept
    {
        if (fmt != nullptr) {
            if (fmt->pb != nullptr)
                avio_closep(&fmt->pb);
            avformat_free_context(fmt);
            fmt = nullptr;
        }
        if (removeTmp && !tmpPath.empty() && !finished)
            (void)std::remove(tmpPath.c_str());
        if (removeTmp && hlsFile && !finished)
            hls.removeAll(); // nothing of an unfinished HLS output stays under its names
    }

    Result<void> write(AVPacket *pkt)
    {
        int ret = av_interleaved_write_frame(fmt, pkt);
        if (ret >= 0 && hls.error() < 0) // a segment or playlist the HLS muxer could not write
            ret = hls.error();
        if (ret < 0) {
            DT_LOG(Media, Warning, "Failed to write %s: %s", output.c_str(),
                   detail::AvErrorText(ret).text);
            return unexpected(Errc::Io, "Failed to write the output", detail::errnoOf(ret));
        }
        return ok();
    }
};

} // namespace depthtouch::media
