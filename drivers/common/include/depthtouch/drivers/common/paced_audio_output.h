#pragma once
/// \file
/// \brief PacedAudioOutput: an audio output without a sound card that keeps time like one, the
/// base of the `null`, `mock` (drivers/mock) and `wav` (drivers/ffmpeg) backends.
///
/// Time: drivers::AudioPacer on the backend clock: frames queued by write() are heard at the sample
/// rate from the moment the device starts; running dry while open is an underrun (counted, then the
/// device waits for the next write). drain() sleeps on the clock until the queue is heard.
/// What is heard is handed to keep() as it is heard, in order: frames dropped by flush() or still
/// queued at close() never are (a file backend holds what a speaker would have played, not what
/// was written).
///
/// Options (`key=value`, parsePacedAudioSettings()): `buffer=MS` the device buffer, 10..2000 ms
/// (default 100); with faults (the `mock` backend): `unplug=S` the device goes away once S seconds
/// of sound were written (write() takes what comes before it, then NoDevice), `refuse_rate=HZ`
/// open() refuses that sample rate (NotSupported), `refuse_channels=N` open() refuses N channels.
/// Unknown keys and values out of range: InvalidArgument.
/// Thread-safety: as hal::AudioOutput.

#include <cstdint>
#include <memory>
#include <vector>

#include "depthtouch/drivers/common/audio_pacer.h"
#include "depthtouch/hal/audio_output_base.h"
#include "depthtouch/hal/backends.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {

/// \brief What the `null` and `mock` audio outputs are told by their options.
struct PacedAudioSettings {
    double bufferMs = 100.0;    ///< Device buffer, ms.
    double unplugSeconds = 0.0; ///< mock: sound written before the device goes away, s (0: never).
    int refuseRate = 0;         ///< mock: a sample rate open() refuses (0: none).
    int refuseChannels = 0;     ///< mock: a channel count open() refuses (0: none).
};

/// \brief Which backend's options parsePacedAudioSettings() reads: `buffer` for all, the faults
/// for Mock, `path` (read by the backend itself) for Wav.
enum class PacedAudioBackend : std::uint8_t { Null, Mock, Wav };

/// \brief The settings of \a options for \a backend.
/// \return Errors: InvalidArgument (a key \a backend does not take, logged; a value out of
/// range). Reentrant.
[[nodiscard]] Result<PacedAudioSettings> parsePacedAudioSettings(hal::OptionList options,
                                                                 PacedAudioBackend backend);

/// \brief A sound card simulated on the clock (see the file comment); a subclass keeps the frames
/// the device takes (keep()).
class PacedAudioOutput : public hal::AudioOutputBase {
public:
    PacedAudioOutput(platform::Clock &clock, const PacedAudioSettings &settings);
    ~PacedAudioOutput() override { close(); }

protected:
    [[nodiscard]] Result<void> openDevice(const hal::AudioFormat &format) override;
    [[nodiscard]] Result<std::size_t> writeDevice(const std::int16_t *samples,
                                                  std::size_t frames) override;
    [[nodiscard]] Result<std::size_t> delayDevice() override;
    [[nodiscard]] std::size_t bufferFramesDevice() const noexcept override
    {
        return pacer_.bufferFrames();
    }
    [[nodiscard]] Result<void> pauseDevice(bool paused) override;
    [[nodiscard]] Result<std::size_t> flushDevice() override;
    [[nodiscard]] Result<void> drainDevice() override;
    void closeDevice() noexcept override {}

    /// \brief What a subclass does with \a frames frames once they are heard (a file backend
    /// writes them), oldest first. An error ends the call that played them (write, delay, flush,
    /// drain) with that error. The default keeps nothing.
    [[nodiscard]] virtual Result<void> keep(const std::int16_t *samples, std::size_t frames);

    /// Plays what is due now, publishes the counts and keeps what was heard.
    [[nodiscard]] Result<void> catchUp();
    /// The same at \a now (a time the caller uses again, so nothing plays in between).
    [[nodiscard]] Result<void> catchUp(platform::TimePoint now);

    platform::Clock &clock_;

private:
    PacedAudioSettings settings_;
    AudioPacer pacer_;
    std::uint64_t unplugAt_ = 0;      ///< Frames written after which the device is gone (0: never).
    std::vector<std::int16_t> queue_; ///< The queued frames (a ring of the buffer's size).
    std::size_t queueHead_ = 0;       ///< Frame index in queue_ of the oldest queued frame.
    std::size_t queueCount_ = 0;      ///< Frames in queue_ not yet heard.
    std::uint64_t playedSeen_ = 0;    ///< The pacer's played() when queue_ was last trimmed.
};

} // namespace depthtouch::drivers
