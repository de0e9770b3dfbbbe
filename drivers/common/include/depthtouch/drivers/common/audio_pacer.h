#pragma once
/// \file
/// \brief AudioPacer: the simulated sound card of the audio outputs without one (`null`, `mock`,
/// `wav`): a buffer of frames that the clock plays out at the sample rate.
///
/// Thread-safety: thread-bound, like the audio output that owns it. Deterministic on a
/// platform::ManualClock.

#include <cstddef>
#include <cstdint>

#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {

/// \brief A device buffer played by the clock.
///
/// Frames pushed into an idle device start playing at once; frame k of a run is heard at
/// start + k / rate. When the queue runs empty while time goes on, the device has an underrun: it
/// is counted once and the device waits, idle, for the next push (as ALSA's recovery with
/// snd_pcm_recover() restarts a stream). Paused, nothing plays and nothing is counted; the run
/// restarts at the resume. Draining ends the run without an underrun.
class AudioPacer {
public:
    /// Restarts empty and idle: \a sampleRate frames per second (> 0), \a bufferFrames at most
    /// queued (> 0), counts at zero.
    void start(int sampleRate, std::size_t bufferFrames) noexcept;
    /// \brief Plays what is due by \a now.
    void update(platform::TimePoint now) noexcept;
    /// \brief Queues what fits of \a frames at \a now. \return the frames taken.
    std::size_t push(std::size_t frames, platform::TimePoint now) noexcept;
    /// \brief Holds (\a paused) or releases the queue at \a now.
    void pause(bool paused, platform::TimePoint now) noexcept;
    /// \brief Drops the queue at \a now: idle after.
    void flush(platform::TimePoint now) noexcept;
    /// \return when the last queued frame will have been heard, \a now when nothing is queued.
    [[nodiscard]] platform::TimePoint drainedAt(platform::TimePoint now) const noexcept;
    /// \brief Ends the run after a drain: idle, no underrun counted for the silence that follows.
    void finishDrain(platform::TimePoint now) noexcept;

    [[nodiscard]] std::size_t queued() const noexcept { return queued_; }
    [[nodiscard]] std::size_t bufferFrames() const noexcept { return buffer_; }
    [[nodiscard]] std::uint64_t played() const noexcept { return played_; }
    [[nodiscard]] std::uint64_t underruns() const noexcept { return underruns_; }

private:
    int rate_ = 48000;
    std::size_t buffer_ = 0;
    std::size_t queued_ = 0;
    std::uint64_t played_ = 0;
    std::uint64_t underruns_ = 0;
    bool paused_ = false;
    bool playing_ = false;           ///< A run is going on (frames were queued while not paused).
    platform::TimePoint runStart_{}; ///< When the run's first frame was heard.
    std::uint64_t runPlayed_ = 0;    ///< Frames of this run heard so far.
};

} // namespace depthtouch::drivers
