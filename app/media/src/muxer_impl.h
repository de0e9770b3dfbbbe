#pragma once
/// \file
/// \brief Muxer's state, shared by muxer.cpp (the output) and encoder.cpp (VideoEncoder::create()
/// adds its stream to the muxer's format context and writes its packets through write()).
/// Thread-safety: as Muxer (one thread).

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "media_libav.h"
#include "hls_files.h"
#include "timed_metadata.h"
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
    /// MPEG-TS and HLS: the tags their timed metadata stream carries (added by start()).
    std::vector<std::pair<std::string, std::string>> timedTags;
    std::optional<TimedMetadata> timed;
    /// With timed metadata: the streams that have not yet had a packet (see write()).
    std::vector<bool> unseenStreams;

    /// How far (µs) the interleaver may hold packets for the sparse timed metadata stream.
    static constexpr std::int64_t kTimedMetadataInterleaveMicroseconds = 100000;

    /// The interleaver holds every packet until each stream has one queued: the timed metadata
    /// stream, a packet a GOP, would hold a live output's pictures for a GOP (2 s of tune-in over
    /// SRT, and as much latency). Once every stream has had its first packet (so that the first
    /// timestamps, an AAC encoder's negative one included, are all known when the muxer makes them
    /// non-negative), it may hold them a tenth of a second at most: more than the picture and
    /// sound streams ever lie apart.
    void noteStream(int index)
    {
        if (unseenStreams.empty() || index < 0 ||
            static_cast<std::size_t>(index) >= unseenStreams.size())
            return;
        unseenStreams[static_cast<std::size_t>(index)] = false;
        for (const bool unseen : unseenStreams)
            if (unseen)
                return;
        fmt->max_interleave_delta = kTimedMetadataInterleaveMicroseconds;
        unseenStreams.clear();
    }

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
        int ret = 0;
        if (timed) {
            if (AVPacket *tag = timed->packetBefore(*fmt, *pkt)) {
                noteStream(tag->stream_index);
                ret = av_interleaved_write_frame(fmt, tag);
            }
            noteStream(pkt->stream_index);
        }
        if (ret >= 0)
            ret = av_interleaved_write_frame(fmt, pkt);
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
