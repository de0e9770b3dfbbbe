#pragma once
/// \file
/// \brief WavAudioOutput (backend `wav`): an audio output that writes what it plays into a WAV
/// file (libavformat's wav muxer, PCM s16le, bit-exact header), keeping time like a sound card
/// (drivers::PacedAudioOutput: the file holds every frame as it is heard, in order, and
/// framesPlayed()/delayFrames() say when; frames dropped by flush() or still queued at close() are
/// not in it, as a speaker would not have played them). For tests, for hearing joins (seek, pause)
/// as a listener would, and for measuring A/V sync by analysing the file against the presented
/// frames' times.
///
/// Device: BackendConfig::device, or option `path=FILE` (default `depthtouch-audio.wav`); the file
/// is created (replaced) at open() and finished (its sizes written) at close(). Options: `buffer`
/// as the `null` backend. Errors: open() Io when the file cannot be created; write() Io when a
/// write fails (the sound is lost: the caller reports it). Thread-safety: as hal::AudioOutput.

#include <cstdint>
#include <memory>
#include <string>

#include "depthtouch/drivers/common/paced_audio_output.h"
#include "depthtouch/hal/backends.h"

struct AVFormatContext;

namespace depthtouch::drivers {

class WavAudioOutput final : public PacedAudioOutput {
public:
    /// Backend factory. Errors: InvalidArgument (options).
    static Result<std::unique_ptr<hal::AudioOutput>> create(const hal::BackendConfig &cfg);

    WavAudioOutput(platform::Clock &clock, const PacedAudioSettings &settings, std::string path);
    ~WavAudioOutput() override;

protected:
    [[nodiscard]] Result<void> openDevice(const hal::AudioFormat &format) override;
    void closeDevice() noexcept override;
    [[nodiscard]] Result<void> keep(const std::int16_t *samples, std::size_t frames) override;

private:
    std::string path_;
    AVFormatContext *out_ = nullptr;
    std::int64_t kept_ = 0; ///< Frames in the file.
};

} // namespace depthtouch::drivers
