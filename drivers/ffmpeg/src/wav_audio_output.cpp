#include "depthtouch/drivers/ffmpeg/wav_audio_output.h"

#include "depthtouch/av/wav_file.h"
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
    if (av::openWavFile(out_, path_.c_str(), format.sampleRate, format.channels) < 0)
        return unexpected(Errc::Io, "cannot create the WAV file");
    kept_ = 0;
    return PacedAudioOutput::openDevice(format);
}

Result<void> WavAudioOutput::keep(const std::int16_t *samples, std::size_t frames)
{
    if (out_ == nullptr)
        return unexpected(Errc::InvalidState, "no WAV file");
    if (av::writeWavFrames(out_, samples, frames, format().channels, kept_) < 0)
        return unexpected(Errc::Io, "cannot write the WAV file (disk full?)");
    kept_ += static_cast<std::int64_t>(frames);
    return ok();
}

void WavAudioOutput::closeDevice() noexcept
{
    (void)catchUp(); // what was heard by now; the rest of the queue never is
    (void)av::closeWavFile(out_);
}

} // namespace depthtouch::drivers
