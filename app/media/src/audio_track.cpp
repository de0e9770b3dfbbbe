/// \file
/// \brief The sender's sound: see audio_track.h.

#include "depthtouch/media/audio_track.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

extern "C" {
#include <libavutil/audio_fifo.h>
#include <libavutil/channel_layout.h>
}

#include "muxer_impl.h"
#include "swr_handle.h"

namespace depthtouch::media {

using namespace detail;

namespace {

struct FifoDeleter {
    void operator()(AVAudioFifo *f) const noexcept { av_audio_fifo_free(f); }
};

constexpr long long kAacBitRatePerChannel = 64000; ///< 128 kbit/s for stereo.

/// \return whether \a codec is a broadcast sound codec a set-top box decodes (AAC, Opus, MPEG-1
/// Layer II/III, AC-3, E-AC-3): sound already so coded is copied; PCM, FLAC and the rest are coded
/// as AAC (PCM would take 1.5 Mbit/s of a stream for stereo at 48 kHz).
bool broadcastCodec(AVCodecID codec)
{
    return codec == AV_CODEC_ID_AAC || codec == AV_CODEC_ID_OPUS || codec == AV_CODEC_ID_MP2 ||
           codec == AV_CODEC_ID_MP3 || codec == AV_CODEC_ID_AC3 || codec == AV_CODEC_ID_EAC3;
}

/// \return whether \a container carries \a codec (a broadcastCodec()) as it is. MPEG-TS (and
/// HLS's segments), whose muxer does not answer avformat_query_codec(): all of them (ISO/IEC
/// 13818-1's audio stream types that libavformat's muxer writes).
bool carries(Container container, const AVOutputFormat &format, AVCodecID codec)
{
    if (!broadcastCodec(codec))
        return false;
    if (container == Container::MpegTs || container == Container::Hls)
        return true;
    return avformat_query_codec(&format, codec, FF_COMPLIANCE_NORMAL) == 1;
}

/// \return \a rate when AAC codes it, else 48000.
int aacRate(const AVCodec &aac, int rate)
{
    for (const int *r = aac.supported_samplerates; r != nullptr && *r != 0; ++r)
        if (*r == rate)
            return rate;
    return 48000;
}

} // namespace

struct AudioTrack::Impl {
    Muxer::Impl *muxer = nullptr;
    InputContextPtr in;
    int index = -1;          ///< The audio stream of `in`.
    AVRational inTb{1, 1};   ///< Its time base.
    std::int64_t origin = 0; ///< Input time (inTb) of output time 0.
    AVStream *out = nullptr;
    PacketPtr packet;
    bool pending = false; ///< `packet` holds a packet read but not yet written.
    bool ended = false;   ///< The input has no more audio.
    // Coding as AAC (when the container does not carry the source's codec):
    CodecContextPtr decoder;
    CodecContextPtr encoder;
    SwrPtr swr;
    std::unique_ptr<AVAudioFifo, FifoDeleter> fifo;
    FramePtr frame;
    FramePtr converted;
    PacketPtr coded;
    std::int64_t nextSample = -1; ///< Output PTS (1/rate) of the next coded sample; -1: none yet.
    std::string description;
    long long bytes = 0;

    /// Output seconds of a packet's PTS (its DTS when it has none).
    [[nodiscard]] double seconds(const AVPacket &p) const
    {
        const std::int64_t ts = p.pts != AV_NOPTS_VALUE ? p.pts : p.dts;
        return ts == AV_NOPTS_VALUE ? 0.0 : static_cast<double>(ts - origin) * av_q2d(inTb);
    }

    Result<void> writeCopy(double endSeconds)
    {
        AVPacket &p = *packet;
        const double at = seconds(p);
        if (at < 0.0 || at >= endSeconds || (p.dts != AV_NOPTS_VALUE && p.dts < origin)) {
            av_packet_unref(&p); // before the picture's start or after its end
            return ok();
        }
        if (p.pts != AV_NOPTS_VALUE)
            p.pts -= origin;
        if (p.dts != AV_NOPTS_VALUE)
            p.dts -= origin;
        av_packet_rescale_ts(&p, inTb, out->time_base);
        p.stream_index = out->index;
        p.pos = -1;
        bytes += p.size;
        return muxer->write(&p);
    }

    /// Codes whole AAC frames from the FIFO (a last, shorter one when \a last), none past
    /// \a endSeconds.
    Result<void> encodeFifo(bool last, double endSeconds)
    {
        const int size = encoder->frame_size;
        const auto limit = static_cast<std::int64_t>(std::floor(endSeconds * encoder->sample_rate));
        for (;;) {
            int n = std::min(av_audio_fifo_size(fifo.get()), size);
            n = static_cast<int>(
                std::min<std::int64_t>(n, std::max<std::int64_t>(0, limit - nextSample)));
            if (n <= 0 || (n < size && !last))
                return ok();
            AVFrame &f = *converted;
            av_frame_unref(&f);
            f.nb_samples = n;
            f.format = encoder->sample_fmt;
            f.sample_rate = encoder->sample_rate;
            if (av_channel_layout_copy(&f.ch_layout, &encoder->ch_layout) < 0 ||
                av_frame_get_buffer(&f, 0) < 0)
                return unexpected(Errc::OutOfResources, "Failed to allocate an audio frame");
            if (av_audio_fifo_read(fifo.get(), reinterpret_cast<void **>(f.data), n) != n)
                return unexpected(Errc::OutOfResources, "Failed to read the audio buffer");
            f.pts = nextSample;
            nextSample += n;
            if (avcodec_send_frame(encoder.get(), &f) < 0)
                return unexpected(Errc::InvalidArgument, "Failed to code the audio as AAC");
            DT_TRY(drainEncoder());
        }
    }

    Result<void> drainEncoder()
    {
        for (;;) {
            const int ret = avcodec_receive_packet(encoder.get(), coded.get());
            if (ret == AVERROR(EAGAIN) || ret == AVERROR_EOF)
                return ok();
            if (ret < 0)
                return unexpected(Errc::InvalidArgument, "Failed to code the audio as AAC");
            av_packet_rescale_ts(coded.get(), encoder->time_base, out->time_base);
            coded->stream_index = out->index;
            bytes += coded->size;
            DT_TRY(muxer->write(coded.get()));
        }
    }

    /// Decodes the held packet (all of them when it is null: the end) into the FIFO, then codes.
    Result<void> writeCoded(bool flush, double endSeconds)
    {
        if (avcodec_send_packet(decoder.get(), flush ? nullptr : packet.get()) < 0) {
            av_packet_unref(packet.get()); // a damaged packet: skipped
            return ok();
        }
        av_packet_unref(packet.get());
        for (;;) {
            const int ret = avcodec_receive_frame(decoder.get(), frame.get());
            if (ret == AVERROR(EAGAIN) || ret == AVERROR_EOF)
                break;
            if (ret < 0)
                return ok(); // a damaged frame: skipped
            DT_TRY(convert(endSeconds));
            av_frame_unref(frame.get());
        }
        return encodeFifo(flush, endSeconds);
    }

    /// The decoded frame, resampled into the FIFO (the first one kept sets the output PTS).
    Result<void> convert(double endSeconds)
    {
        const std::int64_t ts = frame->best_effort_timestamp;
        const double at =
            ts == AV_NOPTS_VALUE ? 0.0 : static_cast<double>(ts - origin) * av_q2d(inTb);
        if (at < 0.0 || at >= endSeconds)
            return ok(); // before the picture's start or after its end
        if (nextSample < 0)
            nextSample = std::llround(at * encoder->sample_rate);
        const int room = swr_get_out_samples(swr.get(), frame->nb_samples);
        AVFrame &c = *converted;
        av_frame_unref(&c);
        c.nb_samples = std::max(room, 1);
        c.format = encoder->sample_fmt;
        c.sample_rate = encoder->sample_rate;
        if (av_channel_layout_copy(&c.ch_layout, &encoder->ch_layout) < 0 ||
            av_frame_get_buffer(&c, 0) < 0)
            return unexpected(Errc::OutOfResources, "Failed to allocate an audio frame");
        const int n =
            swr_convert(swr.get(), c.data, c.nb_samples,
                        const_cast<const std::uint8_t **>(frame->extended_data), frame->nb_samples);
        if (n < 0)
            return unexpected(Errc::InvalidArgument, "Failed to convert the audio");
        if (n > 0 && av_audio_fifo_write(fifo.get(), reinterpret_cast<void **>(c.data), n) != n)
            return unexpected(Errc::OutOfResources, "Failed to buffer the audio");
        return ok();
    }

    /// Reads the next packet of the audio stream into `packet`; false at the end. A read error
    /// (a damaged or truncated file) ends the sound, not the encode: the picture goes on.
    Result<bool> read()
    {
        for (;;) {
            const int ret = av_read_frame(in.get(), packet.get());
            if (ret == AVERROR_EOF)
                return false;
            if (ret < 0) {
                description += ", ended early (unreadable after " +
                               std::to_string(static_cast<long long>(bytes / 1000)) + " kB)";
                return false;
            }
            if (packet->stream_index == index)
                return true;
            av_packet_unref(packet.get());
        }
    }

    Result<void> writeUntil(double seconds_, double endSeconds)
    {
        while (!ended) {
            if (!pending) {
                auto got = read();
                if (!got)
                    return unexpected(got.error());
                if (!*got) {
                    ended = true;
                    break;
                }
                pending = true;
            }
            if (seconds(*packet) > seconds_)
                return ok(); // later: written with a later picture
            pending = false;
            DT_TRY(decoder ? writeCoded(false, endSeconds) : writeCopy(endSeconds));
        }
        return ok();
    }

    Result<void> openCoding(const AVStream &st);
};

Result<void> AudioTrack::Impl::openCoding(const AVStream &st)
{
    const AVCodec *dec = avcodec_find_decoder(st.codecpar->codec_id);
    const AVCodec *aac = avcodec_find_encoder(AV_CODEC_ID_AAC);
    if (dec == nullptr || aac == nullptr)
        return unexpected(Errc::NotSupported, "FFmpeg cannot decode the audio or code AAC");
    decoder.reset(avcodec_alloc_context3(dec));
    encoder.reset(avcodec_alloc_context3(aac));
    frame.reset(av_frame_alloc());
    converted.reset(av_frame_alloc());
    coded.reset(av_packet_alloc());
    if (!decoder || !encoder || !frame || !converted || !coded ||
        avcodec_parameters_to_context(decoder.get(), st.codecpar) < 0)
        return unexpected(Errc::OutOfResources, "Failed to allocate the audio coder");
    decoder->pkt_timebase = st.time_base;
    if (avcodec_open2(decoder.get(), dec, nullptr) < 0)
        return unexpected(Errc::NotSupported, "Failed to open the audio decoder");
    AVCodecContext &e = *encoder;
    e.sample_fmt = AV_SAMPLE_FMT_FLTP; // the native AAC encoder's only format
    e.sample_rate = aacRate(*aac, decoder->sample_rate);
    if (av_channel_layout_copy(&e.ch_layout, &decoder->ch_layout) < 0 ||
        e.ch_layout.nb_channels < 1)
        av_channel_layout_default(&e.ch_layout, 2);
    if (e.ch_layout.order == AV_CHANNEL_ORDER_UNSPEC)
        av_channel_layout_default(&e.ch_layout, e.ch_layout.nb_channels);
    e.bit_rate = kAacBitRatePerChannel * e.ch_layout.nb_channels;
    e.time_base = AVRational{1, e.sample_rate};
    if ((muxer->fmt->oformat->flags & AVFMT_GLOBALHEADER) != 0)
        e.flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    if (avcodec_open2(encoder.get(), aac, nullptr) < 0)
        return unexpected(Errc::NotSupported, "Failed to open the AAC encoder");
    SwrContext *s = nullptr;
    if (swr_alloc_set_opts2(&s, &e.ch_layout, e.sample_fmt, e.sample_rate, &decoder->ch_layout,
                            decoder->sample_fmt, decoder->sample_rate, 0, nullptr) < 0 ||
        swr_init(s) < 0) {
        swr_free(&s);
        return unexpected(Errc::NotSupported, "Failed to set up the audio conversion");
    }
    swr.reset(s);
    fifo.reset(av_audio_fifo_alloc(e.sample_fmt, e.ch_layout.nb_channels, e.frame_size * 4));
    if (!fifo)
        return unexpected(Errc::OutOfResources, "Failed to allocate the audio buffer");
    if (avcodec_parameters_from_context(out->codecpar, encoder.get()) < 0)
        return unexpected(Errc::OutOfResources, "Failed to describe the audio stream");
    out->time_base = e.time_base;
    return ok();
}

AudioTrack::AudioTrack() : impl_(std::make_unique<Impl>()) {}
AudioTrack::~AudioTrack() = default;

Result<std::unique_ptr<AudioTrack>> AudioTrack::open(const std::string &source, bool pictureSource,
                                                     Muxer &muxer)
{
    Muxer::Impl &m = *muxer.impl_;
    if (m.started || m.fmt == nullptr)
        return unexpected(Errc::InvalidState, "Streams must be added before the muxer starts");
    std::unique_ptr<AudioTrack> track(new AudioTrack());
    Impl &a = *track->impl_;
    a.muxer = &m;
    DT_TRY(openAudioInput(source, a.in, a.index,
                          "The sound's source does not open as media (damaged or truncated?)",
                          "The sound's source has no readable streams"));
    if (a.index < 0)
        return std::unique_ptr<AudioTrack>();
    AVFormatContext *ctx = a.in.get();
    const AVStream &st = *ctx->streams[a.index];
    a.inTb = st.time_base;
    // Output 0 is the color stream's start (the same file) or the audio's own start.
    const int video =
        pictureSource ? av_find_best_stream(ctx, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0) : -1;
    const AVStream *zero = video >= 0 ? ctx->streams[video] : &st;
    if (zero->start_time != AV_NOPTS_VALUE)
        a.origin = av_rescale_q(zero->start_time, zero->time_base, a.inTb);
    discardOtherStreams(*ctx, a.index);
    a.packet.reset(av_packet_alloc());
    a.out = avformat_new_stream(m.fmt, nullptr);
    if (!a.packet || a.out == nullptr)
        return unexpected(Errc::OutOfResources, "Failed to add the audio stream");
    a.description = audioDescription(*st.codecpar);
    if (carries(m.container, *m.fmt->oformat, st.codecpar->codec_id)) {
        if (avcodec_parameters_copy(a.out->codecpar, st.codecpar) < 0)
            return unexpected(Errc::OutOfResources, "Failed to describe the audio stream");
        a.out->codecpar->codec_tag = 0; // the output container's own tag
        a.out->time_base = st.time_base;
        a.description += ", copied";
    } else {
        DT_TRY(a.openCoding(st));
        a.description += ", coded as aac";
    }
    if (const AVDictionaryEntry *lang = av_dict_get(st.metadata, "language", nullptr, 0))
        av_dict_set(&a.out->metadata, "language", lang->value, 0);
    return track;
}

Result<void> AudioTrack::writeUntil(double seconds)
{
    return impl_->writeUntil(seconds, std::numeric_limits<double>::infinity());
}

Result<void> AudioTrack::finish(double endSeconds)
{
    Impl &a = *impl_;
    DT_TRY(a.writeUntil(endSeconds, endSeconds));
    if (a.pending) { // after the picture's end
        av_packet_unref(a.packet.get());
        a.pending = false;
    }
    if (!a.decoder)
        return ok();
    if (a.ended)
        DT_TRY(a.writeCoded(true, endSeconds));
    DT_TRY(a.encodeFifo(true, endSeconds));
    if (avcodec_send_frame(a.encoder.get(), nullptr) < 0)
        return unexpected(Errc::InvalidArgument, "Failed to finish the AAC stream");
    return a.drainEncoder();
}

const std::string &AudioTrack::description() const noexcept
{
    return impl_->description;
}

long long AudioTrack::bytes() const noexcept
{
    return impl_->bytes;
}

} // namespace depthtouch::media
