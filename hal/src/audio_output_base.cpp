#include "depthtouch/hal/audio_output_base.h"

namespace depthtouch::hal {

Result<void> AudioOutputBase::checkUsable() const noexcept
{
    switch (state()) {
    case State::Closed:
        return unexpected(Errc::InvalidState, "the audio output is not open");
    case State::Lost:
        return unexpected(Errc::NoDevice, "the audio device is gone");
    default:
        return ok();
    }
}

template <class T> Result<T> AudioOutputBase::noteLoss(Result<T> r) noexcept
{
    if (!r && r.error().code == Errc::NoDevice)
        state_.store(State::Lost, std::memory_order_release);
    return r;
}

Result<void> AudioOutputBase::open(const AudioFormat &format)
{
    if (state() != State::Closed)
        return unexpected(Errc::InvalidState, "open() requires state Closed");
    if (format.sampleRate < kMinAudioRate || format.sampleRate > kMaxAudioRate)
        return unexpected(Errc::InvalidArgument, "sample rate outside 8000..192000 Hz");
    if (format.channels < 1 || format.channels > kMaxAudioChannels)
        return unexpected(Errc::InvalidArgument, "channels outside 1..8");
    if (auto r = openDevice(format); !r)
        return r;
    format_ = format;
    written_ = 0;
    played_.store(0, std::memory_order_relaxed);
    underruns_.store(0, std::memory_order_relaxed);
    state_.store(State::Open, std::memory_order_release);
    return ok();
}

Result<std::size_t> AudioOutputBase::write(const std::int16_t *samples, std::size_t frames)
{
    if (auto r = checkUsable(); !r)
        return unexpected(r.error());
    if (frames == 0)
        return std::size_t{0};
    if (samples == nullptr)
        return unexpected(Errc::InvalidArgument, "no samples to write");
    auto taken = noteLoss(writeDevice(samples, frames));
    if (taken)
        written_ += *taken;
    return taken;
}

Result<std::size_t> AudioOutputBase::delayFrames()
{
    if (auto r = checkUsable(); !r)
        return unexpected(r.error());
    return noteLoss(delayDevice());
}

Result<void> AudioOutputBase::pause(bool paused)
{
    if (auto r = checkUsable(); !r)
        return r;
    if ((state() == State::Paused) == paused)
        return ok();
    if (auto r = noteLoss(pauseDevice(paused)); !r)
        return r;
    state_.store(paused ? State::Paused : State::Open, std::memory_order_release);
    return ok();
}

Result<std::size_t> AudioOutputBase::flush()
{
    if (auto r = checkUsable(); !r)
        return unexpected(r.error());
    return noteLoss(flushDevice());
}

Result<void> AudioOutputBase::drain()
{
    if (auto r = checkUsable(); !r)
        return r;
    if (state() == State::Paused)
        return unexpected(Errc::InvalidState, "a paused audio output does not drain");
    return noteLoss(drainDevice());
}

void AudioOutputBase::close() noexcept
{
    if (state() == State::Closed)
        return;
    closeDevice();
    state_.store(State::Closed, std::memory_order_release);
}

} // namespace depthtouch::hal
