#include "test_media.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>

#include <gtest/gtest.h>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
}

namespace depthtouch::receivertest {

namespace {

struct Encoder {
    AVCodecContext *ctx = nullptr;
    AVStream *stream = nullptr;
    AVFrame *frame = nullptr;
    const ClipStream *spec = nullptr;
    bool depth = false;
    ~Encoder()
    {
        avcodec_free_context(&ctx);
        av_frame_free(&frame);
    }
};

std::string avError(const char *what, int err)
{
    char buf[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(err, buf, sizeof buf);
    return std::string(what) + ": " + buf;
}

std::string drainPackets(AVFormatContext *oc, Encoder &e, AVPacket *pkt)
{
    for (;;) {
        const int r = avcodec_receive_packet(e.ctx, pkt);
        if (r == AVERROR(EAGAIN) || r == AVERROR_EOF)
            return {};
        if (r < 0)
            return avError("encode", r);
        av_packet_rescale_ts(pkt, e.ctx->time_base, e.stream->time_base);
        pkt->stream_index = e.stream->index;
        const int w = av_interleaved_write_frame(oc, pkt);
        if (w < 0)
            return avError("write packet", w);
    }
}

/// Deterministic noise in 0..255 for texture.
int noise(int x, int y) noexcept
{
    auto h =
        static_cast<std::uint32_t>(x) * 0x9e3779b1u ^ static_cast<std::uint32_t>(y) * 0x85ebca77u;
    h ^= h >> 15;
    h *= 0x2c1b3c6du;
    h ^= h >> 12;
    return static_cast<int>(h & 0xffu);
}

void fill(Encoder &e, int index)
{
    AVFrame *f = e.frame;
    const int w = f->width;
    const int h = f->height;
    const int amp = e.spec->texture;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            int v = e.depth ? depthPattern(x, y, index) : (x * 4 + y * 2 + index * 8) & 0xff;
            if (amp > 0) // a texture moving 2 px per frame, plus a little grain
                v = std::clamp(v / 2 + 64 + (noise(x + 2 * index, y) - 128) * amp / 128 +
                                   (noise(x, y + 7919 * index) & 7) - 4,
                               0, 255);
            f->data[0][y * f->linesize[0] + x] = static_cast<std::uint8_t>(v);
        }
    if (f->format == AV_PIX_FMT_YUV420P) {
        for (int y = 0; y < (h + 1) / 2; ++y)
            for (int x = 0; x < (w + 1) / 2; ++x) {
                f->data[1][y * f->linesize[1] + x] = static_cast<std::uint8_t>(128 + (index % 32));
                f->data[2][y * f->linesize[2] + x] = static_cast<std::uint8_t>(96 + x % 64);
            }
    }
}

} // namespace

Clip Clip::standard(int width, int height, int frames, int fps)
{
    Clip c;
    c.color.title = "color";
    c.color.width = width;
    c.color.height = height;
    c.color.frames = frames;
    c.color.fps = fps;
    c.depth = c.color;
    c.depth.title = "depth";
    c.depth.gray = true;
    c.depth.lossless = true;
    c.depth.metadata = {{"depth_near", "0.5"},
                        {"depth_far", "4"},
                        {"depth_mapping", "inverse"},
                        {"depth_bits", "8"}};
    return c;
}

std::uint8_t depthPattern(int x, int y, int frame) noexcept
{
    return static_cast<std::uint8_t>((frame * 16 + x + y / 4) & 0xff);
}

std::string writeClip(const std::string &path, const Clip &clip)
{
    av_log_set_level(AV_LOG_ERROR); // x264 prints its settings and statistics otherwise
    AVFormatContext *oc = nullptr;
    int r = avformat_alloc_output_context2(
        &oc, nullptr, clip.format.empty() ? nullptr : clip.format.c_str(), path.c_str());
    if (r < 0 || oc == nullptr)
        return avError("output context", r);
    std::vector<std::unique_ptr<Encoder>> encoders;
    std::string err;
    AVPacket *pkt = av_packet_alloc();
    const auto fail = [&](std::string message) {
        err = std::move(message);
        return err;
    };
    for (const ClipStream *s : {&clip.color, &clip.depth}) {
        if (!s->enabled)
            continue;
        auto e = std::make_unique<Encoder>();
        e->spec = s;
        e->depth = s == &clip.depth;
        const AVCodec *codec = avcodec_find_encoder_by_name(s->encoder.c_str());
        if (codec == nullptr)
            return fail("no encoder " + s->encoder);
        e->ctx = avcodec_alloc_context3(codec);
        e->ctx->width = s->width;
        e->ctx->height = s->height;
        e->ctx->time_base = {1, s->fps};
        e->ctx->framerate = {s->fps, 1};
        e->ctx->gop_size = clip.gop;
        e->ctx->max_b_frames = s->bframes;
        e->ctx->pix_fmt = s->gray ? AV_PIX_FMT_GRAY8 : AV_PIX_FMT_YUV420P;
        if (s->encoder == "libx264") {
            av_opt_set(e->ctx->priv_data, "preset", s->preset.c_str(), 0);
            if (s->bframes == 0)
                av_opt_set(e->ctx->priv_data, "tune", "zerolatency", 0);
            if (s->lossless)
                av_opt_set(e->ctx->priv_data, "qp", "0", 0);
        }
        if (oc->oformat->flags & AVFMT_GLOBALHEADER)
            e->ctx->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
        e->ctx->thread_count = 1;
        r = avcodec_open2(e->ctx, codec, nullptr);
        if (r < 0)
            return fail(avError("open encoder", r));
        e->stream = avformat_new_stream(oc, nullptr);
        e->stream->time_base = {1, s->fps};
        e->stream->avg_frame_rate = {s->fps, 1};
        avcodec_parameters_from_context(e->stream->codecpar, e->ctx);
        if (!s->title.empty())
            av_dict_set(&e->stream->metadata, "title", s->title.c_str(), 0);
        for (const auto &[k, v] : s->metadata)
            av_dict_set(&e->stream->metadata, k.c_str(), v.c_str(), 0);
        e->frame = av_frame_alloc();
        e->frame->format = e->ctx->pix_fmt;
        e->frame->width = s->width;
        e->frame->height = s->height;
        if (av_frame_get_buffer(e->frame, 0) < 0)
            return fail("frame buffer");
        encoders.push_back(std::move(e));
    }
    if (encoders.empty())
        return fail("no stream");
    if (!(oc->oformat->flags & AVFMT_NOFILE) &&
        (r = avio_open(&oc->pb, path.c_str(), AVIO_FLAG_WRITE)) < 0)
        return fail(avError("open output", r));
    if ((r = avformat_write_header(oc, nullptr)) < 0)
        return fail(avError("write header", r));
    int most = 0;
    for (auto &e : encoders)
        most = std::max(most, e->spec->frames);
    for (int i = 0; i < most && err.empty(); ++i) {
        for (auto &e : encoders) {
            if (i >= e->spec->frames)
                continue;
            av_frame_make_writable(e->frame);
            fill(*e, i);
            const auto ui = static_cast<std::size_t>(i);
            e->frame->pts = ui < e->spec->pts.size() ? e->spec->pts[ui] : i;
            if ((r = avcodec_send_frame(e->ctx, e->frame)) < 0) {
                err = avError("send frame", r);
                break;
            }
            if (err = drainPackets(oc, *e, pkt); !err.empty())
                break;
        }
    }
    for (auto &e : encoders) {
        if (!err.empty())
            break;
        avcodec_send_frame(e->ctx, nullptr);
        err = drainPackets(oc, *e, pkt);
    }
    if (err.empty() && (r = av_write_trailer(oc)) < 0)
        err = avError("write trailer", r);
    if (!(oc->oformat->flags & AVFMT_NOFILE))
        avio_closep(&oc->pb);
    av_packet_free(&pkt);
    encoders.clear();
    avformat_free_context(oc);
    return err;
}

} // namespace depthtouch::receivertest
