#pragma once
/// \file
/// \brief The FFmpeg media source's state (FfmpegMediaSource::Impl), shared by its two files:
/// ffmpeg_media_source.cpp (opening an input, reading and seeking) and ffmpeg_source_streams.cpp
/// (describing its streams: roles, formats, rates, the depth tags, sound). Private to the driver.
/// Thread-safety: as FfmpegMediaSource (the player's source thread; interrupt() from any thread).

#include "depthtouch/drivers/ffmpeg/ffmpeg_media_source.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <memory>
#include <string_view>
#include <tuple>

#include "depthtouch/drivers/common/backend_options.h"
#include "depthtouch/hal/depth_tags.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/log.h"
#include "device_input.h"
#include "ffmpeg_common.h"
#include "h264_sps.h"
#include "hls_ladder_open.h"
#include "hls_variants.h"
#include "rendition_switch.h"
#include "still_image.h"
#include "stream_tags.h"
#include "timed_metadata_reader.h"

extern "C" {
#include <libavutil/dict.h>
#include <libavutil/mathematics.h>
#include <libavutil/parseutils.h>
#include <libavutil/pixdesc.h>
}

namespace depthtouch::drivers {

using namespace ffmpeg;

inline constexpr AVRational kNanoseconds{1, 1'000'000'000};
inline constexpr AVRational kMicroseconds{1, AV_TIME_BASE}; // AV_TIME_BASE_Q: a compound literal

struct FfmpegMediaSource::Impl {
    struct Stream {
        int avIndex = -1;
        hal::Pts frameDuration{0};
        hal::Pts lastPts = hal::kNoPts;
        av::CodecContextPtr imageDecoder; ///< Set for still-image codecs delivered as RawVideo.
    };

    Impl(platform::Clock &c, FfmpegSourceSettings s) : clock(c), settings(std::move(s)) {}

    /// libavformat's interrupt callback: called often while a call blocks (a network read polls
    /// every 100 ms at most), it ends the call on a stop request or at the I/O deadline.
    static int interrupt(void *opaque) noexcept
    {
        const auto *self = static_cast<const Impl *>(opaque);
        if (self->interrupted.load(std::memory_order_relaxed) || self->readCancelled())
            return 1;
        return self->clock.now() > self->ioDeadline ? 1 : 0;
    }
    /// \return whether a cancelRead() came that no read or seek consumed yet.
    [[nodiscard]] bool readCancelled() const noexcept
    {
        return cancelRequests.load(std::memory_order_acquire) !=
               cancelsConsumed.load(std::memory_order_relaxed);
    }
    void consumeCancels() noexcept
    {
        cancelsConsumed.store(cancelRequests.load(std::memory_order_acquire),
                              std::memory_order_relaxed);
    }
    /// \return the error of a libav call that failed with \a r: Timeout after interrupt(), else
    /// \a fallback.
    [[nodiscard]] Error failure(int r, Errc fallback, const char *what) const noexcept
    {
        if (interrupted.load(std::memory_order_relaxed))
            return Error(Errc::Timeout, "Interrupted by a stop request");
        return Error(fallback, what, AVUNERROR(r));
    }
    void armDeadline() noexcept
    {
        ioDeadline = clock.now() + std::chrono::milliseconds(settings.timeoutMs);
    }

    Result<void> open(const char *url);
    /// Opens \a url with libavformat (the forced format, the frame rate option, the I/O deadline)
    /// and reads its stream list into fmt.
    Result<void> openInput(const char *url);
    /// Lists libav stream \a i when it is a video stream this build delivers (\a videoStreams:
    /// the input's video streams, for telling depth from color; \a videoOrdinal: the video
    /// streams before it; \a serviceTags: DepthTouch's MPEG-TS tags, or nullptr).
    void addStream(unsigned i, int videoStreams, int videoOrdinal, const AVDictionary *serviceTags);
    /// Sets info.duration from the container, or from the longest listed stream.
    void readDuration() noexcept;
    /// Lists the audio stream \a st in info.audio.
    void addAudioStream(const AVStream &st);
    /// \return what libavformat opens for \a url: itself, or for a FIFO or a device (but one the
    /// forced format opens itself) `pipe:FD`, opened here non-blocking so that its reads honour
    /// the interrupt callback (device_input.h; a FIFO once a writer came within the timeout).
    Result<std::string> urlToOpen(const char *url, const AVInputFormat *forced)
    {
        const platform::PathKind kind = platform::pathKind(url);
        if (!isDeviceInput(kind, forced != nullptr && (forced->flags & AVFMT_NOFILE) != 0))
            return std::string(url);
        armDeadline();
        auto fd = openDeviceInput(url, kind, clock, ioDeadline, interrupted);
        if (!fd)
            return unexpected(fd.error());
        fifo = std::move(*fd);
        return "pipe:" + std::to_string(fifo.get());
    }
    Result<hal::Packet> read();
    /// \return \a p, a packet of the audio stream delivered, as a hal::Packet (Packet::audio).
    /// \a id: the audio stream's container index as listed at open.
    hal::Packet audioPacket(const AVPacket &p, int id) const noexcept
    {
        const AVRational tb = fmt->streams[p.stream_index]->time_base;
        hal::Packet out;
        out.audio = true;
        out.streamIndex = id;
        out.pts = toPts(p.pts, tb);
        out.dts = toPts(p.dts, tb);
        out.keyframe = (p.flags & AV_PKT_FLAG_KEY) != 0;
        out.data = p.data;
        out.size = static_cast<std::size_t>(p.size);
        return out;
    }
    hal::Pts toPts(std::int64_t ts, AVRational tb) const noexcept
    {
        if (ts == AV_NOPTS_VALUE)
            return hal::kNoPts;
        return hal::Pts(av_rescale_q(ts, tb, kNanoseconds)) - start;
    }
    /// \return the libav index, among the streams listed at open, that packet \a p's stream
    /// stands for (itself but after a rendition switch), or -1 to skip \a p; performs a
    /// switch the packet calls for (rendition_switch.h).
    Result<int> judge(const AVPacket &p, platform::Duration waited)
    {
        if (!renditions.active())
            return p.stream_index;
        const auto seconds = [](platform::Duration d) {
            return std::chrono::duration<double>(d).count();
        };
        switch (
            renditions.judge(*fmt, p, seconds(waited), seconds(clock.now().time_since_epoch()))) {
        case RenditionSwitch::Verdict::Deliver:
            return renditions.identity(p.stream_index);
        case RenditionSwitch::Verdict::Drop:
            break;
        }
        return -1;
    }
    void reset() noexcept
    {
        packet.reset();
        frame.reset();
        fmt.reset();
        ladderText.reset(); // after the demuxer that read it
        fifo.reset();
        streams.clear();
        avToHal.clear();
        pending.clear();
        audioIndex = -1;
        keptVariant = -1;
        renditions = RenditionSwitch{};
        info = {};
        start = hal::Pts{0};
        interrupted.store(false, std::memory_order_relaxed);
        consumeCancels();
    }

    platform::Clock &clock;
    const FfmpegSourceSettings settings;
    platform::TimePoint ioDeadline{};
    std::atomic<bool> interrupted{false};          ///< interrupt() was called (until close()).
    std::atomic<std::uint32_t> cancelRequests{0};  ///< cancelRead() calls.
    std::atomic<std::uint32_t> cancelsConsumed{0}; ///< Of them, those a read or a seek took.
    platform::UniqueFd fifo; ///< A FIFO or device input, opened here (read as pipe:FD).
    /// A ladder opened on the renditions that answered: its playlist, read by fmt (declared
    /// before it, destroyed after it).
    std::unique_ptr<PlaylistText> ladderText;
    av::InputContextPtr fmt;
    av::PacketPtr packet;
    PendingPackets pending; ///< Read ahead of the timed metadata at open: delivered first.
    /// Where the MPEG-TS tags came from (StreamInfo::titleFrom): the service name of files
    /// written before the timed metadata stream, or that stream.
    const char *serviceTagsFrom = "MPEG-TS service";
    av::FramePtr frame;
    av::SwsPtr sws;
    std::vector<Stream> streams; ///< By HAL index.
    std::vector<int> avToHal;    ///< libav stream index → HAL index, -1 when not listed.
    std::vector<std::uint8_t> raw;
    hal::MediaInfo info;
    hal::Pts start{0};
    int keptVariant = -1; ///< keepOneVariant()'s program.
    RenditionSwitch renditions;
    bool live = false;   ///< A network URL or a FIFO (openInput()).
    int audioIndex = -1; ///< The audio stream deliverAudio() chose (libav index), -1: none.
};

} // namespace depthtouch::drivers
