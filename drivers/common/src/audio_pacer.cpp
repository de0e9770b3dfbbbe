#include "depthtouch/drivers/common/audio_pacer.h"

#include <algorithm>
#include <cmath>

namespace depthtouch::drivers {

void AudioPacer::start(int sampleRate, std::size_t bufferFrames) noexcept
{
    *this = AudioPacer{};
    rate_ = std::max(1, sampleRate);
    buffer_ = std::max<std::size_t>(1, bufferFrames);
}

void AudioPacer::update(platform::TimePoint now) noexcept
{
    if (!playing_ || paused_)
        return;
    const double elapsed = std::max(0.0, platform::toSeconds(now - runStart_));
    const auto due = static_cast<std::uint64_t>(std::floor(elapsed * rate_));
    if (due <= runPlayed_)
        return;
    const std::uint64_t step = std::min<std::uint64_t>(due - runPlayed_, queued_);
    queued_ -= static_cast<std::size_t>(step);
    runPlayed_ += step;
    played_ += step;
    if (queued_ == 0 && due > runPlayed_) { // the device ran dry: an underrun, then idle
        ++underruns_;
        playing_ = false;
    }
}

std::size_t AudioPacer::push(std::size_t frames, platform::TimePoint now) noexcept
{
    update(now);
    const std::size_t taken = std::min(frames, buffer_ - queued_);
    queued_ += taken;
    if (taken > 0 && !playing_) {
        playing_ = true;
        runStart_ = now;
        runPlayed_ = 0;
    }
    return taken;
}

void AudioPacer::pause(bool paused, platform::TimePoint now) noexcept
{
    update(now);
    if (paused_ == paused)
        return;
    paused_ = paused;
    if (!paused && playing_) { // the run goes on from the resume
        runStart_ = now;
        runPlayed_ = 0;
    }
}

void AudioPacer::flush(platform::TimePoint now) noexcept
{
    update(now);
    queued_ = 0;
    playing_ = false;
}

platform::TimePoint AudioPacer::drainedAt(platform::TimePoint now) const noexcept
{
    if (!playing_ || queued_ == 0)
        return now;
    const double end = static_cast<double>(runPlayed_ + queued_) / rate_;
    return std::max(now, runStart_ + std::chrono::duration_cast<platform::Duration>(
                                         std::chrono::duration<double>(end)));
}

void AudioPacer::finishDrain(platform::TimePoint now) noexcept
{
    if (playing_ && !paused_) {
        const std::uint64_t before = underruns_;
        update(now);
        underruns_ = before;
    }
    if (queued_ == 0)
        playing_ = false;
}

} // namespace depthtouch::drivers
