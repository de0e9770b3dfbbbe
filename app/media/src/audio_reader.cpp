/// \file
/// \brief The receiver's sound: see audio_reader.h.

#include "depthtouch/media/audio_reader.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

extern "C" {
#include <libavutil/channel_layout.h>
}

#include "media_libav.h"
#include "swr_handle.h"

namespace depthtouch::media {

using namespace detail;

namespace {

/// libav's time base of AVFormatContext::start_time (AV_TIME_BASE_Q is a C compound literal).
constexpr AVRational kMicroseconds{1, AV_TIME_BASE};

/// A frame that starts this close to the previous one's end (s) follows it: 2 ms, four times the
/// rounding of a millisecond time base.
constexpr double kContinuity = 0.002;

/// The rate a decoded stream of \a rate Hz is played at: its own when an AudioOutput takes it.
int playableRate(int rate) noexcept
{
    return rate >= hal::kMinAudioRate && rate <= hal::kMaxAudioRate ? rate : 48000;
}

/// Input samples converted at a time: swr's output for them is at most 24 times as many frames
/// (8 kHz to 192 kHz), 393 216, 6 MiB at 8 channels.
constexpr int kConvertSamples = 16384;

/// \return whether \a rate Hz is a rate the reader takes (hal::kMinSourceRate..kMaxSourceRate).
bool saneRate(int rate) noexcept
{
    return rate >= hal::kMinSourceRate && rate <= hal::kMaxSourceRate;
}

constexpr const char *kBadRate = "The sound's sample rate is outside 8000..384000 Hz";
static_assert(hal::kMinSourceRate == 8000 && hal::kMaxSourceRate == 384000, "kBadRate says so");

/// Packets a live input's queue holds at most: about 10 s of AAC at 48 kHz (1024 frames each).
constexpr std::size_t kMaxQueuedPackets = 512;

/// The packets of a live input's audio stream, from the decode thread (push) to the audio thread
/// (pop). The oldest is dropped when it is full (the sound is not being played).
class PacketQueue final : public hal::AudioPacketSink {
public:
    struct Item {
        std::vector<std::uint8_t> data;
        std::int64_t pts = AV_NOPTS_VALUE; ///< ns on the video packets' clock.
    };

    void push(const hal::Packet &p) noexcept override
    {
        try {
            Item item{std::vector<std::uint8_t>(p.data, p.data + p.size),
                      p.pts == hal::kNoPts ? AV_NOPTS_VALUE : p.pts.count()};
            std::lock_guard<std::mutex> lock(mutex_);
            if (items_.size() >= kMaxQueuedPackets)
                items_.pop_front();
            items_.push_back(std::move(item));
        } catch (...) { // out of memory: this packet of sound is dropped
        }
    }
    /// \return false when there is none now.
    bool pop(Item &out)
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (items_.empty())
            return false;
        out = std::move(items_.front());
        items_.pop_front();
        return true;
    }

private:
    std::mutex mutex_;
    std::deque<Item> items_;
};

/// What AudioReader::Impl::decodeMore() came to.
enum class Got : std::uint8_t { Frame, End, Pending };

} // namespace

struct AudioReader::Impl {
    std::shared_ptr<PacketQueue> queue; ///< A live input's packets; null: `in` is read.
    PacketQueue::Item item;             ///< The queue's packet being decoded.
    InputContextPtr in;
    int index = -1;          ///< The audio stream of `in`.
    AVRational tb{1, 1};     ///< Its time base.
    std::int64_t origin = 0; ///< Its time (tb) of media time 0: the input's start.
    CodecContextPtr decoder;
    SwrPtr swr;
    // What swr converts from (set from the first frame, again when a frame differs).
    int inFormat = -1;
    int inRate = 0;
    AVChannelLayout inLayout{};
    hal::AudioFormat out;
    AVChannelLayout outLayout{};
    PacketPtr packet;
    FramePtr frame;
    int frameUsed = -1;                ///< Samples of `frame` converted so far; -1: no frame held.
    std::vector<std::int16_t> pending; ///< Converted frames not yet read.
    std::size_t pendingFrames = 0;
    std::size_t pendingPos = 0; ///< Frames of `pending` already read.
    double pendingStart = 0.0;  ///< Media time of pending's first frame, s.
    double nextStart = 0.0;     ///< Media time after the last converted frame, s.
    bool haveNext = false;      ///< nextStart follows a frame (not a seek or the start).
    double skipUntil = -std::numeric_limits<double>::infinity(); ///< seek(): drop before it.
    bool flushed = false; ///< The decoder was sent its end (the input has no more packets).
    bool ended = false;   ///< The decoder is drained: nothing more until seek().
    std::string description;

    ~Impl()
    {
        av_channel_layout_uninit(&inLayout);
        av_channel_layout_uninit(&outLayout);
    }

    /// Sets swr up for frames like \a f (the first one, or one whose format changed).
    /// InvalidArgument for a rate outside hal::kMinSourceRate..kMaxSourceRate.
    Result<void> configure(const AVFrame &f)
    {
        if (!saneRate(f.sample_rate))
            return unexpected(Errc::InvalidArgument, kBadRate);
        if (swr && f.format == inFormat && f.sample_rate == inRate &&
            av_channel_layout_compare(&f.ch_layout, &inLayout) == 0)
            return ok();
        av_channel_layout_uninit(&inLayout);
        if (av_channel_layout_copy(&inLayout, &f.ch_layout) < 0)
            return unexpected(Errc::OutOfResources, "Failed to describe the sound");
        if (inLayout.order == AV_CHANNEL_ORDER_UNSPEC)
            av_channel_layout_default(&inLayout, inLayout.nb_channels);
        inFormat = f.format;
        inRate = f.sample_rate;
        SwrContext *s = nullptr;
        if (swr_alloc_set_opts2(&s, &outLayout, AV_SAMPLE_FMT_S16, out.sampleRate, &inLayout,
                                static_cast<AVSampleFormat>(inFormat), inRate, 0, nullptr) < 0 ||
            swr_init(s) < 0) {
            swr_free(&s);
            return unexpected(Errc::NotSupported, "Failed to convert the sound");
        }
        swr.reset(s);
        return ok();
    }

    /// Drops the frame being converted (a seek, an error).
    void dropFrame() noexcept
    {
        av_frame_unref(frame.get());
        frameUsed = -1;
    }

    /// \return the planes of `frame` from its sample \a at.
    std::vector<const std::uint8_t *> planesFrom(int at) const
    {
        const auto fmt = static_cast<AVSampleFormat>(frame->format);
        const bool planar = av_sample_fmt_is_planar(fmt) != 0;
        const int channels = frame->ch_layout.nb_channels;
        const auto step = static_cast<std::size_t>(av_get_bytes_per_sample(fmt)) *
                          static_cast<std::size_t>(planar ? 1 : channels);
        std::vector<const std::uint8_t *> planes(static_cast<std::size_t>(planar ? channels : 1));
        for (std::size_t c = 0; c < planes.size(); ++c)
            planes[c] = frame->extended_data[c] + static_cast<std::size_t>(at) * step;
        return planes;
    }

    /// Converts the next kConvertSamples samples at most of `frame` into `pending` (so that its
    /// size stays bounded whatever the frame's length) and drops what lies before skipUntil.
    Result<void> convert()
    {
        if (frameUsed == 0)
            DT_TRY(configure(*frame));
        const std::int64_t ts = frame->best_effort_timestamp;
        double start = ts == AV_NOPTS_VALUE || frameUsed > 0
                           ? nextStart
                           : static_cast<double>(ts - origin) * av_q2d(tb);
        // A container whose timestamps are rounded (MKV: to the millisecond) puts each frame up
        // to half a unit off the previous one's end: that is no gap and no overlap.
        if (haveNext && std::abs(start - nextStart) <= kContinuity)
            start = nextStart;
        haveNext = true;
        const int samples = std::min(frame->nb_samples - frameUsed, kConvertSamples);
        std::vector<const std::uint8_t *> planes = planesFrom(frameUsed);
        frameUsed += samples;
        const int room = std::max(swr_get_out_samples(swr.get(), samples), 1);
        const auto channels = static_cast<std::size_t>(out.channels);
        pending.resize(static_cast<std::size_t>(room) * channels);
        auto *dst = reinterpret_cast<std::uint8_t *>(pending.data());
        const int n = swr_convert(swr.get(), &dst, room, planes.data(), samples);
        if (n < 0)
            return unexpected(Errc::InvalidArgument, "Failed to convert the sound");
        pendingFrames = static_cast<std::size_t>(n);
        pendingStart = start;
        pendingPos = 0;
        nextStart = start + n / static_cast<double>(out.sampleRate);
        if (start < skipUntil) {
            const auto skip = static_cast<std::size_t>(
                std::llround((skipUntil - start) * static_cast<double>(out.sampleRate)));
            pendingPos = std::min(skip, pendingFrames);
        }
        return ok();
    }

    /// Reads packets of the audio stream into the decoder until it gives a frame.
    /// \return Frame, End (the end of the sound) or Pending (a live input's next packet has not
    /// come yet).
    Result<Got> decodeMore()
    {
        for (;;) {
            if (frameUsed >= 0) { // a frame being converted, a piece at a time
                auto converted = convert();
                if (!converted || frameUsed >= frame->nb_samples)
                    dropFrame();
                if (!converted)
                    return unexpected(converted.error());
                if (pendingPos < pendingFrames)
                    return Got::Frame;
                continue;
            }
            const int got = avcodec_receive_frame(decoder.get(), frame.get());
            if (got >= 0) {
                frameUsed = 0;
                continue;
            }
            if (got == AVERROR_EOF || (got == AVERROR(EAGAIN) && flushed))
                return Got::End;
            if (got != AVERROR(EAGAIN))
                continue; // a damaged frame: skipped
            if (queue) {
                if (!queue->pop(item))
                    return Got::Pending;
                packet->data = item.data.data(); // not reference-counted: the decoder copies it
                packet->size = static_cast<int>(item.data.size());
                packet->pts = packet->dts = item.pts;
                avcodec_send_packet(decoder.get(), packet.get()); // a damaged packet: skipped
                packet->data = nullptr;
                packet->size = 0;
                continue;
            }
            const int r = av_read_frame(in.get(), packet.get());
            if (r == AVERROR_EOF) {
                flushed = true;
                avcodec_send_packet(decoder.get(), nullptr);
                continue;
            }
            if (r < 0)
                return unexpected(Errc::Io, "The sound could not be read further");
            if (packet->stream_index == index)
                avcodec_send_packet(decoder.get(), packet.get()); // a damaged packet: skipped
            av_packet_unref(packet.get());
        }
    }

    Result<void> openDecoder(const AVCodecParameters &par)
    {
        const AVCodec *dec = avcodec_find_decoder(par.codec_id);
        if (dec == nullptr)
            return unexpected(Errc::NotSupported, "No decoder for the sound's codec");
        decoder.reset(avcodec_alloc_context3(dec));
        packet.reset(av_packet_alloc());
        frame.reset(av_frame_alloc());
        if (!decoder || !packet || !frame || avcodec_parameters_to_context(decoder.get(), &par) < 0)
            return unexpected(Errc::OutOfResources, "Failed to set the sound's decoder up");
        decoder->pkt_timebase = tb;
        if (avcodec_open2(decoder.get(), dec, nullptr) < 0)
            return unexpected(Errc::NotSupported, "The sound's decoder refused the stream");
        // The decoder's rate where it reads one from the stream (AAC's), else the container's.
        const int rate = decoder->sample_rate > 0 ? decoder->sample_rate : par.sample_rate;
        if (!saneRate(rate))
            return unexpected(Errc::InvalidArgument, kBadRate);
        const int channels = par.ch_layout.nb_channels;
        out.sampleRate = playableRate(rate);
        out.channels = channels >= 1 && channels <= hal::kMaxAudioChannels ? channels : 2;
        if (out.channels == channels && par.ch_layout.order != AV_CHANNEL_ORDER_UNSPEC)
            av_channel_layout_copy(&outLayout, &par.ch_layout);
        else
            av_channel_layout_default(&outLayout, out.channels);
        return ok();
    }
};

AudioReader::AudioReader() : impl_(std::make_unique<Impl>()) {}
AudioReader::~AudioReader() = default;

Result<std::unique_ptr<AudioReader>> AudioReader::open(const std::string &url)
{
    quietFfmpegLog();
    std::unique_ptr<AudioReader> reader(new AudioReader());
    Impl &a = *reader->impl_;
    DT_TRY(openAudioInput(url, a.in, a.index, "The input does not open as media",
                          "The input has no readable streams"));
    if (a.index < 0)
        return std::unique_ptr<AudioReader>();
    AVFormatContext *ctx = a.in.get();
    const AVStream &st = *ctx->streams[a.index];
    a.tb = st.time_base;
    if (ctx->start_time != AV_NOPTS_VALUE)
        a.origin = av_rescale_q(ctx->start_time, kMicroseconds, a.tb);
    discardOtherStreams(*ctx, a.index);
    DT_TRY(a.openDecoder(*st.codecpar));
    a.description = audioDescription(*st.codecpar);
    return reader;
}

Result<std::unique_ptr<AudioReader>> AudioReader::fromPackets(const hal::AudioStreamInfo &stream)
{
    quietFfmpegLog();
    const AVCodec *dec = avcodec_find_decoder_by_name(stream.codec.c_str());
    if (dec == nullptr)
        return unexpected(Errc::NotSupported, "No decoder for the sound's codec");
    std::unique_ptr<AVCodecParameters, void (*)(AVCodecParameters *)> par(
        avcodec_parameters_alloc(), [](AVCodecParameters *p) { avcodec_parameters_free(&p); });
    if (!par)
        return unexpected(Errc::OutOfResources, "Failed to describe the sound");
    par->codec_type = AVMEDIA_TYPE_AUDIO;
    par->codec_id = dec->id;
    par->sample_rate = stream.sampleRate;
    av_channel_layout_default(&par->ch_layout, std::max(stream.channels, 1));
    if (!stream.extradata.empty()) {
        const std::size_t size = stream.extradata.size();
        par->extradata =
            static_cast<std::uint8_t *>(av_mallocz(size + AV_INPUT_BUFFER_PADDING_SIZE));
        if (par->extradata == nullptr)
            return unexpected(Errc::OutOfResources, "Failed to describe the sound");
        std::memcpy(par->extradata, stream.extradata.data(), size);
        par->extradata_size = static_cast<int>(size);
    }
    std::unique_ptr<AudioReader> reader(new AudioReader());
    Impl &a = *reader->impl_;
    a.tb = AVRational{1, 1'000'000'000}; // hal::Pts: ns, 0 at the input's start
    a.queue = std::make_shared<PacketQueue>();
    DT_TRY(a.openDecoder(*par));
    a.description = stream.codec + " " + std::to_string(stream.sampleRate) + " Hz " +
                    std::to_string(stream.channels) + " ch";
    return reader;
}

std::shared_ptr<hal::AudioPacketSink> AudioReader::packetSink() const
{
    return impl_->queue;
}

hal::AudioFormat AudioReader::format() const noexcept
{
    return impl_->out;
}

Result<hal::PcmBlock> AudioReader::read(std::int16_t *samples, std::size_t frames)
{
    Impl &a = *impl_;
    if (samples == nullptr && frames > 0)
        return unexpected(Errc::InvalidArgument, "No buffer for the sound");
    hal::PcmBlock block;
    block.start = a.nextStart;
    if (frames == 0 || a.ended)
        return block;
    if (a.pendingPos >= a.pendingFrames) {
        auto more = a.decodeMore();
        if (more && *more == Got::Pending) {
            block.pending = true;
            return block;
        }
        if (!more || *more == Got::End) {
            a.ended = true;
            if (!more)
                return unexpected(more.error());
            return block;
        }
    }
    const auto channels = static_cast<std::size_t>(a.out.channels);
    block.frames = std::min(frames, a.pendingFrames - a.pendingPos);
    block.start =
        a.pendingStart + static_cast<double>(a.pendingPos) / static_cast<double>(a.out.sampleRate);
    std::memcpy(samples, a.pending.data() + a.pendingPos * channels,
                block.frames * channels * sizeof(std::int16_t));
    a.pendingPos += block.frames;
    return block;
}

Result<void> AudioReader::seek(double seconds)
{
    Impl &a = *impl_;
    if (a.queue)
        return unexpected(Errc::NotSupported, "A live input's sound cannot seek");
    const double at = std::max(seconds, 0.0);
    const std::int64_t target = a.origin + static_cast<std::int64_t>(std::floor(at / av_q2d(a.tb)));
    if (av_seek_frame(a.in.get(), a.index, target, AVSEEK_FLAG_BACKWARD) < 0)
        return unexpected(Errc::Io, "The sound could not seek");
    avcodec_flush_buffers(a.decoder.get());
    a.dropFrame();
    a.swr.reset(); // set up again from the next frame: nothing of before the seek stays in it
    a.pendingFrames = a.pendingPos = 0;
    a.skipUntil = at;
    a.nextStart = at;
    a.haveNext = false;
    a.flushed = a.ended = false;
    return ok();
}

const std::string &AudioReader::description() const noexcept
{
    return impl_->description;
}

} // namespace depthtouch::media
