/// \file
/// \brief The sender's video encoders (see encoder.h); the muxer is in muxer.cpp.

#include "depthtouch/media/encoder.h"

#include <algorithm>
#include <cmath>
#include <string>

extern "C" {
#include <libavutil/eval.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
}

#include "muxer_impl.h"

namespace depthtouch::media {

using namespace detail;

namespace {

/// Every PTS travels in this time base (90 kHz, as MPEG): exact for 24, 25, 30, 60 and 30000/1001
/// fps.
constexpr AVRational kTimeBase{1, 90000};

/// The libavcodec encoder of a VideoCodec: its name, its pixel format and the frames it takes.
struct CodecChoice {
    AVPixelFormat pixFmt = AV_PIX_FMT_YUV420P;
    const char *name = "libx264";
    PixelFormat input = PixelFormat::Rgb24;
};

/// \return the encoder for \a config.codec in \a container, or InvalidArgument (odd 4:2:0 size),
/// NotSupported (FFV1 outside MKV).
Result<CodecChoice> codecFor(const VideoEncoderConfig &config, Container container)
{
    CodecChoice out;
    switch (config.codec) {
    case VideoCodec::H264Yuv420p:
        if (config.width % 2 != 0 || config.height % 2 != 0)
            return unexpected(Errc::InvalidArgument, "4:2:0 color needs an even width and height");
        out.input = PixelFormat::Rgb24;
        break;
    case VideoCodec::H264Gray:
        out.pixFmt = AV_PIX_FMT_GRAY8;
        out.input = PixelFormat::Gray8;
        break;
    case VideoCodec::H264Gray10:
        out.pixFmt = AV_PIX_FMT_GRAY10;
        out.input = PixelFormat::Gray16;
        break;
    case VideoCodec::HevcMain10:
        if (config.width % 2 != 0 || config.height % 2 != 0)
            return unexpected(Errc::InvalidArgument,
                              "HEVC 4:2:0 depth needs an even width and height");
        out.pixFmt = AV_PIX_FMT_YUV420P10;
        out.name = "libx265";
        out.input = PixelFormat::Gray16;
        break;
    case VideoCodec::Ffv1Gray16:
        out.pixFmt = AV_PIX_FMT_GRAY16;
        out.name = "ffv1";
        out.input = PixelFormat::Gray16;
        if (container != Container::Matroska)
            return unexpected(Errc::NotSupported, "FFV1 depth needs an MKV output");
        break;
    case VideoCodec::H264Rgb:
        out.pixFmt = AV_PIX_FMT_RGB24;
        out.name = "libx264rgb";
        out.input = PixelFormat::Rgb24;
        break;
    }
    return out;
}

/// x265's own parameters (`-x265-params`): its log to errors only (it prints to stderr by itself),
/// closed GOPs (every key frame an IDR picture, as x264's: a receiver that tunes in or seeks there
/// loses no leading pictures), no scene-cut key frames with a GOP, lossless when asked.
std::string x265Params(const VideoEncoderConfig &config)
{
    std::string p = "log-level=error:open-gop=0";
    if (config.gop > 0)
        p += ":scenecut=0";
    if (config.lossless)
        p += ":lossless=1";
    return p;
}

/// The encoder's private options (x264 and x265: preset, CRF or lossless; FFV1: level 3, slice
/// CRCs, intra only), and the GOP into \a c. The caller frees the dictionary.
AVDictionary *encoderOptions(const VideoEncoderConfig &config, AVCodecContext &c)
{
    AVDictionary *opts = nullptr;
    if (config.codec == VideoCodec::Ffv1Gray16) {
        av_dict_set(&opts, "level", "3", 0);
        av_dict_set(&opts, "slicecrc", "1", 0);
        c.gop_size = 1;
    } else {
        const bool x265 = config.codec == VideoCodec::HevcMain10;
        av_dict_set(&opts, "preset", config.preset.c_str(), 0);
        if (config.gop > 0) {
            c.gop_size = config.gop;
            // Key frames on the gop grid only, so every stream of the output has its key frames
            // on the same pictures (each a tune-in point for all of them).
            if (!x265)
                av_dict_set(&opts, "x264-params", "scenecut=0", 0);
        }
        if (x265)
            av_dict_set(&opts, "x265-params", x265Params(config).c_str(), 0);
        if (x265 && config.lossless)
            return opts;
        if (config.lossless || config.codec == VideoCodec::H264Rgb) {
            av_dict_set(&opts, "qp", "0", 0);
            return opts;
        }
        // libx264 and libx265 take ABR when bit_rate is set and no crf is; the VBV caps either.
        if (config.rate.bitRate > 0)
            c.bit_rate = config.rate.bitRate;
        else
            av_dict_set(&opts, "crf", std::to_string(config.crf).c_str(), 0);
        c.rc_max_rate = config.rate.maxRate;
        c.rc_buffer_size = static_cast<int>(config.rate.bufSize);
    }
    return opts;
}

/// Depth (Gray16 holding 0..1023) into the luma of a yuv420p10 \a frame, both chroma planes
/// neutral (512), as MPEG Immersive Video carries geometry (ISO/IEC 23090-12): a 4:2:0 Main10
/// picture that every HEVC hardware decoder takes.
void copyIntoLuma(const Image &image, AVFrame &frame)
{
    av_image_copy_plane(frame.data[0], frame.linesize[0], image.data.data(),
                        static_cast<int>(image.stride), image.width * 2, image.height);
    constexpr std::uint16_t kNeutral = 512;
    for (int p = 1; p < 3; ++p) {
        for (int y = 0; y < (image.height + 1) / 2; ++y) {
            auto *row = reinterpret_cast<std::uint16_t *>(frame.data[p] + y * frame.linesize[p]);
            std::fill(row, row + (image.width + 1) / 2, kNeutral);
        }
    }
}

} // namespace

std::optional<long long> parseBitRate(const std::string &text)
{
    constexpr double kMin = 1000.0;        // x264 counts kbit/s
    constexpr double kMax = 1099511627776; // 2^40: beyond any link, and within x264's int kbit/s
    if (text.empty() || text.front() == ' ' || text.front() == '\t')
        return std::nullopt;
    char *tail = nullptr;
    const double v = av_strtod(text.c_str(), &tail);
    if (tail == nullptr || *tail != '\0' || !(v >= kMin) || v > kMax || v != std::floor(v))
        return std::nullopt;
    return static_cast<long long>(v);
}

bool isEncodableSize(int width, int height) noexcept
{
    constexpr long long kMaxMacroblocks = 139264; // level 6.2 MaxFS
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        return false;
    const long long mbs = ((width + 15LL) / 16) * ((height + 15LL) / 16);
    return mbs <= kMaxMacroblocks &&
           av_image_check_size(static_cast<unsigned>(width), static_cast<unsigned>(height), 0,
                               nullptr) == 0;
}

// ---------------------------------------------------------------------------------------------
// VideoEncoder

struct VideoEncoder::Impl {
    VideoEncoderConfig config;
    Muxer::Impl *muxer = nullptr;
    CodecContextPtr codec;
    FramePtr frame;
    PacketPtr packet;
    Scaler scaler;
    AVStream *stream = nullptr;
    PixelFormat input = PixelFormat::Rgb24;
    std::int64_t lastPts = AV_NOPTS_VALUE;
    long long frames = 0;
    long long bytes = 0;

    Result<void> drain()
    {
        for (;;) {
            const int ret = avcodec_receive_packet(codec.get(), packet.get());
            if (ret == AVERROR(EAGAIN) || ret == AVERROR_EOF)
                return ok();
            if (ret < 0) {
                DT_LOG(Media, Warning, "Failed to encode %s: %s", config.title.c_str(),
                       AvErrorText(ret).text);
                return unexpected(Errc::InvalidArgument, "The encoder failed");
            }
            bytes += packet->size;
            packet->stream_index = stream->index;
            av_packet_rescale_ts(packet.get(), codec->time_base, stream->time_base);
            auto w = muxer->write(packet.get());
            av_packet_unref(packet.get());
            DT_TRY(w);
        }
    }
};

VideoEncoder::VideoEncoder() : impl_(std::make_unique<Impl>()) {}
VideoEncoder::~VideoEncoder() = default;

VideoEncoderConfig colorStreamConfig(int width, int height, double fps, int crf,
                                     const std::string &preset, int threads)
{
    VideoEncoderConfig cc;
    cc.codec = VideoCodec::H264Yuv420p;
    cc.width = width;
    cc.height = height;
    cc.fps = fps;
    cc.crf = crf;
    cc.preset = preset;
    cc.threads = threads;
    cc.title = "color";
    return cc;
}

Result<std::unique_ptr<VideoEncoder>> VideoEncoder::create(const VideoEncoderConfig &config,
                                                           Muxer &muxer)
{
    Muxer::Impl &m = *muxer.impl_;
    if (m.started || m.fmt == nullptr)
        return unexpected(Errc::InvalidState, "Streams must be added before the muxer starts");
    if (!isEncodableSize(config.width, config.height))
        return unexpected(Errc::InvalidArgument,
                          "Frame size beyond H.264's largest (139264 macroblocks, e.g. 8192x4352)");
    if (!(config.fps >= kMinEncodeFps) || config.fps > kMaxEncodeFps)
        return unexpected(Errc::InvalidArgument, "Frame rate must be in 0.1..1000 frames/s");
    if (config.crf < 0 || config.crf > 51)
        return unexpected(Errc::InvalidArgument, "CRF must be in 0..51");

    std::unique_ptr<VideoEncoder> enc(new VideoEncoder());
    Impl &e = *enc->impl_;
    e.config = config;
    e.muxer = &m;

    auto choice = codecFor(config, m.container);
    if (!choice)
        return unexpected(choice.error());
    const AVPixelFormat pixFmt = choice->pixFmt;
    const char *codecName = choice->name;
    e.input = choice->input;
    const AVCodec *codec = avcodec_find_encoder_by_name(codecName);
    if (codec == nullptr)
        return unexpected(Errc::NotSupported,
                          "FFmpeg lacks the encoder (libx264, libx264rgb, libx265 or ffv1)");
    e.codec.reset(avcodec_alloc_context3(codec));
    e.frame.reset(av_frame_alloc());
    e.packet.reset(av_packet_alloc());
    if (!e.codec || !e.frame || !e.packet)
        return unexpected(Errc::OutOfResources, "Failed to allocate the encoder");
    AVCodecContext &c = *e.codec;
    c.width = config.width;
    c.height = config.height;
    c.pix_fmt = pixFmt;
    c.time_base = kTimeBase;
    c.framerate = av_d2q(config.fps, 100000);
    c.sample_aspect_ratio = AVRational{1, 1};
    c.thread_count = config.threads;
    if (config.codec == VideoCodec::H264Yuv420p) {
        // libswscale's RGB → YUV matrix is BT.601, limited range.
        c.color_range = AVCOL_RANGE_MPEG;
        c.colorspace = AVCOL_SPC_SMPTE170M;
    } else if (config.codec == VideoCodec::H264Rgb) {
        // Codes, not light: RGB as it is (no matrix), every level used.
        c.color_range = AVCOL_RANGE_JPEG;
        c.colorspace = AVCOL_SPC_RGB;
    } else {
        // Nearness levels use the whole sample range: 0 = far plane, 2^bits − 1 = near plane.
        c.color_range = AVCOL_RANGE_JPEG;
    }
    if ((m.fmt->oformat->flags & AVFMT_GLOBALHEADER) != 0)
        c.flags |= AV_CODEC_FLAG_GLOBAL_HEADER;

    AVDictionary *opts = encoderOptions(config, c);
    const int ret = avcodec_open2(e.codec.get(), codec, &opts);
    av_dict_free(&opts);
    if (ret < 0) {
        DT_LOG(Media, Warning, "Failed to open encoder %s for %s: %s", codecName,
               config.title.c_str(), AvErrorText(ret).text);
        return unexpected(Errc::InvalidArgument,
                          "Failed to open the encoder (bad preset or options)");
    }

    e.stream = avformat_new_stream(m.fmt, nullptr);
    if (e.stream == nullptr)
        return unexpected(Errc::OutOfResources, "Failed to add a stream");
    e.stream->time_base = kTimeBase;
    e.stream->avg_frame_rate = c.framerate;
    e.stream->r_frame_rate = c.framerate;
    if (avcodec_parameters_from_context(e.stream->codecpar, e.codec.get()) < 0)
        return unexpected(Errc::OutOfResources, "Failed to describe the stream");
    if (!config.title.empty()) {
        av_dict_set(&e.stream->metadata, "title", config.title.c_str(), 0);
        // MP4 has no track title: it names a track by its handler.
        if (m.container == Container::Mp4)
            av_dict_set(&e.stream->metadata, "handler_name", config.title.c_str(), 0);
    }
    for (const auto &[key, value] : config.tags)
        av_dict_set(&e.stream->metadata, key.c_str(), value.c_str(), 0);

    e.frame->format = pixFmt;
    e.frame->width = c.width;
    e.frame->height = c.height;
    e.frame->color_range = c.color_range;
    e.frame->colorspace = c.colorspace;
    if (av_frame_get_buffer(e.frame.get(), 0) < 0)
        return unexpected(Errc::OutOfResources, "Failed to allocate an encoder frame");
    return enc;
}

Result<void> VideoEncoder::encode(const Image &image, double ptsSeconds)
{
    Impl &e = *impl_;
    if (!e.muxer->started)
        return unexpected(Errc::InvalidState, "Encoding before the muxer started");
    if (image.width != e.config.width || image.height != e.config.height ||
        image.format != e.input || image.empty())
        return unexpected(Errc::InvalidArgument, "Picture of the wrong size or layout");
    const std::int64_t pts = std::llround(ptsSeconds * kTimeBase.den);
    if (e.lastPts != AV_NOPTS_VALUE && pts <= e.lastPts)
        return unexpected(Errc::InvalidArgument, "PTS not after the previous frame's");
    // The encoder may still hold a reference to the previous picture's buffer.
    if (av_frame_make_writable(e.frame.get()) < 0)
        return unexpected(Errc::OutOfResources, "Failed to allocate an encoder frame");

    if (e.config.codec == VideoCodec::H264Yuv420p) {
        AVFrame src{};
        src.format = AV_PIX_FMT_RGB24;
        src.width = image.width;
        src.height = image.height;
        src.data[0] = const_cast<std::uint8_t *>(image.data.data());
        src.linesize[0] = static_cast<int>(image.stride);
        DT_TRY(e.scaler.convert(src, e.frame->data, e.frame->linesize, AV_PIX_FMT_YUV420P,
                                image.width, image.height));
    } else if (e.config.codec == VideoCodec::HevcMain10) {
        copyIntoLuma(image, *e.frame);
    } else {
        // Gray and RGB24 layouts match the codec's sample layout bit for bit (gray10/gray16
        // native order; libx264rgb takes packed RGB24).
        av_image_copy_plane(e.frame->data[0], e.frame->linesize[0], image.data.data(),
                            static_cast<int>(image.stride),
                            image.width * bytesPerPixel(image.format), image.height);
    }
    e.frame->pts = pts;
    e.lastPts = pts;
    const int ret = avcodec_send_frame(e.codec.get(), e.frame.get());
    if (ret < 0) {
        DT_LOG(Media, Warning, "Failed to encode %s: %s", e.config.title.c_str(),
               AvErrorText(ret).text);
        return unexpected(Errc::InvalidArgument, "The encoder refused a frame");
    }
    ++e.frames;
    return e.drain();
}

Result<void> VideoEncoder::flush()
{
    Impl &e = *impl_;
    e.muxer->beginDrain();
    const int ret = avcodec_send_frame(e.codec.get(), nullptr);
    if (ret < 0 && ret != AVERROR_EOF)
        return unexpected(Errc::InvalidArgument, "Failed to flush the encoder");
    return e.drain();
}

long long VideoEncoder::frames() const noexcept
{
    return impl_->frames;
}

long long VideoEncoder::bytes() const noexcept
{
    return impl_->bytes;
}

} // namespace depthtouch::media
