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
#include "ffmpeg_source_impl.h"
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

DT_LOG_CATEGORY(Ffmpeg)

namespace depthtouch::drivers {

using namespace ffmpeg;

namespace {
constexpr int kLiveFpsProbeFrames = 5; ///< See openInput().
/// How many packets open() reads ahead for a timed ID3 tag (about a GOP of a live stream joined
/// mid-GOP: the sender writes one before each color key frame).
constexpr int kTimedMetadataPackets = 600;
} // namespace

Result<void> FfmpegMediaSource::Impl::openInput(const char *url)
{
    AVFormatContext *ctx = avformat_alloc_context();
    if (ctx == nullptr)
        return unexpected(Errc::OutOfResources, "Failed to allocate the demuxer");
    ctx->interrupt_callback = {&Impl::interrupt, this};
    const AVInputFormat *forced = nullptr;
    if (!settings.format.empty()) {
        forced = av_find_input_format(settings.format.c_str());
        if (forced == nullptr) {
            avformat_free_context(ctx);
            return unexpected(Errc::NotSupported, "Unknown container format (option format)");
        }
    }
    auto openUrl = urlToOpen(url, forced);
    if (!openUrl) {
        avformat_free_context(ctx);
        return unexpected(openUrl.error());
    }
    AVDictionary *opts = nullptr;
    if (settings.fps > 0.0)
        av_dict_set(&opts, "framerate", std::to_string(settings.fps).c_str(), 0);
    // A live input (a network URL, a FIFO) takes its frame rate from the timestamps of 5 frames
    // (libavformat's fpsprobesize) instead of 20: the probe no longer holds the first picture
    // back by about 0.7 s at 30 fps, and 5 steps of a constant rate give it (docs/
    // playing.md "Tune-in"). A file is probed in full: it is read from disk in no time.
    const std::string_view target(*openUrl);
    live = (target.find("://") != std::string_view::npos && target.substr(0, 7) != "file://") ||
           target.substr(0, 5) == "pipe:";
    if (live)
        ctx->fps_probe_size = kLiveFpsProbeFrames;
    // Bounded probing (ffmpeg's probesize and analyzeduration): a live input's capped at 3 s of
    // media time (FfmpegSourceSettings::kLiveAnalyzeDurationUs) instead of libavformat's 5 s.
    if (settings.probeSize > 0)
        ctx->probesize = settings.probeSize;
    if (settings.analyzeDurationUs > 0 || live)
        ctx->max_analyze_duration = settings.analyzeDurationUs > 0
                                        ? settings.analyzeDurationUs
                                        : FfmpegSourceSettings::kLiveAnalyzeDurationUs;
    const auto limits = [fps = ctx->fps_probe_size, size = ctx->probesize,
                         duration = ctx->max_analyze_duration](AVFormatContext &c) {
        std::tie(c.fps_probe_size, c.probesize, c.max_analyze_duration) =
            std::tuple(fps, size, duration);
    };
    armDeadline();
    int r = avformat_open_input(&ctx, openUrl->c_str(), forced, &opts); // frees ctx on failure
    av_dict_free(&opts);
    if (r < 0 && forced == nullptr && !fifo && !interrupted.load(std::memory_order_relaxed)) {
        // One rendition of a ladder that does not answer fails the whole open: open the others.
        const LadderOpenHooks hooks{{&Impl::interrupt, this},
                                    [this] { armDeadline(); },
                                    [this] { return interrupted.load(); },
                                    limits};
        if (auto answering = openAnsweringRenditions(*openUrl, hooks, ladderText))
            std::tie(ctx, r) = std::tuple(*answering, 0);
    }
    if (r < 0) {
        char msg[AV_ERROR_MAX_STRING_SIZE] = {};
        av_strerror(r, msg, sizeof msg);
        DT_LOG(Ffmpeg, Debug, "Failed to open '%s': %s", url, msg);
        return unexpected(failure(r, errcOf(r, Errc::Io), "Failed to open the media input"));
    }
    fmt.reset(ctx);
    if (const int n = discardDataStreams(*ctx); n > 0) // a private-data PID stalls the probe
        DT_LOG(Ffmpeg, Debug, "'%s': %d data streams ignored", url, n);
    armDeadline();
    r = avformat_find_stream_info(ctx, nullptr);
    if (r < 0) {
        DT_LOG(Ffmpeg, Debug, "Failed to read the stream list of '%s'", url);
        return unexpected(
            failure(r, errcOf(r, Errc::InvalidArgument), "Failed to read the stream list"));
    }
    keptVariant = keepOneVariant(*ctx, RenditionChoice{settings.renditionHeight},
                                 info.renditions); // sizes known
    return ok();
}

Result<void> FfmpegMediaSource::Impl::open(const char *url)
{
    DT_TRY(openInput(url));
    AVFormatContext *ctx = fmt.get();
    const auto keptVideo = [ctx](unsigned i) {
        return ctx->streams[i]->codecpar->codec_type == AVMEDIA_TYPE_VIDEO &&
               ctx->streams[i]->discard != AVDISCARD_ALL;
    };
    int videoStreams = 0;
    for (unsigned i = 0; i < ctx->nb_streams; ++i)
        if (keptVideo(i))
            ++videoStreams;
    if (videoStreams == 0)
        return unexpected(Errc::InvalidArgument, "The input has no video stream");

    if (ctx->start_time != AV_NOPTS_VALUE)
        start = hal::Pts(av_rescale_q(ctx->start_time, kMicroseconds, kNanoseconds));
    avToHal.assign(ctx->nb_streams, -1);
    AVDictionary *tags = serviceTagsOf(*ctx);
    serviceTagsFrom = "MPEG-TS service";
    if (tags == nullptr) {
        tags = readTimedMetadata(*ctx, pending, kTimedMetadataPackets, [this] { armDeadline(); });
        serviceTagsFrom = "MPEG-TS timed metadata";
    }
    const std::unique_ptr<AVDictionary, void (*)(AVDictionary *)> service(
        tags, [](AVDictionary *d) { av_dict_free(&d); });
    int videoOrdinal = 0;
    for (unsigned i = 0; i < ctx->nb_streams; ++i) {
        addStream(i, videoStreams, videoOrdinal, service.get());
        if (keptVideo(i))
            ++videoOrdinal;
    }
    if (info.streams.empty())
        return unexpected(Errc::NotSupported, "No video stream with a codec this build decodes");

    readDuration();
    const bool noFile = (ctx->iformat->flags & AVFMT_NOFILE) != 0;
    // Image sequences (no file of their own) seek by file number.
    info.seekable =
        noFile || (ctx->pb != nullptr && (ctx->pb->seekable & AVIO_SEEKABLE_NORMAL) != 0);
    packet.reset(av_packet_alloc());
    frame.reset(av_frame_alloc());
    if (!packet || !frame)
        return unexpected(Errc::OutOfResources, "Failed to allocate a packet");
    if (settings.renditionAuto) {
        std::vector<int> video;
        for (const Stream &s : streams)
            video.push_back(s.avIndex);
        renditions.start(*ctx, keptVariant, video, info.renditions);
    }
    return ok();
}

Result<hal::Packet> FfmpegMediaSource::Impl::read()
{
    for (;;) {
        av_packet_unref(packet.get());
        if (interrupted.load(std::memory_order_relaxed))
            return unexpected(Errc::Timeout, "Interrupted by a stop request");
        int r = 0;
        platform::Duration waited{0};
        if (renditions.due()) { // rendition_switch.h
            armDeadline();
            DT_TRY(renditions.perform(*fmt));
        }
        if (!pending.empty()) { // read ahead at open (readTimedMetadata())
            av_packet_move_ref(packet.get(), pending.front().get());
            pending.pop_front();
        } else {
            armDeadline();
            const platform::TimePoint asked = clock.now();
            r = av_read_frame(fmt.get(), packet.get());
            waited = clock.now() - asked;
        }
        if (r < 0 && interrupted.load(std::memory_order_relaxed))
            return unexpected(Errc::Timeout, "Interrupted by a stop request");
        if (r < 0 && readCancelled()) {
            consumeCancels();
            // The interrupted read marked the I/O context ended: the input itself is fine.
            if (fmt->pb != nullptr) {
                fmt->pb->eof_reached = 0;
                fmt->pb->error = 0;
            }
            return unexpected(Errc::Timeout, "Read cancelled (a seek)");
        }
        if (r == AVERROR_EOF)
            return unexpected(Errc::EndOfStream, "End of the media input");
        if (r < 0) {
            if (fmt->pb != nullptr && avio_feof(fmt->pb) != 0)
                return unexpected(Errc::EndOfStream, "End of the media input");
            return unexpected(Errc::Io, "Failed to read a packet", AVUNERROR(r));
        }
        const AVPacket &p = *packet;
        auto judged = judge(p, waited); // the stream listed at open it stands for
        if (!judged)
            return unexpected(judged.error());
        const int id = *judged;
        if (id < 0)
            continue;
        if (id == audioIndex && p.size > 0 && p.data != nullptr)
            return audioPacket(p, id);
        if (static_cast<std::size_t>(id) >= avToHal.size())
            continue;
        const int halIndex = avToHal[static_cast<std::size_t>(id)];
        if (halIndex < 0 || p.size <= 0 || p.data == nullptr)
            continue;
        Stream &s = streams[static_cast<std::size_t>(halIndex)];
        hal::Packet out;
        out.streamIndex = halIndex;
        const AVRational tb = fmt->streams[p.stream_index]->time_base;
        out.dts = toPts(p.dts, tb);
        out.pts = toPts(p.pts, tb);
        if (out.pts == hal::kNoPts)
            out.pts = out.dts;
        if (out.pts == hal::kNoPts)
            out.pts = s.lastPts == hal::kNoPts ? hal::Pts{0} : s.lastPts + s.frameDuration;
        s.lastPts = out.pts;
        out.keyframe = (p.flags & AV_PKT_FLAG_KEY) != 0;
        if (!s.imageDecoder) {
            out.data = p.data;
            out.size = static_cast<std::size_t>(p.size);
            return out;
        }
        // Still image: decoded here into a tightly packed RawVideo image.
        const hal::StreamInfo &si = info.streams[static_cast<std::size_t>(halIndex)];
        DT_TRY(decodeStillImage(*s.imageDecoder, *packet, *frame, si, raw, sws));
        out.data = raw.data();
        out.size = raw.size();
        out.keyframe = true;
        return out;
    }
}

Result<std::unique_ptr<hal::MediaSource>> FfmpegMediaSource::create(const hal::BackendConfig &cfg)
{
    auto settings = FfmpegSourceSettings::parse(cfg.options);
    if (!settings)
        return unexpected(settings.error());
    quietLibav();
    return std::unique_ptr<hal::MediaSource>(
        std::make_unique<FfmpegMediaSource>(cfg.clockRef(), std::move(*settings)));
}

FfmpegMediaSource::FfmpegMediaSource(platform::Clock &clock, FfmpegSourceSettings settings)
    : impl_(std::make_unique<Impl>(clock, std::move(settings)))
{
}

FfmpegMediaSource::~FfmpegMediaSource() = default;

Result<void> FfmpegMediaSource::openDevice(const char *url)
{
    return impl_->open(url);
}

void FfmpegMediaSource::closeDevice() noexcept
{
    impl_->reset();
}

void FfmpegMediaSource::interrupt() noexcept
{
    impl_->interrupted.store(true, std::memory_order_relaxed);
}

void FfmpegMediaSource::cancelRead() noexcept
{
    impl_->cancelRequests.fetch_add(1, std::memory_order_acq_rel);
}

const hal::MediaInfo &FfmpegMediaSource::infoDevice() const noexcept
{
    return impl_->info;
}

Result<hal::Packet> FfmpegMediaSource::readPacketDevice()
{
    return impl_->read();
}

Result<void> FfmpegMediaSource::deliverAudio(int containerIndex)
{
    if (state() != State::Open)
        return unexpected(Errc::InvalidState, "The media source is not open");
    if (containerIndex < 0) {
        impl_->audioIndex = -1;
        return ok();
    }
    for (const hal::AudioStreamInfo &a : impl_->info.audio)
        if (a.containerIndex == containerIndex) {
            impl_->audioIndex = containerIndex;
            return ok();
        }
    return unexpected(Errc::InvalidArgument, "No such audio stream");
}

Result<void> FfmpegMediaSource::seekDevice(hal::Pts position)
{
    impl_->consumeCancels(); // what a cancelled read was cancelled for
    const std::int64_t us =
        std::chrono::duration_cast<std::chrono::microseconds>(position + impl_->start).count();
    impl_->armDeadline();
    const int r = av_seek_frame(impl_->fmt.get(), -1, us, AVSEEK_FLAG_BACKWARD);
    if (r < 0)
        return unexpected(impl_->failure(r, Errc::Io, "Failed to seek"));
    impl_->pending.clear();
    impl_->renditions.onSeek();
    for (auto &s : impl_->streams) {
        s.lastPts = hal::kNoPts;
        if (s.imageDecoder)
            avcodec_flush_buffers(s.imageDecoder.get());
    }
    return ok();
}

} // namespace depthtouch::drivers
