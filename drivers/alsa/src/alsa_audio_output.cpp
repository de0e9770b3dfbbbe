#include "depthtouch/drivers/alsa/alsa_audio_output.h"

#include <alsa/asoundlib.h>

#include <algorithm>
#include <cerrno>
#include <cmath>

#include "depthtouch/drivers/common/backend_options.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Alsa)

namespace depthtouch::drivers {

namespace {

constexpr const char *kKeys[] = {"device", "buffer"};

/// alsa-lib's messages (it prints them on stderr by default): dropped, as the errors it returns
/// reach the caller with a text of their own.
void quietAlsa(const char *, int, const char *, int, const char *, ...) {}

/// \return whether \a err says the device went away.
bool gone(long err) noexcept
{
    return err == -ENODEV || err == -ENOTTY || err == -ENXIO || err == -EBADFD;
}

} // namespace

Result<std::unique_ptr<hal::AudioOutput>> AlsaAudioOutput::create(const hal::BackendConfig &cfg)
{
    if (auto r = rejectUnknownOptions(cfg.options, kKeys, std::size(kKeys), kLogCategoryAlsa,
                                      "Unknown alsa option");
        !r)
        return unexpected(r.error());
    double bufferMs = 100.0;
    if (!readOption(cfg.options, "buffer", bufferMs, 10.0, 2000.0))
        return unexpected(Errc::InvalidArgument, "alsa option buffer outside 10..2000 ms");
    std::string device(cfg.device);
    if (const auto d = cfg.options.find("device"))
        device = std::string(*d);
    if (device.empty())
        device = "default";
    static const bool quiet = snd_lib_error_set_handler(&quietAlsa) == 0;
    (void)quiet;
    snd_pcm_t *probe = nullptr;
    if (snd_pcm_open(&probe, device.c_str(), SND_PCM_STREAM_PLAYBACK, SND_PCM_NONBLOCK) < 0)
        return unexpected(Errc::NoDevice, "no ALSA playback device");
    snd_pcm_close(probe);
    return std::unique_ptr<hal::AudioOutput>(
        std::make_unique<AlsaAudioOutput>(std::move(device), bufferMs));
}

AlsaAudioOutput::AlsaAudioOutput(std::string device, double bufferMs)
    : device_(std::move(device)), bufferMs_(bufferMs)
{
}

AlsaAudioOutput::~AlsaAudioOutput()
{
    close();
}

Result<void> AlsaAudioOutput::openDevice(const hal::AudioFormat &format)
{
    snd_pcm_t *pcm = nullptr;
    int err = snd_pcm_open(&pcm, device_.c_str(), SND_PCM_STREAM_PLAYBACK, SND_PCM_NONBLOCK);
    if (err < 0)
        return unexpected(Errc::NoDevice, "the ALSA device does not open", -err);
    const auto latencyUs = static_cast<unsigned>(std::lround(bufferMs_ * 1000.0));
    err = snd_pcm_set_params(pcm, SND_PCM_FORMAT_S16, SND_PCM_ACCESS_RW_INTERLEAVED,
                             static_cast<unsigned>(format.channels),
                             static_cast<unsigned>(format.sampleRate), 1, latencyUs);
    snd_pcm_uframes_t buffer = 0;
    snd_pcm_uframes_t period = 0;
    if (err >= 0)
        err = snd_pcm_get_params(pcm, &buffer, &period);
    if (err < 0) {
        snd_pcm_close(pcm);
        DT_LOG(Alsa, Warning, "'%s' refuses %d Hz, %d channels: %s", device_.c_str(),
               format.sampleRate, format.channels, snd_strerror(err));
        return unexpected(Errc::NotSupported, "the ALSA device refuses the format", -err);
    }
    pcm_ = pcm;
    buffer_ = static_cast<std::size_t>(buffer);
    return ok();
}

void AlsaAudioOutput::publish(long delay) noexcept
{
    const auto queued = static_cast<std::uint64_t>(std::max(0L, delay));
    setPlayed(framesWritten() - std::min(framesWritten(), queued));
}

Result<void> AlsaAudioOutput::recover(long err)
{
    if (gone(err))
        return unexpected(Errc::NoDevice, "the ALSA device is gone", static_cast<int>(-err));
    if (err == -EPIPE || err == -ESTRPIPE)
        countUnderrun();
    const int r = snd_pcm_recover(pcm_, static_cast<int>(err), 1);
    if (r < 0)
        return unexpected(gone(r) ? Errc::NoDevice : Errc::Io, "ALSA could not recover", -r);
    return ok();
}

Result<std::size_t> AlsaAudioOutput::writeDevice(const std::int16_t *samples, std::size_t frames)
{
    for (int attempt = 0; attempt < 2; ++attempt) {
        const snd_pcm_sframes_t avail = snd_pcm_avail_update(pcm_);
        if (avail < 0) {
            if (auto r = recover(avail); !r)
                return unexpected(r.error());
            continue;
        }
        const auto n = std::min(frames, static_cast<std::size_t>(avail));
        if (n == 0)
            return std::size_t{0};
        const snd_pcm_sframes_t wrote = snd_pcm_writei(pcm_, samples, n);
        if (wrote == -EAGAIN)
            return std::size_t{0};
        if (wrote < 0) {
            if (auto r = recover(wrote); !r)
                return unexpected(r.error());
            continue;
        }
        snd_pcm_sframes_t delay = 0;
        if (snd_pcm_delay(pcm_, &delay) == 0)
            publish(delay - wrote); // the base counts this write after we return
        return static_cast<std::size_t>(wrote);
    }
    return std::size_t{0};
}

Result<std::size_t> AlsaAudioOutput::delayDevice()
{
    snd_pcm_sframes_t delay = 0;
    const int err = snd_pcm_delay(pcm_, &delay);
    if (err < 0) {
        if (auto r = recover(err); !r)
            return unexpected(r.error());
        delay = 0;
    }
    publish(delay);
    return static_cast<std::size_t>(std::max<snd_pcm_sframes_t>(0, delay));
}

Result<void> AlsaAudioOutput::pauseDevice(bool paused)
{
    const int err = snd_pcm_pause(pcm_, paused ? 1 : 0);
    if (err < 0) {
        if (gone(err))
            return unexpected(Errc::NoDevice, "the ALSA device is gone", -err);
        return unexpected(Errc::NotSupported, "the ALSA device cannot pause", -err);
    }
    return ok();
}

Result<void> AlsaAudioOutput::restart(int err, const char *what)
{
    if (err >= 0)
        err = snd_pcm_prepare(pcm_);
    if (err < 0)
        return unexpected(gone(err) ? Errc::NoDevice : Errc::Io, what, -err);
    publish(0);
    return ok();
}

Result<std::size_t> AlsaAudioOutput::flushDevice()
{
    // The delay just before the drop: what it drops (a stopped or broken stream drops nothing
    // that would be heard).
    snd_pcm_sframes_t delay = 0;
    if (snd_pcm_delay(pcm_, &delay) < 0)
        delay = 0;
    DT_TRY(restart(snd_pcm_drop(pcm_), "ALSA could not flush"));
    return static_cast<std::size_t>(std::max<snd_pcm_sframes_t>(0, delay));
}

Result<void> AlsaAudioOutput::drainDevice()
{
    snd_pcm_nonblock(pcm_, 0);
    const int err = snd_pcm_drain(pcm_);
    snd_pcm_nonblock(pcm_, 1);
    return restart(err, "ALSA could not drain");
}

void AlsaAudioOutput::closeDevice() noexcept
{
    if (pcm_ != nullptr)
        snd_pcm_close(pcm_);
    pcm_ = nullptr;
    buffer_ = 0;
}

} // namespace depthtouch::drivers
