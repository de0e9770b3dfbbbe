#pragma once
/// \file
/// \brief AlsaAudioOutput (backend `alsa`): sound through an ALSA PCM (libasound), the set-top
/// box's sound output.
///
/// Device: BackendConfig::device or option `device=NAME` (an ALSA PCM name: `default`,
/// `hw:0,3`, `plughw:1`, `null`); default `default`. The factory opens the PCM once to see that it
/// is there (NoDevice otherwise, so autoprobe falls back to `null`). open() asks for S16
/// interleaved at the format's rate and channels with ALSA's own conversion allowed
/// (snd_pcm_set_params()), and a buffer of `buffer=MS` (10..2000, default 100). Writes never block
/// (SND_PCM_NONBLOCK): write() takes what snd_pcm_avail_update() says fits. As mpv's ao_alsa does:
/// an underrun (-EPIPE) or a suspend (-ESTRPIPE) is counted and recovered with snd_pcm_recover(),
/// and the write goes on; delayFrames() is snd_pcm_delay(); framesPlayed() is frames written less
/// that delay. An unplugged device (-ENODEV, -ENOTTY, -EBADFD after recovery fails) is NoDevice:
/// the output is Lost. pause() uses snd_pcm_pause() (NotSupported where the device cannot pause),
/// flush() snd_pcm_delay() (what it drops), snd_pcm_drop() then snd_pcm_prepare(), drain() a
/// blocking snd_pcm_drain(). Thread-safety: as hal::AudioOutput.

#include <memory>
#include <string>

#include "depthtouch/hal/audio_output_base.h"
#include "depthtouch/hal/backends.h"

struct _snd_pcm; // libasound's snd_pcm_t

namespace depthtouch::drivers {

class AlsaAudioOutput final : public hal::AudioOutputBase {
public:
    /// Backend factory. Errors: InvalidArgument (options), NoDevice (the PCM does not open).
    static Result<std::unique_ptr<hal::AudioOutput>> create(const hal::BackendConfig &cfg);

    AlsaAudioOutput(std::string device, double bufferMs);
    ~AlsaAudioOutput() override;

protected:
    [[nodiscard]] Result<void> openDevice(const hal::AudioFormat &format) override;
    [[nodiscard]] Result<std::size_t> writeDevice(const std::int16_t *samples,
                                                  std::size_t frames) override;
    [[nodiscard]] Result<std::size_t> delayDevice() override;
    [[nodiscard]] std::size_t bufferFramesDevice() const noexcept override { return buffer_; }
    [[nodiscard]] Result<void> pauseDevice(bool paused) override;
    [[nodiscard]] Result<std::size_t> flushDevice() override;
    [[nodiscard]] Result<void> drainDevice() override;
    void closeDevice() noexcept override;

private:
    /// Counts and recovers an underrun or suspend (\a err -EPIPE or -ESTRPIPE), or says what
    /// \a err is. \return ok when the stream can go on.
    [[nodiscard]] Result<void> recover(long err);
    /// After a drop or a drain that returned \a err: prepares the PCM for the next write (empty).
    /// \return NoDevice (gone) or Io with \a what (a static string) when either failed.
    [[nodiscard]] Result<void> restart(int err, const char *what);
    /// Publishes framesPlayed() from the frames written and \a delay.
    void publish(long delay) noexcept;

    std::string device_;
    double bufferMs_ = 100.0;
    _snd_pcm *pcm_ = nullptr;
    std::size_t buffer_ = 0;
};

} // namespace depthtouch::drivers
