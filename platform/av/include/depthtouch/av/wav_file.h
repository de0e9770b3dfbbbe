#pragma once
/// \file
/// \brief A WAV file of interleaved signed 16-bit PCM written with libavformat's wav muxer, with a
/// bit-exact header: the `wav` sound output's file (drivers/ffmpeg) and the built-in scenes'
/// soundtracks (dt_media). Header-only, as the rest of dt_av_handles.
///
/// Errors are libav's: 0 or a negative AVERROR code. Thread-safety: one file, one thread.

#include <cerrno>
#include <cstdint>
#include <cstring>

extern "C" {
#include <libavformat/avformat.h>
#include <libavutil/channel_layout.h>
}

namespace depthtouch::av {

/// \brief Makes a WAV muxer of \a rate Hz and \a channels channels writing through \a pb (the
/// caller's AVIOContext, which stays the caller's: closeWavFile() flushes it, never closes it), or,
/// with \a pb null, into \a path opened by libavformat; writes its header.
/// \param[out] out The muxer (nullptr on failure). \return 0 or an AVERROR.
inline int openWavMuxer(AVFormatContext *&out, AVIOContext *pb, const char *path, int rate,
                        int channels) noexcept
{
    out = nullptr;
    AVFormatContext *ctx = nullptr;
    if (avformat_alloc_output_context2(&ctx, nullptr, "wav", path) < 0 || ctx == nullptr)
        return AVERROR(ENOMEM);
    ctx->flags |= AVFMT_FLAG_BITEXACT;
    AVStream *st = avformat_new_stream(ctx, nullptr);
    int err = st == nullptr ? AVERROR(ENOMEM) : 0;
    if (err == 0) {
        st->codecpar->codec_type = AVMEDIA_TYPE_AUDIO;
        st->codecpar->codec_id = AV_CODEC_ID_PCM_S16LE;
        st->codecpar->sample_rate = rate;
        av_channel_layout_default(&st->codecpar->ch_layout, channels);
        st->codecpar->bits_per_coded_sample = 16;
        st->codecpar->block_align = 2 * channels;
        st->codecpar->bit_rate = 16LL * rate * channels;
        st->time_base = AVRational{1, rate};
        if (pb != nullptr) {
            ctx->pb = pb;
            ctx->flags |= AVFMT_FLAG_CUSTOM_IO;
        } else {
            err = avio_open(&ctx->pb, path, AVIO_FLAG_WRITE);
        }
    }
    if (err >= 0)
        err = avformat_write_header(ctx, nullptr);
    if (err >= 0 && ctx->pb->error < 0)
        err = ctx->pb->error;
    if (err < 0) {
        if (ctx->pb != nullptr && (ctx->flags & AVFMT_FLAG_CUSTOM_IO) == 0)
            avio_closep(&ctx->pb);
        avformat_free_context(ctx);
        return err;
    }
    out = ctx;
    return 0;
}

/// \brief Creates \a path as a WAV file of \a rate Hz and \a channels channels and writes its
/// header (in place: see openWavMuxer() to write through an output of one's own).
/// \param[out] out The muxer (nullptr on failure). \return 0 or an AVERROR.
inline int openWavFile(AVFormatContext *&out, const char *path, int rate, int channels) noexcept
{
    return openWavMuxer(out, nullptr, path, rate, channels);
}

/// \brief Appends \a frames frames of \a samples (\a channels interleaved), the first being frame
/// \a first of the file. \return 0 or an AVERROR (a full disk included).
inline int writeWavFrames(AVFormatContext *out, const std::int16_t *samples, std::size_t frames,
                          int channels, std::int64_t first) noexcept
{
    const auto bytes = static_cast<int>(frames * static_cast<std::size_t>(channels) * 2);
    AVPacket *pkt = av_packet_alloc();
    if (pkt == nullptr || av_new_packet(pkt, bytes) < 0) {
        av_packet_free(&pkt);
        return AVERROR(ENOMEM);
    }
    std::memcpy(pkt->data, samples, static_cast<std::size_t>(bytes));
    pkt->pts = first;
    pkt->dts = first;
    pkt->duration = static_cast<std::int64_t>(frames);
    pkt->stream_index = 0;
    int err = av_write_frame(out, pkt);
    av_packet_free(&pkt);
    if (err >= 0 && out->pb->error < 0)
        err = out->pb->error;
    return err;
}

/// \brief Writes the sizes into the header (an output that can seek) and closes \a out (nullptr
/// after; no-op when null); a caller's AVIOContext (openWavMuxer()) is flushed, not closed.
/// \return 0 or an AVERROR.
inline int closeWavFile(AVFormatContext *&out) noexcept
{
    if (out == nullptr)
        return 0;
    int err = av_write_trailer(out);
    if (err >= 0 && out->pb->error < 0)
        err = out->pb->error;
    int closed = 0;
    if ((out->flags & AVFMT_FLAG_CUSTOM_IO) != 0) {
        avio_flush(out->pb);
        closed = out->pb->error;
        out->pb = nullptr;
    } else {
        closed = avio_closep(&out->pb);
    }
    avformat_free_context(out);
    out = nullptr;
    return err < 0 ? err : closed;
}

} // namespace depthtouch::av
