#include "depthtouch/drivers/common/paced_audio_output.h"

#include <algorithm>
#include <cmath>

#include "depthtouch/drivers/common/backend_options.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(AudioOutput)

namespace depthtouch::drivers {

namespace {

// The keys each backend takes, indexed by PacedAudioBackend (unused entries empty).
constexpr const char *kKeys[][4] = {
    {"buffer"},
    {"buffer", "unplug", "refuse_rate", "refuse_channels"},
    {"buffer", "path"},
};
constexpr std::size_t kKeyCounts[] = {1, 4, 2};

} // namespace

Result<PacedAudioSettings> parsePacedAudioSettings(hal::OptionList options,
                                                   PacedAudioBackend backend)
{
    const auto b = static_cast<std::size_t>(backend);
    if (auto r = rejectUnknownOptions(options, kKeys[b], kKeyCounts[b], kLogCategoryAudioOutput,
                                      "Unknown audio output option");
        !r)
        return unexpected(r.error());
    PacedAudioSettings s;
    if (!readOption(options, "buffer", s.bufferMs, 10.0, 2000.0) ||
        !readOption(options, "unplug", s.unplugSeconds, 0.0, 1e6) ||
        !readOption(options, "refuse_rate", s.refuseRate, 0, hal::kMaxAudioRate) ||
        !readOption(options, "refuse_channels", s.refuseChannels, 0, hal::kMaxAudioChannels))
        return unexpected(Errc::InvalidArgument, "Audio output option out of range");
    return s;
}

PacedAudioOutput::PacedAudioOutput(platform::Clock &clock, const PacedAudioSettings &settings)
    : clock_(clock), settings_(settings)
{
}

Result<void> PacedAudioOutput::openDevice(const hal::AudioFormat &format)
{
    if (format.sampleRate == settings_.refuseRate)
        return unexpected(Errc::NotSupported, "the audio device refuses this sample rate");
    if (format.channels == settings_.refuseChannels)
        return unexpected(Errc::NotSupported, "the audio device refuses this channel count");
    const auto buffer = static_cast<std::size_t>(
        std::max(1.0, std::round(settings_.bufferMs * 1e-3 * format.sampleRate)));
    pacer_.start(format.sampleRate, buffer);
    queue_.assign(buffer * static_cast<std::size_t>(format.channels), 0);
    queueHead_ = queueCount_ = 0;
    playedSeen_ = 0;
    unplugAt_ =
        static_cast<std::uint64_t>(std::llround(settings_.unplugSeconds * format.sampleRate));
    return ok();
}

Result<void> PacedAudioOutput::catchUp()
{
    return catchUp(clock_.now());
}

Result<void> PacedAudioOutput::catchUp(platform::TimePoint now)
{
    pacer_.update(now);
    setPlayed(pacer_.played());
    for (std::uint64_t n = underruns(); n < pacer_.underruns(); ++n)
        countUnderrun();
    // Hand the frames heard since the last call to keep(), oldest first (one or two pieces of the
    // ring).
    const auto channels = static_cast<std::size_t>(format().channels);
    const std::size_t capacity = queue_.size() / std::max<std::size_t>(1, channels);
    auto heard = static_cast<std::size_t>(
        std::min<std::uint64_t>(pacer_.played() - playedSeen_, queueCount_));
    playedSeen_ = pacer_.played();
    while (heard > 0 && capacity > 0) {
        const std::size_t piece = std::min(heard, capacity - queueHead_);
        const std::int16_t *from = queue_.data() + queueHead_ * channels;
        queueHead_ = (queueHead_ + piece) % capacity;
        queueCount_ -= piece;
        heard -= piece;
        if (auto r = keep(from, piece); !r)
            return r;
    }
    return ok();
}

Result<void> PacedAudioOutput::keep(const std::int16_t *, std::size_t)
{
    return ok();
}

Result<std::size_t> PacedAudioOutput::writeDevice(const std::int16_t *samples, std::size_t frames)
{
    // Once this says NoDevice the output is Lost (AudioOutputBase): no hook runs until an open().
    if (unplugAt_ > 0) {
        const std::uint64_t left = unplugAt_ - std::min(unplugAt_, framesWritten());
        if (left == 0)
            return unexpected(Errc::NoDevice, "the audio device was unplugged");
        frames = static_cast<std::size_t>(std::min<std::uint64_t>(frames, left));
    }
    // First what was heard (it makes room in the ring), at the same time as the push: nothing
    // plays between the two.
    const platform::TimePoint now = clock_.now();
    DT_TRY(catchUp(now));
    const std::size_t taken = pacer_.push(frames, now);
    const auto channels = static_cast<std::size_t>(format().channels);
    const std::size_t capacity = queue_.size() / std::max<std::size_t>(1, channels);
    for (std::size_t i = 0; i < taken; ++i) {
        const std::size_t at = (queueHead_ + queueCount_ + i) % capacity;
        std::copy_n(samples + i * channels, channels, queue_.data() + at * channels);
    }
    queueCount_ += taken;
    return taken;
}

Result<std::size_t> PacedAudioOutput::delayDevice()
{
    DT_TRY(catchUp());
    return pacer_.queued();
}

Result<void> PacedAudioOutput::pauseDevice(bool paused)
{
    pacer_.pause(paused, clock_.now());
    return catchUp();
}

Result<std::size_t> PacedAudioOutput::flushDevice()
{
    const platform::TimePoint now = clock_.now();
    DT_TRY(catchUp(now)); // what was heard up to now stays heard
    const std::size_t dropped = pacer_.queued();
    pacer_.flush(now);
    queueHead_ = queueCount_ = 0;
    playedSeen_ = pacer_.played();
    DT_TRY(catchUp());
    return dropped;
}

Result<void> PacedAudioOutput::drainDevice()
{
    (void)clock_.sleepUntil(pacer_.drainedAt(clock_.now()));
    pacer_.finishDrain(clock_.now());
    return catchUp();
}

} // namespace depthtouch::drivers
