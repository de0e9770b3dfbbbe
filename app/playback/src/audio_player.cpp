/// \file
/// \brief The sound of an open stream: see audio_player.h.

#include "depthtouch/playback/audio_player.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "depthtouch/platform/thread_config.h"

namespace depthtouch::playback {

namespace {

constexpr std::size_t kBlockFrames = 2048; ///< Frames read from the source at a time.
constexpr double kGainRampSeconds = 0.01;  ///< A volume change moves over this long.
constexpr double kMinQueueSeconds = 0.01;
constexpr double kMaxQueueSeconds = 1.0;
constexpr double kFastestDevice = 1.005; ///< The fastest a device's rate is believed, × nominal.
constexpr double kRunSlack = 0.02;       ///< Sound a device may seem to play ahead of time, s.
/// The longest sleep of the audio thread between two looks at its stop request.
constexpr platform::Duration kStopSlice = std::chrono::milliseconds(10);

/// Frames of a ramp (the fade-in and fade-out of a join) at \a rate Hz.
std::size_t rampFrames(int rate) noexcept
{
    return static_cast<std::size_t>(std::ceil(kGainRampSeconds * static_cast<double>(rate)));
}

} // namespace

double volumeGain(double percent, bool mute) noexcept
{
    if (mute || !(percent > 0.0))
        return 0.0;
    const double v = std::min(percent, AudioPlayerConfig::kMaxVolume) / 100.0;
    return v * v * v;
}

AudioPlayer::AudioPlayer(hal::AudioSource &source, hal::AudioOutput &output, platform::Clock &clock,
                         const AudioPlayerConfig &config)
    : source_(source), output_(output), clock_(clock), config_(config), format_(source.format()),
      queueFrames_(static_cast<std::size_t>(
          std::llround(config.queueSeconds * static_cast<double>(format_.sampleRate))))
{
    const auto samples = kBlockFrames * static_cast<std::size_t>(format_.channels);
    block_.resize(samples);
    scaled_.resize(samples);
    const auto channels = static_cast<std::size_t>(format_.channels);
    written_.resize((queueFrames_ + kBlockFrames) * channels);
    fadeOut_.resize(rampFrames(format_.sampleRate) * channels);
    targetGain_ = gain_ = volumeGain(config.volume, config.mute);
}

Result<std::unique_ptr<AudioPlayer>> AudioPlayer::create(hal::AudioSource &source,
                                                         hal::AudioOutput &output,
                                                         platform::Clock &clock,
                                                         const AudioPlayerConfig &config)
{
    static_assert(options::kVolume.min == 0.0 && options::kVolume.max == 130.0,
                  "the message below says the range");
    if (!options::kVolume.contains(config.volume))
        return unexpected(Errc::InvalidArgument, "The volume must be 0 to 130 %");
    if (!(config.queueSeconds >= kMinQueueSeconds && config.queueSeconds <= kMaxQueueSeconds))
        return unexpected(Errc::InvalidArgument, "The sound's queue must be 0.01 to 1 s");
    DT_TRY(output.open(source.format()));
    return std::unique_ptr<AudioPlayer>(new AudioPlayer(source, output, clock, config));
}

AudioPlayer::~AudioPlayer()
{
    if (thread_) {
        thread_->requestStop();
        thread_->join();
    }
    output_.close();
}

Result<void> AudioPlayer::startThread()
{
    // A quarter of the queue between turns keeps it at least three quarters full.
    const auto period = std::chrono::duration_cast<platform::Duration>(
        std::chrono::duration<double>(config_.queueSeconds / 4.0));
    // The wait is slept in slices of kStopSlice at most: a stop (a join) waits for one slice and
    // the step under way (bounded: AudioReader converts a bounded piece at a time), not a turn.
    thread_.emplace(platform::kAudioThread, platform::kPlainThreadOptions,
                    [this, period](platform::StopToken stop) {
                        while (!stop.stopRequested()) {
                            step();
                            for (platform::Duration left = period;
                                 left > platform::Duration{0} && !stop.stopRequested();
                                 left -= kStopSlice)
                                clock_.sleepFor(std::min(left, kStopSlice));
                        }
                    });
    if (auto r = thread_->start(); !r) {
        thread_.reset();
        return unexpected(Errc::OutOfResources, "No thread for the sound");
    }
    return ok();
}

void AudioPlayer::start(double seconds)
{
    std::lock_guard<std::mutex> lock(mutex_);
    ++startGen_;
    startAt_ = seconds;
    published_.running = false;
}

void AudioPlayer::halt()
{
    std::lock_guard<std::mutex> lock(mutex_);
    ++haltGen_;
    published_.running = false;
}

void AudioPlayer::setPaused(bool paused)
{
    std::lock_guard<std::mutex> lock(mutex_);
    paused_ = paused;
    if (paused)
        published_.running = false;
}

void AudioPlayer::setVolume(double percent)
{
    std::lock_guard<std::mutex> lock(mutex_);
    config_.volume = options::kVolume.clamp(std::isfinite(percent) ? percent : 0.0);
    targetGain_ = volumeGain(config_.volume, config_.mute);
}

void AudioPlayer::setMute(bool mute)
{
    std::lock_guard<std::mutex> lock(mutex_);
    config_.mute = mute;
    targetGain_ = volumeGain(config_.volume, config_.mute);
}

MasterClock AudioPlayer::clock() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return published_;
}

double AudioPlayer::volume() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return config_.volume;
}

bool AudioPlayer::muted() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return config_.mute;
}

AudioStats AudioPlayer::stats() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return stats_;
}

void AudioPlayer::publish(bool running, double mediaTime, double queued, platform::TimePoint at)
{
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.delaySeconds = queued;
    const bool current = startGen_ == startSeen_ && haltGen_ == haltSeen_ && !paused_;
    published_.running = running && current;
    published_.at = at;
    published_.mediaTime = mediaTime;
    stats_.framesWritten = soundFrames_;
    stats_.underruns = underruns_;
    stats_.silenceFrames = silenceFrames_;
    stats_.ended = mode_ == Mode::Ended;
}

void AudioPlayer::lose(const Error &error)
{
    mode_ = Mode::Lost;
    std::lock_guard<std::mutex> lock(mutex_);
    if (stats_.lost.empty())
        stats_.lost = std::string("the sound output failed: ") + error.what;
    published_.running = false;
}

void AudioPlayer::step()
{
    std::uint64_t startGen = 0;
    std::uint64_t haltGen = 0;
    double startAt = 0.0;
    bool paused = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        startGen = startGen_;
        haltGen = haltGen_;
        startAt = startAt_;
        paused = paused_;
        rampTarget_ = targetGain_;
    }
    if (mode_ == Mode::Lost)
        return;
    if (mode_ == Mode::Playing && output_.delayFrames()) // the device's count brought up to date
        countUnderruns(); // before a restart forgets that the sound had ended
    if (mode_ != Mode::Playing)
        gain_ = rampTarget_; // nothing sounds: a new volume needs no ramp
    if (!control(startGen, haltGen, startAt, paused))
        return;
    if (mode_ == Mode::Idle || mode_ == Mode::Paused) {
        // Halted: the fade-out of the cut, then nothing. Paused: silence keeps the device going.
        auto delay = queued();
        if (!delay)
            return lose(delay.error());
        std::size_t want = fadeOutFrames_ - fadeOutPos_;
        if (mode_ == Mode::Paused)
            want = std::max(want, queueFrames_ - std::min(queueFrames_, *delay));
        for (std::size_t w = 1; want > 0 && w > 0; want -= w)
            w = writeZeros(want);
        if (mode_ == Mode::Lost)
            return;
        publish(false, mode_ == Mode::Paused ? pausedAt_ : writtenEnd_, 0.0, clock_.now());
        return;
    }
    if (mode_ == Mode::Playing) {
        auto before = queued();
        if (!before)
            return lose(before.error());
        fill(*before);
        if (mode_ == Mode::Lost)
            return;
    }
    auto delay = queued();
    if (!delay)
        return lose(delay.error());
    countUnderruns();
    const double queued = static_cast<double>(*delay) / static_cast<double>(format_.sampleRate);
    if (mode_ == Mode::Playing && sourceEnded_ && *delay == 0)
        mode_ = Mode::Ended;
    publish(mode_ == Mode::Playing, writtenEnd_ - queued, queued, clock_.now());
}

bool AudioPlayer::control(std::uint64_t startGen, std::uint64_t haltGen, double startAt,
                          bool paused)
{
    const bool restart = startGen != startSeen_;
    if (restart || haltGen != haltSeen_) {
        haltSeen_ = haltGen;
        startSeen_ = startGen;
        if (!cut())
            return false;
        mode_ = Mode::Idle;
        if (restart && paused) {
            mode_ = Mode::Paused; // a seek while paused: the sound starts there at the resume
            pausedAt_ = startAt;
        } else if (restart) {
            begin(startAt);
        }
    }
    if (paused == pausedSeen_)
        return true;
    pausedSeen_ = paused;
    if (paused && mode_ == Mode::Playing) {
        const auto dropped = cut();
        if (!dropped)
            return false;
        pausedAt_ = writtenEnd_ - static_cast<double>(*dropped) / format_.sampleRate;
        mode_ = Mode::Paused;
    } else if (!paused && mode_ == Mode::Paused) {
        if (!cut()) // the silence queued while paused
            return false;
        begin(pausedAt_);
    }
    return true;
}

std::optional<std::size_t> AudioPlayer::cut()
{
    // The drop first: the device plays on until it, and the frames it dropped are those after
    // the last one heard.
    auto dropped = output_.flush();
    if (!dropped) {
        lose(dropped.error());
        return std::nullopt;
    }
    const std::size_t delay = atLeastTheRun(*dropped);
    runStart_ = clock_.now(); // the device is empty: a new run of frames begins
    runFirstFrame_ = writtenFrames_;
    // The dropped queue's first frames (the one heard next first) faded to 0 over the ramp, to
    // be written next. A queue shorter than the ramp (a late thread left little queued) is
    // followed by the sound that would have come next, so the fade still takes the whole ramp
    // where the source has it.
    const auto channels = static_cast<std::size_t>(format_.channels);
    const std::size_t ringFrames = written_.size() / channels;
    const std::size_t ramp = fadeOut_.size() / channels;
    const std::size_t queued =
        static_cast<std::size_t>(std::min<std::uint64_t>({delay, writtenFrames_, ringFrames}));
    std::size_t n = std::min(queued, ramp);
    const std::uint64_t first = writtenFrames_ - queued;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t at = static_cast<std::size_t>((first + i) % ringFrames) * channels;
        std::copy_n(written_.data() + at, channels, fadeOut_.data() + i * channels);
    }
    n += nextSound(fadeOut_.data() + n * channels, ramp - n);
    for (std::size_t i = 0; i < n; ++i) {
        const double g = 1.0 - static_cast<double>(i + 1) / static_cast<double>(n);
        for (std::size_t c = 0; c < channels; ++c)
            fadeOut_[i * channels + c] =
                static_cast<std::int16_t>(std::lround(fadeOut_[i * channels + c] * g));
    }
    fadeOutFrames_ = n;
    fadeOutPos_ = 0;
    return delay;
}

std::size_t AudioPlayer::nextSound(std::int16_t *to, std::size_t frames) const
{
    if (mode_ != Mode::Playing || blockPos_ >= have_.frames)
        return 0;
    const double rate = static_cast<double>(format_.sampleRate);
    const double gap = have_.start + static_cast<double>(blockPos_) / rate - writtenEnd_;
    if (std::llround(gap * rate) != 0)
        return 0; // silence comes next: nothing to fade
    const auto channels = static_cast<std::size_t>(format_.channels);
    const std::size_t n = std::min(frames, have_.frames - blockPos_);
    const std::int16_t *src = block_.data() + blockPos_ * channels;
    for (std::size_t i = 0; i < n * channels; ++i)
        to[i] = static_cast<std::int16_t>(
            std::clamp(std::round(static_cast<double>(src[i]) * gain_), -32768.0, 32767.0));
    return n;
}

Result<std::size_t> AudioPlayer::queued()
{
    auto delay = output_.delayFrames();
    if (!delay)
        return delay;
    return atLeastTheRun(*delay);
}

std::size_t AudioPlayer::atLeastTheRun(std::size_t delay) const
{
    // A device cannot play faster than time passes; one that seems to (ALSA's `null` PCM takes
    // every frame at once and says none is queued) would run the clock, and the picture that
    // follows it, ahead. The queue is at least what was written in this run less what could have
    // been heard since it began: its time at the rate, 0.5 % fast (no sound card's crystal is off
    // by that much), plus 20 ms.
    const double rate = static_cast<double>(format_.sampleRate);
    const double couldHear =
        platform::toSeconds(clock_.now() - runStart_) * rate * kFastestDevice + kRunSlack * rate;
    const auto run = static_cast<double>(writtenFrames_ - runFirstFrame_);
    if (run > couldHear)
        delay = std::max(delay, static_cast<std::size_t>(run - couldHear));
    return delay;
}

void AudioPlayer::begin(double seconds)
{
    // A source that cannot seek plays on from where it is: its sound before t is dropped.
    (void)source_.seek(seconds);
    writtenEnd_ = seconds;
    have_ = {};
    blockPos_ = 0;
    sourceEnded_ = false;
    gain_ = 0.0; // faded in over the ramp: a start, a seek, a loop or a resume does not click
    underrunsSeen_ = output_.underruns(); // the device running dry while halted is none
    mode_ = Mode::Playing;
}

void AudioPlayer::countUnderruns()
{
    // The device running dry after the last sound is the end, not an underrun.
    const std::uint64_t underruns = output_.underruns();
    if (!sourceEnded_)
        underruns_ += underruns - underrunsSeen_;
    underrunsSeen_ = underruns;
}

void AudioPlayer::fill(std::size_t delay)
{
    const double rate = static_cast<double>(format_.sampleRate);
    std::size_t queued = delay;
    while (queued < queueFrames_) {
        const std::size_t want = std::min(queueFrames_ - queued, kBlockFrames);
        if (blockPos_ >= have_.frames) {
            if (sourceEnded_)
                return;
            auto got = source_.read(block_.data(), kBlockFrames);
            if (got && got->frames == 0 && got->pending)
                return; // a live input's sound has not come yet: the next turn
            if (!got || got->frames == 0) {
                sourceEnded_ = true; // the end, or a read error: the sound ends there
                return;
            }
            have_ = *got;
            blockPos_ = 0;
        }
        const double gap = have_.start + static_cast<double>(blockPos_) / rate - writtenEnd_;
        const auto gapFrames = std::llround(gap * rate);
        std::size_t taken = 0;
        if (gapFrames >= 1) {
            taken = writeSilence(std::min(want, static_cast<std::size_t>(gapFrames)));
        } else if (gapFrames <= -1) {
            blockPos_ += std::min(have_.frames - blockPos_, static_cast<std::size_t>(-gapFrames));
            continue;
        } else {
            taken = writeSound(std::min(want, have_.frames - blockPos_));
        }
        if (mode_ == Mode::Lost || taken == 0)
            return; // lost, or the device's buffer is full
        queued += taken;
    }
}

namespace {

/// \return \a from moved toward \a to by at most \a by.
double moveToward(double from, double to, double by) noexcept
{
    return from < to ? std::min(from + by, to) : std::max(from - by, to);
}

} // namespace

std::size_t AudioPlayer::writeSound(std::size_t frames)
{
    const auto channels = static_cast<std::size_t>(format_.channels);
    const double rate = static_cast<double>(format_.sampleRate);
    const double step = 1.0 / (kGainRampSeconds * rate);
    const std::int16_t *src = block_.data() + blockPos_ * channels;
    for (std::size_t i = 0; i < frames; ++i) {
        const double g = moveToward(gain_, rampTarget_, static_cast<double>(i + 1) * step);
        for (std::size_t c = 0; c < channels; ++c) {
            const double v = std::round(static_cast<double>(src[i * channels + c]) * g);
            scaled_[i * channels + c] = static_cast<std::int16_t>(std::clamp(v, -32768.0, 32767.0));
        }
    }
    const std::size_t w = writeOut(frames);
    gain_ = moveToward(gain_, rampTarget_, static_cast<double>(w) * step);
    blockPos_ += w;
    writtenEnd_ += static_cast<double>(w) / rate;
    soundFrames_ += w;
    return w;
}

std::size_t AudioPlayer::writeSilence(std::size_t frames)
{
    const std::size_t w = writeZeros(frames);
    writtenEnd_ += static_cast<double>(w) / static_cast<double>(format_.sampleRate);
    silenceFrames_ += w;
    return w;
}

std::size_t AudioPlayer::writeZeros(std::size_t frames)
{
    const auto channels = static_cast<std::size_t>(format_.channels);
    frames = std::min(frames, kBlockFrames);
    std::fill_n(scaled_.begin(), frames * channels, std::int16_t{0});
    return writeOut(frames);
}

std::size_t AudioPlayer::writeOut(std::size_t frames)
{
    const auto channels = static_cast<std::size_t>(format_.channels);
    const std::size_t mixed = std::min(frames, fadeOutFrames_ - fadeOutPos_);
    const std::int16_t *fade = fadeOut_.data() + fadeOutPos_ * channels;
    for (std::size_t i = 0; i < mixed * channels; ++i)
        scaled_[i] = static_cast<std::int16_t>(
            std::clamp(scaled_[i] + static_cast<int>(fade[i]), -32768, 32767));
    auto w = output_.write(scaled_.data(), frames);
    if (!w) {
        lose(w.error());
        return 0;
    }
    fadeOutPos_ += std::min(*w, mixed);
    const std::size_t ringFrames = written_.size() / channels;
    for (std::size_t i = 0; i < *w; ++i) {
        const std::size_t at = static_cast<std::size_t>((writtenFrames_ + i) % ringFrames);
        std::copy_n(scaled_.data() + i * channels, channels, written_.data() + at * channels);
    }
    writtenFrames_ += *w;
    return *w;
}

} // namespace depthtouch::playback
