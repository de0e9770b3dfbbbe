#pragma once
/// \file
/// \brief AudioPlayer: the sound of an open stream, pulled from a hal::AudioSource, turned by the
/// volume and written to a hal::AudioOutput on the audio thread, and the audio clock the picture
/// and the haptic time follow (docs/playing.md, "Sound"; docs/architecture.md §1).
///
/// Clock: audio is the master clock when it plays (mpv's default `--video-sync=audio`). After each
/// turn the audio thread publishes which media time the speaker plays at that moment: the media
/// time after the last frame written minus the device's queue (AudioOutput::delayFrames()). The
/// render thread moves the picture's media origin onto it (FrameClock::follow()), and with it the
/// haptic task's. The device's queue is kept at AudioPlayerConfig::queueSeconds: that is the
/// latency of pause, seek and volume.
///
/// Timeline: start(t) plays from media time t (the first frame on screen after open, a seek, a
/// loop): the source seeks there sample-accurately; where the source has no sound (before its
/// start, a gap) silence is played, sound it repeats is dropped. halt() silences at once (a seek
/// begins, stop). Pause silences the same way and plays silence while paused (the device keeps
/// running, as Kodi's sink does); resume starts again at the media time heard at the pause. The
/// volume is a gain on the samples, (volume / 100)³ as mpv's software volume, moved to a new value
/// over 10 ms so a change does not click; mute is gain 0 the same way.
///
/// Joins without a click: every start (open, seek, loop, resume) fades in over the same 10 ms, and
/// every cut (halt, pause, a start while sound plays) drops the device's queue but first fades out
/// over 10 ms from the sample being heard (the dropped queue's first 10 ms, ramped to 0), mixed
/// into what comes next. No sample step at a join is larger than the sound's own steps plus a
/// ramp step (full scale / 480 at 48 kHz).
///
/// Failures: a source that cannot be read further ends the sound (stats().ended); an output that
/// is unplugged or fails ends the sound with stats().lost set; the picture plays on its own clock
/// from then on.
///
/// Thread-safety: the control calls (start, halt, setPaused, setVolume, setMute, clock, stats) on
/// any thread but the haptic thread (they take a short mutex); step() on one thread: the audio
/// thread (startThread()) or a test's. Buffers are allocated by the constructor.

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "depthtouch/hal/audio_output.h"
#include "depthtouch/hal/audio_source.h"
#include "depthtouch/options/option_range.h"
#include "depthtouch/playback/master_clock.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/realtime_thread.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::playback {

/// \brief Settings of an AudioPlayer (the `play` options --volume, --mute).
struct AudioPlayerConfig {
    /// Largest volume, percent (mpv's --volume-max default): options::kVolume's, the one range
    /// of every volume setting.
    static constexpr double kMaxVolume = options::kVolume.max;
    double volume = 100.0; ///< Percent, 0..kMaxVolume.
    bool mute = false;
    /// Sound kept queued in the device, s (10 ms .. 1 s): the delay of pause, seek and volume.
    double queueSeconds = 0.1;
};

/// \brief Counters of the sound since the player was made. Plain values.
struct AudioStats {
    std::uint64_t framesWritten = 0; ///< Frames of sound (not silence) the device took.
    std::uint64_t silenceFrames = 0; ///< Silence written where the source had no sound.
    /// The device's (AudioOutput::underruns()) while the source had sound: running dry after
    /// its end is not one.
    std::uint64_t underruns = 0;
    double delaySeconds = 0.0; ///< The device's queue at the last turn, s.
    bool ended = false;        ///< The source has no more sound (until the next start()).
    std::string lost;          ///< Why the sound stopped for good; empty while it works.
};

/// See the file comment.
class AudioPlayer {
public:
    /// \brief Opens \a output for \a source's format. Both must outlive the player.
    /// \return the player (idle until start()). Errors: InvalidArgument (a config out of range),
    /// the output's open() error.
    static Result<std::unique_ptr<AudioPlayer>> create(hal::AudioSource &source,
                                                       hal::AudioOutput &output,
                                                       platform::Clock &clock,
                                                       const AudioPlayerConfig &config);
    /// Stops the audio thread and closes the output.
    ~AudioPlayer();
    AudioPlayer(const AudioPlayer &) = delete;
    AudioPlayer &operator=(const AudioPlayer &) = delete;

    /// \brief Starts the audio thread (platform::kAudioThread), which runs step() every quarter of
    /// the queue. \return Errc::OutOfResources when no thread could be started.
    [[nodiscard]] Result<void> startThread();

    /// \name Control
    ///@{
    /// Plays from media time \a seconds (see the file comment).
    void start(double seconds);
    /// Silences at once and waits for the next start().
    void halt();
    void setPaused(bool paused);
    /// \a percent clamped to 0..kMaxVolume.
    void setVolume(double percent);
    void setMute(bool mute);
    ///@}

    [[nodiscard]] MasterClock clock() const;
    [[nodiscard]] double volume() const; ///< %, as setVolume() left it.
    [[nodiscard]] bool muted() const;
    [[nodiscard]] AudioStats stats() const;

    /// \brief One turn of the audio thread: takes the commands and fills the device's queue up to
    /// queueSeconds. Never blocks.
    void step();

private:
    AudioPlayer(hal::AudioSource &source, hal::AudioOutput &output, platform::Clock &clock,
                const AudioPlayerConfig &config);
    /// Adds the device's underruns since the last call, unless the source had ended.
    void countUnderruns();
    /// Writes sound or silence until the queue holds \a queueFrames or the source ends.
    void fill(std::size_t delay);
    /// Writes \a frames of `block_` from `blockPos_` with the gain; \return the frames taken.
    std::size_t writeSound(std::size_t frames);
    /// Writes \a frames of silence on the timeline (the source's gap); \return the frames taken.
    std::size_t writeSilence(std::size_t frames);
    /// Writes \a frames of silence off the timeline (paused, a halt's fade-out).
    std::size_t writeZeros(std::size_t frames);
    /// Writes the first \a frames of `scaled_` with the pending fade-out mixed in and keeps them
    /// in `written_`; \return the frames taken (0 when lost).
    std::size_t writeOut(std::size_t frames);
    /// Takes the commands: halt, start, pause, resume. \return false when the output was lost.
    bool control(std::uint64_t startGen, std::uint64_t haltGen, double startAt, bool paused);
    /// Drops the device's queue, keeping its first 10 ms faded to 0 as the pending fade-out: the
    /// frames that follow the last one heard before the drop (AudioOutput::flush() says how many it
    /// dropped; a queue asked for first would be stale by what played until the drop).
    /// \return the frames dropped, as queued() counts them; none when the output was lost.
    std::optional<std::size_t> cut();
    /// Plays from media time \a seconds (the source seeks there), faded in.
    void begin(double seconds);
    /// \return the device's queue, frames: AudioOutput::delayFrames(), but never less than what
    /// this run wrote beyond what could have been heard in its time (a device that takes frames
    /// faster than real time does not run the clock ahead). Errors: the device's.
    [[nodiscard]] Result<std::size_t> queued();
    /// \return \a delay (frames the device says it holds), but never less than what this run
    /// wrote beyond what could have been heard in its time.
    [[nodiscard]] std::size_t atLeastTheRun(std::size_t delay) const;
    /// Copies up to \a frames of the sound that comes next (the source's block after what was
    /// written, at the present gain) into \a to, without taking them; 0 unless sound plays and
    /// follows on without a gap. For a fade-out longer than what the device has queued.
    [[nodiscard]] std::size_t nextSound(std::int16_t *to, std::size_t frames) const;
    void lose(const Error &error);
    /// Publishes the clock (\a mediaTime heard at \a at) and the counters; \a queued: the
    /// device's queue, s.
    void publish(bool running, double mediaTime, double queued, platform::TimePoint at);

    hal::AudioSource &source_;
    hal::AudioOutput &output_;
    platform::Clock &clock_;
    AudioPlayerConfig config_;
    hal::AudioFormat format_;
    std::size_t queueFrames_;

    // Commands (mutex_), written by the control calls, taken by step().
    mutable std::mutex mutex_;
    std::uint64_t startGen_ = 0;
    double startAt_ = 0.0;
    std::uint64_t haltGen_ = 0;
    bool paused_ = false;
    double targetGain_ = 1.0;
    MasterClock published_;
    AudioStats stats_;

    // The audio thread's own.
    enum class Mode : std::uint8_t { Idle, Playing, Paused, Ended, Lost };
    Mode mode_ = Mode::Idle;
    std::uint64_t startSeen_ = 0;
    std::uint64_t haltSeen_ = 0;
    bool pausedSeen_ = false;
    double gain_ = 1.0;                ///< Gain of the last frame written.
    double rampTarget_ = 1.0;          ///< The gain it moves to (targetGain_ as of this turn).
    double writtenEnd_ = 0.0;          ///< Media time after the last frame written, s.
    std::vector<std::int16_t> block_;  ///< The source's block being written.
    std::vector<std::int16_t> scaled_; ///< Its frames with the gain, as written.
    hal::PcmBlock have_{};             ///< What block_ holds.
    std::size_t blockPos_ = 0;         ///< Frames of block_ written.
    bool sourceEnded_ = false;
    double pausedAt_ = 0.0; ///< Paused: the media time heard at the pause, s.
    /// The last frames written, after the gain (a ring of the queue's size and a block): what the
    /// device has queued, for the fade-out of a cut.
    std::vector<std::int16_t> written_;
    std::uint64_t writtenFrames_ = 0;   ///< Frames ever put in written_.
    platform::TimePoint runStart_{};    ///< When the device was last emptied (cut()).
    std::uint64_t runFirstFrame_ = 0;   ///< writtenFrames_ then.
    std::vector<std::int16_t> fadeOut_; ///< The pending fade-out (10 ms at most).
    std::size_t fadeOutFrames_ = 0;     ///< Its length, frames.
    std::size_t fadeOutPos_ = 0;        ///< Frames of it written.
    std::uint64_t soundFrames_ = 0;
    std::uint64_t silenceFrames_ = 0;
    std::uint64_t underruns_ = 0;     ///< Counted (AudioStats::underruns).
    std::uint64_t underrunsSeen_ = 0; ///< The device's count at the last turn.
    std::optional<platform::RealtimeThread> thread_;
};

/// \return the gain of \a percent volume, muted or not: (percent / 100)³, 0 when muted.
double volumeGain(double percent, bool mute) noexcept;

} // namespace depthtouch::playback
