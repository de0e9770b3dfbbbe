#pragma once
/// \file
/// \brief Muxer's state, shared by muxer.cpp (the output) and encoder.cpp (VideoEncoder::create()
/// adds its stream to the muxer's format context and writes its packets through write()).
/// Thread-safety: as Muxer (one thread).

#include <algorithm>
#include <cmath>
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
    /// The encoders are being flushed (beginDrain()): no time limit on the interleaver any more.
    bool draining = false;

    /// Before the encoders give out the frames they hold, stream after stream (x264's and x265's
    /// lookahead: a second or more): the interleaver keeps every packet until the trailer (0: no
    /// time limit) and writes them in DTS order, so that the first stream flushed is not written
    /// ahead of the others' ends.
    void beginDrain() noexcept
    {
        draining = true;
        if (fmt != nullptr)
            fmt->max_interleave_delta = 0;
    }

    /// With timed metadata: the streams that have not yet had a packet (see write()).
    std::vector<bool> unseenStreams;
    bool allSeen = false;
    double newestSeconds = -1e300; ///< The latest DTS given to the interleaver, any stream (s).
    double lagSeconds = 0.0;       ///< The most a packet's DTS trailed the newest one (s).

    /// How far (µs) the interleaver may hold packets for the sparse timed metadata stream, beyond
    /// twice the encoders' own lag.
    static constexpr std::int64_t kTimedMetadataInterleaveMicroseconds = 100000;

    /// The interleaver holds every packet until each stream has one queued: the timed metadata
    /// stream, a packet a GOP, would hold a live output's pictures for a GOP (2 s of tune-in over
    /// SRT, and as much latency). Once every stream has had its first packet (so that the first
    /// timestamps, an AAC encoder's negative one included, are all known when the muxer makes them
    /// non-negative), it may hold them a tenth of a second more than twice the most one stream's
    /// packets trailed another's: x264 streams come a frame or two apart, an x265 depth stream
    /// 0.3 s or more from x264's color (another lookahead and frame threads; growing after the
    /// first packets: hence twice, and raised whenever a packet trails by more), and every packet
    /// must still go out in DTS order.
    void noteStream(const AVPacket &pkt)
    {
        const int index = pkt.stream_index;
        if (draining || (unseenStreams.empty() && !allSeen) || index < 0 ||
            static_cast<unsigned>(index) >= fmt->nb_streams)
            return;
        const std::int64_t ts = pkt.dts != AV_NOPTS_VALUE ? pkt.dts : pkt.pts;
        if (ts != AV_NOPTS_VALUE) {
            const double t = static_cast<double>(ts) * av_q2d(fmt->streams[index]->time_base);
            lagSeconds = std::max(lagSeconds, newestSeconds - t);
            newestSeconds = std::max(newestSeconds, t);
        }
        const std::int64_t delta =
            kTimedMetadataInterleaveMicroseconds + std::llround(2.0 * lagSeconds * 1e6);
        if (allSeen) {
            fmt->max_interleave_delta = std::max(fmt->max_interleave_delta, delta);
            return;
        }
        unseenStreams[static_cast<std::size_t>(index)] = false;
        for (const bool unseen : unseenStreams)
            if (unseen)
                return;
        allSeen = true;
        unseenStreams.clear();
        fmt->max_interleave_delta = delta; // from the default 10 s down to what the streams need
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
                noteStream(*tag);
                ret = av_interleaved_write_frame(fmt, tag);
            }
            noteStream(*pkt);
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
