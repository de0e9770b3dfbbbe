/// \file
/// \brief Test support: reading encoded files back (see readback.h).

#include "readback.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <memory>

#include <gtest/gtest.h>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

namespace depthtouch::media::test {

namespace {

std::string lower(std::string s)
{
    for (char &c : s)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::map<std::string, std::string> tagsOf(const AVDictionary *d)
{
    std::map<std::string, std::string> out;
    const AVDictionaryEntry *e = nullptr;
    while ((e = av_dict_get(d, "", e, AV_DICT_IGNORE_SUFFIX)) != nullptr)
        out[lower(e->key)] = e->value;
    return out;
}

struct Decoder {
    AVCodecContext *ctx = nullptr;
    bool color = false;
    ~Decoder() { avcodec_free_context(&ctx); }
};

Image toImage(const AVFrame &f, bool color)
{
    if (color) {
        Image img = Image::make(f.width, f.height, PixelFormat::Rgb24);
        SwsContext *sws = sws_getContext(
            f.width, f.height, static_cast<AVPixelFormat>(f.format), f.width, f.height,
            AV_PIX_FMT_RGB24, SWS_BILINEAR | SWS_ACCURATE_RND, nullptr, nullptr, nullptr);
        std::uint8_t *dst[4] = {img.data.data(), nullptr, nullptr, nullptr};
        const int stride[4] = {static_cast<int>(img.stride), 0, 0, 0};
        sws_scale(sws, f.data, f.linesize, 0, f.height, dst, stride);
        sws_freeContext(sws);
        return img;
    }
    // Luma plane as is (a gray H.264 stream decodes as yuv420p with neutral chroma).
    const AVPixFmtDescriptor *d = av_pix_fmt_desc_get(static_cast<AVPixelFormat>(f.format));
    const bool deep = d != nullptr && d->comp[0].depth > 8;
    Image img = Image::make(f.width, f.height, deep ? PixelFormat::Gray16 : PixelFormat::Gray8);
    for (int y = 0; y < f.height; ++y)
        std::memcpy(img.row(y), f.data[0] + static_cast<std::ptrdiff_t>(y) * f.linesize[0],
                    img.stride);
    return img;
}

} // namespace

FileReadback readBack(const std::string &path, std::vector<int> colorStreams, bool keepFrames)
{
    FileReadback out;
    AVFormatContext *fmt = nullptr;
    if (avformat_open_input(&fmt, path.c_str(), nullptr, nullptr) < 0) {
        out.error = "cannot open " + path;
        return out;
    }
    std::unique_ptr<AVFormatContext, void (*)(AVFormatContext *)> guard(
        fmt, [](AVFormatContext *c) { avformat_close_input(&c); });
    if (avformat_find_stream_info(fmt, nullptr) < 0) {
        out.error = "no stream info";
        return out;
    }
    out.format = fmt->iformat->name;
    out.tags = tagsOf(fmt->metadata);
    std::vector<std::unique_ptr<Decoder>> decoders;
    for (unsigned i = 0; i < fmt->nb_streams; ++i) {
        const AVStream *st = fmt->streams[i];
        StreamReadback s;
        s.codec = avcodec_get_name(st->codecpar->codec_id);
        const char *prof = avcodec_profile_name(st->codecpar->codec_id, st->codecpar->profile);
        s.profile = prof != nullptr ? prof : "";
        s.width = st->codecpar->width;
        s.height = st->codecpar->height;
        s.tags = tagsOf(st->metadata);
        out.streams.push_back(s);
        auto dec = std::make_unique<Decoder>();
        dec->color = std::find(colorStreams.begin(), colorStreams.end(), static_cast<int>(i)) !=
                     colorStreams.end();
        const AVCodec *codec = avcodec_find_decoder(st->codecpar->codec_id);
        if (codec != nullptr) {
            dec->ctx = avcodec_alloc_context3(codec);
            avcodec_parameters_to_context(dec->ctx, st->codecpar);
            dec->ctx->pkt_timebase = st->time_base;
            dec->ctx->thread_count = 1;
            if (avcodec_open2(dec->ctx, codec, nullptr) < 0)
                avcodec_free_context(&dec->ctx);
        }
        decoders.push_back(std::move(dec));
    }
    AVPacket *pkt = av_packet_alloc();
    AVFrame *frame = av_frame_alloc();
    const auto receive = [&](unsigned i) {
        Decoder &d = *decoders[i];
        while (avcodec_receive_frame(d.ctx, frame) == 0) {
            StreamReadback &s = out.streams[i];
            if ((frame->flags & AV_FRAME_FLAG_CORRUPT) != 0 || frame->decode_error_flags != 0)
                ++out.decodeErrors;
            const char *name = av_get_pix_fmt_name(static_cast<AVPixelFormat>(frame->format));
            s.pixFmt = name != nullptr ? name : "";
            s.pts.push_back(static_cast<double>(frame->best_effort_timestamp) *
                            av_q2d(fmt->streams[i]->time_base));
            if (keepFrames)
                s.frames.push_back(toImage(*frame, d.color));
            av_frame_unref(frame);
        }
    };
    while (av_read_frame(fmt, pkt) >= 0) {
        const auto i = static_cast<unsigned>(pkt->stream_index);
        if (i < decoders.size() && decoders[i]->ctx != nullptr) {
            if (avcodec_send_packet(decoders[i]->ctx, pkt) < 0)
                ++out.decodeErrors;
            receive(i);
        }
        av_packet_unref(pkt);
    }
    for (unsigned i = 0; i < decoders.size(); ++i) {
        if (decoders[i]->ctx == nullptr)
            continue;
        avcodec_send_packet(decoders[i]->ctx, nullptr);
        receive(i);
    }
    av_frame_free(&frame);
    av_packet_free(&pkt);
    out.ok = true;
    return out;
}

void expectStream(const StreamReadback &stream, const StreamFacts &want)
{
    if (!want.codec.empty()) {
        EXPECT_EQ(stream.codec, want.codec);
    }
    if (!want.pixFmt.empty()) {
        EXPECT_EQ(stream.pixFmt, want.pixFmt);
    }
    if (!want.profile.empty()) {
        EXPECT_EQ(stream.profile, want.profile);
    }
    for (const auto &[key, value] : want.tags)
        EXPECT_EQ(stream.tags.at(key), value) << key;
}

double psnr(const Image &a, const Image &b)
{
    if (a.width != b.width || a.height != b.height || a.format != b.format || a.empty())
        return 0.0;
    double se = 0.0;
    std::size_t n = 0;
    const std::size_t rowBytes =
        static_cast<std::size_t>(a.width) * static_cast<std::size_t>(bytesPerPixel(a.format));
    for (int y = 0; y < a.height; ++y)
        for (std::size_t x = 0; x < rowBytes; ++x) {
            const double d = static_cast<double>(a.row(y)[x]) - static_cast<double>(b.row(y)[x]);
            se += d * d;
            ++n;
        }
    if (se == 0.0)
        return 99.0;
    return 10.0 * std::log10(255.0 * 255.0 / (se / static_cast<double>(n)));
}

} // namespace depthtouch::media::test
