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

DT_LOG_CATEGORY(Ffmpeg)

namespace depthtouch::drivers {

using namespace ffmpeg;

namespace {

constexpr AVRational kNanoseconds{1, 1'000'000'000};
constexpr AVRational kMicroseconds{1, AV_TIME_BASE}; // AV_TIME_BASE_Q is a C compound literal

} // namespace

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

void FfmpegMediaSource::Impl::addStream(unsigned i, int videoStreams, int videoOrdinal,
                                        const AVDictionary *serviceTags)
{
    AVFormatContext *ctx = fmt.get();
    const AVStream &st = *ctx->streams[i];
    const AVCodecParameters &par = *st.codecpar;
    if (st.discard == AVDISCARD_ALL) // another rendition (hls_variants.h)
        return;
    if (par.codec_type == AVMEDIA_TYPE_AUDIO)
        addAudioStream(st);
    if (par.codec_type != AVMEDIA_TYPE_VIDEO)
        return;
    if ((st.disposition & AV_DISPOSITION_ATTACHED_PIC) != 0)
        return;
    hal::StreamInfo si;
    si.index = static_cast<int>(info.streams.size());
    si.containerIndex = static_cast<int>(i);
    const AVDictionaryEntry *title = av_dict_get(st.metadata, "title", nullptr, 0);
    const AVDictionaryEntry *handler = av_dict_get(st.metadata, "handler_name", nullptr, 0);
    if (title != nullptr) {
        si.title = title->value;
        si.titleFrom = "title";
    } else if (handler != nullptr && isRoleName(handler->value)) {
        si.title = handler->value;
        si.titleFrom = "MP4 handler name";
    } else if (serviceTags != nullptr && videoOrdinal < 2) {
        si.title = videoOrdinal == 0 ? "color" : "depth";
        si.titleFrom = serviceTagsFrom;
    }
    const AVPixelFormat pixfmt =
        si.title == "color" ? static_cast<AVPixelFormat>(par.format) : samplesFormatOf(par);
    if (si.title == "depth")
        si.kind = hal::StreamKind::Depth;
    else if (si.title == "color")
        si.kind = hal::StreamKind::Color;
    else
        si.kind =
            videoStreams == 1 && isGray(pixfmt) ? hal::StreamKind::Depth : hal::StreamKind::Color;
    si.codec = codecOf(par.codec_id);
    si.format = halFormatOf(pixfmt, si.kind);
    si.width = par.width;
    si.height = par.height;
    // A live input's average over its few probed frames is rough (29.92 for 30 was seen); the
    // rate of its timestamp steps is exact for a constant rate.
    const bool real = st.r_frame_rate.num > 0 && st.r_frame_rate.den > 0;
    const bool average = st.avg_frame_rate.num > 0 && st.avg_frame_rate.den > 0;
    AVRational rate = average && !(live && real) ? st.avg_frame_rate : st.r_frame_rate;
    if (rate.num > 0 && rate.den > 0)
        si.frameRate = {rate.num, rate.den};
    si.timeBase = {st.time_base.num, st.time_base.den};
    if (par.extradata != nullptr && par.extradata_size > 0)
        si.extradata.assign(par.extradata,
                            par.extradata + static_cast<std::size_t>(par.extradata_size));
    for (const char *key : hal::kDepthTagNames)
        hal::applyDepthTag(key, tagOf(st, *ctx, serviceTags, key), si.depth);

    Stream s;
    s.avIndex = static_cast<int>(i);
    if (rate.num > 0 && rate.den > 0)
        s.frameDuration = hal::Pts(av_rescale_q(1, av_inv_q(rate), kNanoseconds));
    if (si.codec == hal::CodecId::Unknown) {
        // A still-image codec (image sequence): decode here, deliver RawVideo packets.
        if (si.format == hal::PixelFormat::Unknown || si.width <= 0 || si.height <= 0)
            return;
        s.imageDecoder = openStillImageDecoder(par);
        if (!s.imageDecoder)
            return;
        si.codec = hal::CodecId::RawVideo;
        si.extradata.clear();
    }
    avToHal[i] = si.index;
    info.streams.push_back(std::move(si));
    streams.push_back(std::move(s));
}

void FfmpegMediaSource::Impl::readDuration() noexcept
{
    const AVFormatContext *ctx = fmt.get();
    if (ctx->duration != AV_NOPTS_VALUE && ctx->duration > 0) {
        info.duration = hal::Pts(av_rescale_q(ctx->duration, kMicroseconds, kNanoseconds));
    } else {
        for (const Stream &s : streams) {
            const AVStream &st = *ctx->streams[s.avIndex];
            if (st.duration != AV_NOPTS_VALUE)
                info.duration = std::max(
                    info.duration, hal::Pts(av_rescale_q(st.duration, st.time_base, kNanoseconds)));
        }
    }
}

void FfmpegMediaSource::Impl::addAudioStream(const AVStream &st)
{
    const AVCodecParameters &par = *st.codecpar;
    hal::AudioStreamInfo a;
    a.containerIndex = st.index;
    a.codec = avcodec_get_name(par.codec_id);
    a.sampleRate = par.sample_rate;
    a.channels = par.ch_layout.nb_channels;
    if (st.start_time != AV_NOPTS_VALUE)
        a.start = hal::Pts(av_rescale_q(st.start_time, st.time_base, kNanoseconds)) - start;
    // MKV gives no stream duration but libavformat's muxer writes a DURATION tag.
    const AVDictionaryEntry *tag = av_dict_get(st.metadata, "DURATION", nullptr, 0);
    std::int64_t tagged = 0;
    if (st.duration != AV_NOPTS_VALUE && st.duration > 0)
        a.duration = hal::Pts(av_rescale_q(st.duration, st.time_base, kNanoseconds));
    else if (tag != nullptr && av_parse_time(&tagged, tag->value, 1) == 0 && tagged > 0)
        a.duration = hal::Pts(av_rescale_q(tagged, kMicroseconds, kNanoseconds));
    const AVDictionaryEntry *lang = av_dict_get(st.metadata, "language", nullptr, 0);
    if (lang != nullptr && std::string_view(lang->value) != "und") // ISO 639-2 "undetermined"
        a.language = lang->value;
    if (par.extradata != nullptr && par.extradata_size > 0)
        a.extradata.assign(par.extradata, par.extradata + par.extradata_size);
    info.audio.push_back(std::move(a));
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
