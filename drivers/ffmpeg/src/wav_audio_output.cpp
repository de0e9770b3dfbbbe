#include "depthtouch/drivers/ffmpeg/wav_audio_output.h"

#include <cstring>

extern "C" {
#include <libavformat/avformat.h>
#include <libavutil/channel_layout.h>
}

#include "ffmpeg_common.h"

namespace depthtouch::drivers {

namespace {

constexpr const char *kDefaultPath = "depthtouch-audio.wav";

} // namespace

Result<std::unique_ptr<hal::AudioOutput>> WavAudioOutput::create(const hal::BackendConfig &cfg)
{
    auto s = parsePacedAudioSettings(cfg.options, PacedAudioBackend::Wav);
    if (!s)
        return unexpected(s.error());
    std::string path(cfg.options.find("path").value_or(cfg.device));
    if (path.empty())
        path = kDefaultPath;
    return std::unique_ptr<hal::AudioOutput>(
        std::make_unique<WavAudioOutput>(cfg.clockRef(), *s, std::move(path)));
}

WavAudioOutput::WavAudioOutput(platform::Clock &clock, const PacedAudioSettings &settings,
                               std::string path)
    : PacedAudioOutput(clock, settings), path_(std::move(path))
{
}

WavAudioOutput::~WavAudioOutput()
{
    close();
}

Result<void> WavAudioOutput::openDevice(const hal::AudioFormat &format)
{
    ffmpeg::quietLibav();
    AVFormatContext *out = nullptr;
    if (avformat_alloc_output_context2(&out, nullptr, "wav", path_.c_str()) < 0 || out == nullptr)
        return unexpected(Errc::Io, "cannot set up the WAV file");
    out->flags |= AVFMT_FLAG_BITEXACT;
    AVStream *st = avformat_new_stream(out, nullptr);
    int err = st == nullptr ? AVERROR(ENOMEM) : 0;
    if (err == 0) {
        st->codecpar->codec_type = AVMEDIA_TYPE_AUDIO;
        st->codecpar->codec_id = AV_CODEC_ID_PCM_S16LE;
        st->codecpar->sample_rate = format.sampleRate;
        av_channel_layout_default(&st->codecpar->ch_layout, format.channels);
        st->codecpar->bits_per_coded_sample = 16;
        st->codecpar->block_align = 2 * format.channels;
        st->codecpar->bit_rate = 16LL * format.sampleRate * format.channels;
        st->time_base = AVRational{1, format.sampleRate};
        err = avio_open(&out->pb, path_.c_str(), AVIO_FLAG_WRITE);
    }
    if (err >= 0)
        err = avformat_write_header(out, nullptr);
    if (err < 0) {
        if (out->pb != nullptr)
            avio_closep(&out->pb);
        avformat_free_context(out);
        return unexpected(Errc::Io, "cannot create the WAV file");
    }
    out_ = out;
    return PacedAudioOutput::openDevice(format);
}

Result<void> WavAudioOutput::keep(const std::int16_t *samples, std::size_t frames)
{
    if (out_ == nullptr)
        return unexpected(Errc::InvalidState, "no WAV file");
    const auto bytes = static_cast<int>(frames * static_cast<std::size_t>(format().channels) * 2);
    AVPacket *pkt = av_packet_alloc();
    if (pkt == nullptr || av_new_packet(pkt, bytes) < 0) {
        av_packet_free(&pkt);
        return unexpected(Errc::OutOfResources, "no memory for the WAV packet");
    }
    std::memcpy(pkt->data, samples, static_cast<std::size_t>(bytes));
    pkt->pts = static_cast<std::int64_t>(framesWritten());
    pkt->dts = pkt->pts;
    pkt->duration = static_cast<std::int64_t>(frames);
    pkt->stream_index = 0;
    const int err = av_write_frame(out_, pkt);
    av_packet_free(&pkt);
    if (err < 0 || out_->pb->error < 0)
        return unexpected(Errc::Io, "cannot write the WAV file (disk full?)");
    return ok();
}

void WavAudioOutput::closeDevice() noexcept
{
    if (out_ == nullptr)
        return;
    av_write_trailer(out_);
    avio_closep(&out_->pb);
    avformat_free_context(out_);
    out_ = nullptr;
}

} // namespace depthtouch::drivers
