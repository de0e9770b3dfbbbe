#include "depthtouch/drivers/ffmpeg/ffmpeg_video_decoder.h"

#include <cstring>
#include <filesystem>
#include <iterator>
#include <string_view>
#include <system_error>
#include <vector>

#include "depthtouch/drivers/common/backend_options.h"
#include "depthtouch/drivers/common/frame_pool.h"
#include "depthtouch/drivers/ffmpeg/drm_prime.h"
#include "depthtouch/platform/log.h"
#include "ffmpeg_common.h"
#include "frame_scaler.h"
#include "hw_accel.h"

extern "C" {
#include <libavutil/hwcontext.h>
#include <libavutil/hwcontext_drm.h>
#include <libavutil/opt.h>
#include <libavutil/pixdesc.h>
}

DT_LOG_CATEGORY(Ffmpeg)

namespace depthtouch::drivers {

using namespace ffmpeg;

namespace {

constexpr const char *kOptionKeys[] = {"pool", "queue", "threads", "drm-prime", "hwaccel"};
constexpr AVRational kNanoseconds{1, 1'000'000'000};
constexpr int kMaxSize = 8192;

struct QueuedPacket {
    std::vector<std::uint8_t> data; ///< Payload + AV_INPUT_BUFFER_PADDING_SIZE zero bytes.
    std::size_t size = 0;
    hal::Pts pts = hal::kNoPts;
    hal::Pts dts = hal::kNoPts;
    bool keyframe = false;
};

std::int64_t toAvTs(hal::Pts t) noexcept
{
    return t == hal::kNoPts ? AV_NOPTS_VALUE : t.count();
}

/// AVCodecContext::get_format of the `drm-prime` option: DRM PRIME frames when the decoder offers
/// them, else libavcodec's own choice (a software format).
AVPixelFormat preferDrmPrime(AVCodecContext *ctx, const AVPixelFormat *formats)
{
    for (const AVPixelFormat *f = formats; *f != AV_PIX_FMT_NONE; ++f)
        if (*f == AV_PIX_FMT_DRM_PRIME)
            return *f;
    return avcodec_default_get_format(ctx, formats);
}

/// How \a codec exports DRM PRIME frames.
enum class DrmPrimeSupport : std::uint8_t { None, Internal, NeedsDrmDevice };

DrmPrimeSupport drmPrimeSupport(const AVCodec *codec) noexcept
{
    DrmPrimeSupport best = DrmPrimeSupport::None;
    for (int i = 0;; ++i) {
        const AVCodecHWConfig *hw = avcodec_get_hw_config(codec, i);
        if (hw == nullptr)
            break;
        if (hw->pix_fmt != AV_PIX_FMT_DRM_PRIME)
            continue;
        if ((hw->methods & AV_CODEC_HW_CONFIG_METHOD_INTERNAL) != 0)
            return DrmPrimeSupport::Internal;
        if ((hw->methods & AV_CODEC_HW_CONFIG_METHOD_HW_DEVICE_CTX) != 0 &&
            hw->device_type == AV_HWDEVICE_TYPE_DRM)
            best = DrmPrimeSupport::NeedsDrmDevice;
    }
    return best;
}

/// The frames a receiver holds when it keeps zero-copy frames (its colour frames: pairing window
/// 8 + 4 + 4 held downstream) plus margin: the pool of `drm-prime` unless `pool` is given.
constexpr int kDrmPrimePoolFrames = 24;
/// V4L2 capture buffers beyond the pool: the decoder's reference frames stay in the driver.
constexpr int kCaptureBufferMargin = 8;

} // namespace

Result<FfmpegDecoderSettings> FfmpegDecoderSettings::parse(hal::OptionList options)
{
    FfmpegDecoderSettings s;
    DT_TRY(rejectUnknownOptions(options, kOptionKeys, std::size(kOptionKeys), kLogCategoryFfmpeg,
                                "Unknown ffmpeg video decoder option"));
    auto drmPrime = options.getBool("drm-prime", s.drmPrime);
    if (!drmPrime)
        return unexpected(Errc::InvalidArgument,
                          "ffmpeg decoder option drm-prime must be a boolean");
    auto pool = options.getInt("pool", *drmPrime ? kDrmPrimePoolFrames : s.poolFrames);
    auto queue = options.getInt("queue", s.queuePackets);
    auto threads = options.getInt("threads", s.threads);
    if (!pool || *pool < 1 || *pool > 64)
        return unexpected(Errc::InvalidArgument, "ffmpeg decoder option pool must be 1..64");
    if (!queue || *queue < 1 || *queue > 256)
        return unexpected(Errc::InvalidArgument, "ffmpeg decoder option queue must be 1..256");
    if (!threads || *threads < 1 || *threads > 16)
        return unexpected(Errc::InvalidArgument, "ffmpeg decoder option threads must be 1..16");
    const std::string hwaccel(options.find("hwaccel").value_or(s.hwaccel));
    DT_TRY(parseHwAccel(hwaccel));
    s.poolFrames = *pool;
    s.queuePackets = *queue;
    s.threads = *threads;
    s.drmPrime = *drmPrime;
    s.hwaccel = hwaccel;
    return s;
}

struct FfmpegVideoDecoder::Impl {
    Impl(platform::Clock &c, const FfmpegDecoderSettings &s, const char *decoderName)
        : clock(c), settings(s), hwName(decoderName)
    {
    }

    void dropQueue() noexcept
    {
        head = 0;
        count = 0;
    }
    /// Packets given to libavcodec that produced no frame become dropped.
    void settleDropped() noexcept
    {
        if (sent > received)
            counters.framesDropped.fetch_add(sent - received, std::memory_order_relaxed);
        sent = 0;
        received = 0;
    }
    Result<hal::FrameRef> lendFrame() noexcept;
    /// Drops the AVFrame references of DRM PRIME frames whose FrameRef was returned (decode
    /// thread: FrameRef release itself only flips the pool slot, lock-free).
    void releaseReturned() noexcept
    {
        for (std::size_t i = 0; i < held.size(); ++i)
            if (held[i]->buf[0] != nullptr && !pool.isLent(static_cast<std::uint32_t>(i)))
                av_frame_unref(held[i].get());
    }

    platform::Clock &clock;
    const FfmpegDecoderSettings settings;
    const char *hwName; ///< libavcodec decoder by name (h264_v4l2m2m), nullptr for software.
    hal::VideoDecoderCapabilities caps;
    hal::StreamConfig config;
    av::CodecContextPtr ctx;
    av::PacketPtr packet;
    av::FramePtr frame;
    FrameScaler scaler;      ///< copyFrame(), and frames of another size scaled to the stream's.
    int scaledFromWidth = 0; ///< The decoded size last logged as scaled (0: none).
    int scaledFromHeight = 0;
    FramePool pool;

    std::vector<QueuedPacket> queue;
    std::size_t head = 0;
    std::size_t count = 0;
    bool eosSent = false;   ///< libavcodec was told to drain.
    bool ended = false;     ///< libavcodec returned EOF.
    std::uint64_t sent = 0; ///< Packets given to libavcodec since configure/flush.
    std::uint64_t received = 0;
    std::uint64_t sequence = 0;

    hal::DecoderCounters counters;

    HwAccel hw;             ///< The hwaccel device of this configure(), or software.
    av::FramePtr hwScratch; ///< A hardware frame copied to system memory.

    /// `drm-prime` and the decoder can export DRM PRIME: frames may be lent as dma-bufs.
    bool primeMode = false;
    bool loggedPrime = false; ///< The first DRM PRIME frame was logged (per configure()).
    bool loggedCpu = false;   ///< The first CPU frame in prime mode was logged (per configure()).
    /// Prime mode: per pool slot, the AVFrame whose dma-bufs the lent frame describes; kept until
    /// the FrameRef is returned. Declared after ctx: freed before it.
    std::vector<av::FramePtr> held;
};

Result<hal::FrameRef> FfmpegVideoDecoder::Impl::lendFrame() noexcept
{
    std::uint32_t slot = 0;
    hal::Frame *out = pool.acquire(slot);
    if (out == nullptr) {
        av_frame_unref(frame.get());
        return unexpected(Errc::Busy, "Every pool frame is lent");
    }
    const bool corrupt =
        frame->decode_error_flags != 0 || (frame->flags & AV_FRAME_FLAG_CORRUPT) != 0;
    const std::int64_t ts =
        frame->best_effort_timestamp != AV_NOPTS_VALUE ? frame->best_effort_timestamp : frame->pts;
    // A hwaccel device's frame, or any frame of a V4L2 M2M decoder.
    const bool hardware = hwName != nullptr || (hw.active() && frame->format == hw.pixFmt);
    Result<void> copied = ok();
    bool dmabuf = false;
    if (primeMode && frame->format == AV_PIX_FMT_DRM_PRIME) {
        // Zero-copy: describe the dma-bufs and keep the AVFrame (and so its fds) until returned.
        av_frame_unref(held[slot].get());
        const auto *desc = reinterpret_cast<const AVDRMFrameDescriptor *>(frame->data[0]);
        auto img = desc != nullptr
                       ? dmaBufFromDrmDescriptor(*desc, frame->width, frame->height)
                       : Result<hal::DmaBufImage>(unexpected(
                             Errc::InvalidArgument, "DRM PRIME frame without a descriptor"));
        if (img) {
            out->dmabuf = *img;
            out->image = hal::ImageView{};
            out->image.width = img->width;
            out->image.height = img->height;
            out->image.format = img->fourcc == hal::kDrmFormatNv12 ? hal::PixelFormat::Nv12
                                                                   : hal::PixelFormat::Yuv420p;
            av_frame_move_ref(held[slot].get(), frame.get());
            dmabuf = true;
            if (!loggedPrime) {
                loggedPrime = true;
                DT_LOG(Ffmpeg, Info, "%s lends DRM PRIME frames (%dx%d, %d planes): no copy",
                       hwName != nullptr ? hwName : "libavcodec", img->width, img->height,
                       img->planeCount);
            }
        } else {
            DT_LOG(Ffmpeg, Warning, "Failed to describe a DRM PRIME frame: %s", img.error().what);
            copied = unexpected(img.error());
        }
    } else {
        if (primeMode) {
            copied = pool.ensurePixels(slot);
            if (!loggedCpu) {
                loggedCpu = true;
                DT_LOG(Ffmpeg, Warning,
                       "drm-prime: the decoder gave %s frames, not DRM PRIME: copying them to CPU "
                       "frames",
                       av_get_pix_fmt_name(static_cast<AVPixelFormat>(frame->format)));
            }
        }
        const AVFrame *sys = inSystemMemory(*frame, hw, hwScratch.get());
        if (copied && sys == nullptr)
            copied = unexpected(Errc::Io, "Failed to copy a hardware frame to memory");
        if (copied && (sys->width != out->image.width || sys->height != out->image.height) &&
            (sys->width != scaledFromWidth || sys->height != scaledFromHeight)) {
            scaledFromWidth = sys->width;
            scaledFromHeight = sys->height;
            DT_LOG(Ffmpeg, Warning, "The %s stream's pictures changed to %dx%d: scaled to %dx%d",
                   hal::streamKindName(config.kind), sys->width, sys->height, out->image.width,
                   out->image.height);
        }
        if (copied) // depth and material codes nearest-neighbour: no surface between two codes
            copied = scaler.copy(*sys, out->image,
                                 config.kind == hal::StreamKind::Depth ||
                                     out->image.format == hal::PixelFormat::Rgb24);
        if (hwScratch)
            av_frame_unref(hwScratch.get());
        out->dmabuf = hal::DmaBufImage{};
    }
    av_frame_unref(frame.get());
    if (!copied) {
        pool.releaseFrame(slot);
        counters.framesDropped.fetch_add(1, std::memory_order_relaxed);
        return unexpected(Errc::Io, copied.error().what);
    }
    out->kind = config.kind;
    out->pts = ts == AV_NOPTS_VALUE ? hal::kNoPts : hal::Pts(ts);
    out->time = clock.now();
    out->sequence = ++sequence;
    out->corrupt = corrupt;
    counters.framesDecoded.fetch_add(1, std::memory_order_relaxed);
    if (dmabuf)
        counters.framesDmaBuf.fetch_add(1, std::memory_order_relaxed);
    if (hardware)
        counters.framesHardware.fetch_add(1, std::memory_order_relaxed);
    if (corrupt)
        counters.framesConcealed.fetch_add(1, std::memory_order_relaxed);
    return pool.lend(slot);
}

FfmpegVideoDecoder::FfmpegVideoDecoder(std::unique_ptr<Impl> impl) : impl_(std::move(impl))
{
    caps_ = impl_->caps;
}
FfmpegVideoDecoder::~FfmpegVideoDecoder() = default;

Result<std::unique_ptr<hal::VideoDecoder>> FfmpegVideoDecoder::create(const hal::BackendConfig &cfg)
{
    auto settings = FfmpegDecoderSettings::parse(cfg.options);
    if (!settings)
        return unexpected(settings.error());
    quietLibav();
    auto impl = std::make_unique<Impl>(cfg.clockRef(), *settings, nullptr);
    for (hal::CodecId c : {hal::CodecId::H264, hal::CodecId::Hevc, hal::CodecId::Ffv1,
                           hal::CodecId::RawVideo, hal::CodecId::Mjpeg})
        if (avcodec_find_decoder(avCodecOf(c)) != nullptr)
            impl->caps.codecs |= hal::codecBit(c);
    if (impl->caps.codecs == 0)
        return unexpected(Errc::NoDevice, "libavcodec has none of the video decoders");
    impl->caps.maxWidth = kMaxSize;
    impl->caps.maxHeight = kMaxSize;
    impl->caps.poolFrames = settings->poolFrames;
    impl->caps.queuePackets = settings->queuePackets;
    impl->caps.hardware = false;
    return std::unique_ptr<hal::VideoDecoder>(new FfmpegVideoDecoder(std::move(impl)));
}

Result<std::unique_ptr<hal::VideoDecoder>>
FfmpegVideoDecoder::createV4l2m2m(const hal::BackendConfig &cfg)
{
    auto settings = FfmpegDecoderSettings::parse(cfg.options);
    if (!settings)
        return unexpected(settings.error());
    quietLibav();
    constexpr const char *kName = "h264_v4l2m2m";
    if (avcodec_find_decoder_by_name(kName) == nullptr)
        return unexpected(Errc::NoDevice, "libavcodec has no h264_v4l2m2m decoder");
    bool device = false;
    std::error_code ec;
    for (const auto &e : std::filesystem::directory_iterator("/dev", ec))
        if (e.path().filename().string().rfind("video", 0) == 0)
            device = true;
    if (!device)
        return unexpected(Errc::NoDevice, "No V4L2 device (/dev/video*) for h264_v4l2m2m");
    auto impl = std::make_unique<Impl>(cfg.clockRef(), *settings, kName);
    impl->caps.codecs = hal::codecBit(hal::CodecId::H264);
    impl->caps.maxWidth = 4096;
    impl->caps.maxHeight = 4096;
    impl->caps.poolFrames = settings->poolFrames;
    impl->caps.queuePackets = settings->queuePackets;
    impl->caps.hardware = true;
    return std::unique_ptr<hal::VideoDecoder>(new FfmpegVideoDecoder(std::move(impl)));
}

Result<void> FfmpegVideoDecoder::configureDevice(const hal::StreamConfig &cfg)
{
    Impl &d = *impl_;
    if (avCodecOf(cfg.codec) == AV_CODEC_ID_NONE)
        return unexpected(Errc::NotSupported, "Codec not supported by the ffmpeg decoder");
    hal::PixelFormat format = cfg.format;
    if (format == hal::PixelFormat::Unknown)
        format = cfg.kind == hal::StreamKind::Depth ? hal::PixelFormat::Gray8
                                                    : hal::PixelFormat::Yuv420p;
    const AVPixelFormat avFormat = avFormatOf(format);
    if (avFormat == AV_PIX_FMT_NONE || hal::planeCount(format) == 0)
        return unexpected(Errc::NotSupported, "Output pixel format not supported");
    if (d.pool.lent() != 0)
        return unexpected(Errc::Busy, "configure() needs every frame back");

    const AVCodec *codec = d.hwName != nullptr ? avcodec_find_decoder_by_name(d.hwName)
                                               : avcodec_find_decoder(avCodecOf(cfg.codec));
    if (codec == nullptr)
        return unexpected(Errc::NotSupported, "libavcodec has no decoder for the codec");
    av::CodecContextPtr ctx(avcodec_alloc_context3(codec));
    av::PacketPtr packet(av_packet_alloc());
    av::FramePtr frame(av_frame_alloc());
    if (!ctx || !packet || !frame)
        return unexpected(Errc::OutOfResources, "Failed to allocate the decoder");
    ctx->width = cfg.width;
    ctx->height = cfg.height;
    ctx->pkt_timebase = kNanoseconds;
    if (cfg.frameRate.num > 0 && cfg.frameRate.den > 0)
        ctx->framerate = {cfg.frameRate.num, cfg.frameRate.den};
    if (cfg.codec == hal::CodecId::RawVideo)
        ctx->pix_fmt = avFormat; // tightly packed images in the stream's format
    if (!cfg.extradata.empty()) {
        const std::size_t n = cfg.extradata.size();
        ctx->extradata = static_cast<std::uint8_t *>(av_mallocz(n + AV_INPUT_BUFFER_PADDING_SIZE));
        if (ctx->extradata == nullptr)
            return unexpected(Errc::OutOfResources, "Failed to allocate the codec setup data");
        std::memcpy(ctx->extradata, cfg.extradata.data(), n);
        ctx->extradata_size = static_cast<int>(n);
    }
    ctx->thread_count = d.hwName != nullptr ? 1 : d.settings.threads;
    ctx->thread_type = FF_THREAD_SLICE;
    // The pictures libavcodec cannot vouch for stay withheld (the file comment: a depth picture
    // predicted from pictures the decoder never had is a made-up surface under the finger).
    ctx->flags &= ~AV_CODEC_FLAG_OUTPUT_CORRUPT;
    ctx->flags2 &= ~AV_CODEC_FLAG2_SHOW_ALL;
    bool prime = false;
    if (d.settings.drmPrime && cfg.kind == hal::StreamKind::Color) {
        const DrmPrimeSupport support = drmPrimeSupport(codec);
        if (support == DrmPrimeSupport::NeedsDrmDevice) {
            AVBufferRef *device = nullptr;
            if (av_hwdevice_ctx_create(&device, AV_HWDEVICE_TYPE_DRM, nullptr, nullptr, 0) >= 0)
                ctx->hw_device_ctx = device; // owned by ctx from now on
            else
                DT_LOG(Ffmpeg, Warning, "drm-prime: failed to open a DRM device for %s",
                       codec->name);
        }
        prime = support == DrmPrimeSupport::Internal || ctx->hw_device_ctx != nullptr;
        if (prime) {
            ctx->get_format = preferDrmPrime;
            // Lent frames hold V4L2 capture buffers: the driver needs its own beyond them.
            if (d.hwName != nullptr)
                av_opt_set_int(ctx->priv_data, "num_capture_buffers",
                               d.settings.poolFrames + kCaptureBufferMargin, 0);
        } else {
            DT_LOG(Ffmpeg, Warning,
                   "drm-prime: the %s decoder of this libavcodec cannot export DRM PRIME frames: "
                   "decoding to CPU frames",
                   codec->name);
        }
    }
    HwAccel hw;
    av::FramePtr hwScratch;
    if (d.hwName == nullptr && !prime) {
        auto mode = parseHwAccel(d.settings.hwaccel);
        auto attached = mode ? attachHwAccel(*ctx, *codec, *mode) : unexpected(mode.error());
        if (!attached)
            return unexpected(attached.error());
        hw = *attached;
        if (hw.active()) {
            hwScratch.reset(av_frame_alloc());
            if (!hwScratch)
                return unexpected(Errc::OutOfResources, "Failed to allocate the decoder");
        }
    }
    const int r = avcodec_open2(ctx.get(), codec, nullptr);
    if (r < 0) {
        DT_LOG(Ffmpeg, Error, "Failed to open the %s decoder", codec->name);
        return unexpected(d.hwName != nullptr ? Errc::NoDevice : errcOf(r, Errc::NotSupported),
                          "Failed to open the decoder", AVUNERROR(r));
    }
    if (auto a = d.pool.allocate(d.settings.poolFrames, format, cfg.width, cfg.height,
                                 prime ? FramePool::Pixels::OnDemand : FramePool::Pixels::Now);
        !a)
        return unexpected(a.error());
    std::vector<av::FramePtr> held;
    if (prime) {
        for (int i = 0; i < d.settings.poolFrames; ++i) {
            held.emplace_back(av_frame_alloc());
            if (!held.back())
                return unexpected(Errc::OutOfResources, "Failed to allocate the decoder");
        }
    }
    std::vector<QueuedPacket> queue(static_cast<std::size_t>(d.settings.queuePackets));

    d.held.clear(); // no frame is lent (checked above)
    d.ctx = std::move(ctx);
    d.held = std::move(held);
    d.primeMode = prime;
    d.hw = hw;
    d.hwScratch = std::move(hwScratch);
    d.loggedPrime = d.loggedCpu = false;
    d.packet = std::move(packet);
    d.frame = std::move(frame);
    d.queue = std::move(queue);
    d.scaler = FrameScaler{};
    d.scaledFromWidth = d.scaledFromHeight = 0;
    d.config = cfg;
    d.config.format = format;
    d.dropQueue();
    d.eosSent = d.ended = false;
    d.sent = d.received = 0;
    return ok();
}

Result<void> FfmpegVideoDecoder::queuePacketDevice(const hal::Packet &pkt)
{
    Impl &d = *impl_;
    if (d.count == d.queue.size())
        return unexpected(Errc::Busy, "Decoder input queue is full");
    if (pkt.data == nullptr || pkt.size == 0) {
        d.counters.framesDropped.fetch_add(1, std::memory_order_relaxed);
        return unexpected(Errc::InvalidArgument, "Packet without data");
    }
    QueuedPacket &q = d.queue[(d.head + d.count) % d.queue.size()];
    q.size = pkt.size;
    q.pts = pkt.pts;
    q.dts = pkt.dts;
    q.keyframe = pkt.keyframe;
    q.data.resize(pkt.size + AV_INPUT_BUFFER_PADDING_SIZE);
    std::memcpy(q.data.data(), pkt.data, pkt.size);
    std::memset(q.data.data() + pkt.size, 0, AV_INPUT_BUFFER_PADDING_SIZE);
    d.counters.packetsQueued.fetch_add(1, std::memory_order_relaxed);
    ++d.count;
    return ok();
}

Result<hal::FrameRef> FfmpegVideoDecoder::dequeueFrameDevice(hal::Deadline until)
{
    Impl &d = *impl_;
    d.releaseReturned();
    if (d.ended)
        return unexpected(Errc::EndOfStream, "Decoder drained");
    if (!d.pool.hasFree())
        return unexpected(Errc::Busy, "Every pool frame is lent");
    // Each pass either returns or hands one queued packet to libavcodec: bounded by the queue.
    for (std::size_t pass = 0; pass <= d.queue.size() + 1; ++pass) {
        const int r = avcodec_receive_frame(d.ctx.get(), d.frame.get());
        if (r >= 0) {
            ++d.received;
            return d.lendFrame();
        }
        if (r == AVERROR_EOF) {
            d.ended = true;
            d.settleDropped();
            return unexpected(Errc::EndOfStream, "Decoder drained");
        }
        if (r != AVERROR(EAGAIN)) {
            d.counters.framesDropped.fetch_add(1, std::memory_order_relaxed);
            return unexpected(Errc::Io, "Failed to decode a frame", AVUNERROR(r));
        }
        int s = 0;
        if (d.count == 0) {
            if (!draining() || d.eosSent)
                break;
            d.eosSent = true;
            s = avcodec_send_packet(d.ctx.get(), nullptr);
        } else {
            QueuedPacket &q = d.queue[d.head];
            d.head = (d.head + 1) % d.queue.size();
            --d.count;
            AVPacket &p = *d.packet;
            av_packet_unref(&p);
            p.data = q.data.data();
            p.size = static_cast<int>(q.size);
            p.pts = toAvTs(q.pts);
            p.dts = toAvTs(q.dts);
            p.flags = q.keyframe ? AV_PKT_FLAG_KEY : 0;
            s = avcodec_send_packet(d.ctx.get(), &p);
            p.data = nullptr;
            p.size = 0;
            if (s >= 0)
                ++d.sent;
        }
        if (s < 0 && s != AVERROR_EOF) {
            d.counters.framesDropped.fetch_add(1, std::memory_order_relaxed);
            return unexpected(Errc::Io, "The decoder rejected a packet", AVUNERROR(s));
        }
    }
    d.clock.sleepUntil(until);
    return unexpected(Errc::Timeout, "No frame decoded by the deadline");
}

void FfmpegVideoDecoder::flushDevice() noexcept
{
    Impl &d = *impl_;
    d.counters.framesDropped.fetch_add(d.count, std::memory_order_relaxed);
    d.settleDropped();
    d.dropQueue();
    avcodec_flush_buffers(d.ctx.get());
    d.eosSent = d.ended = false;
}

void FfmpegVideoDecoder::closeDevice() noexcept
{
    Impl &d = *impl_;
    d.settleDropped();
    d.dropQueue();
    d.releaseReturned();
    d.ctx.reset();
    d.scaler = FrameScaler{};
    d.eosSent = d.ended = false;
}

hal::DecoderStats FfmpegVideoDecoder::stats() const noexcept
{
    return impl_->counters.snapshot();
}

int FfmpegVideoDecoder::framesLent() const noexcept
{
    return impl_->pool.lent();
}

} // namespace depthtouch::drivers
