#pragma once
/// \file
/// \brief AudioOutput: a sound device that plays interleaved 16-bit PCM and says how far it got,
/// beside the display and the haptic device (docs/devices.md, "Sound output").
///
/// State machine:
/// \verbatim
///   Closed --open(format)--> Open <--pause(true)/pause(false)--> Paused
///     ^                       |  (device unplugged)                 |
///     |                       v                                     |
///     +------close()------- Lost <------(device unplugged)----------+
/// \endverbatim
/// A call that is not allowed in the current state returns Errc::InvalidState and has no effect.
/// In Lost every call but close() and state() returns Errc::NoDevice; the caller closes and opens
/// again. Backends derive from AudioOutputBase (audio_output_base.h), which does the state and
/// argument checks of this contract and counts what was written.
///
/// Time model, as ALSA's (snd_pcm_delay(), snd_pcm_recover()) and mpv's ao_alsa use it: write()
/// queues frames in the device's buffer without blocking (it takes what fits); the device plays
/// them at the sample rate on its own clock; delayFrames() is the time, in frames, until a frame
/// written now is heard. A device that runs out of frames while Open has an underrun: it is counted
/// (underruns()), and playback resumes at the next write() (the device recovers by itself). Paused
/// holds the queue where it is (no frame is played, none is lost, no underrun).
///
/// Units: frames (one sample per channel), sample rate in hertz; time on the backend clock
/// (BackendConfig::clock).
/// Thread-safety: thread-bound: every method from the one audio thread, except state(),
/// framesPlayed() and underruns(), which any thread may read. Never called from the real-time
/// haptic thread. The header is C++17-clean.

#include <cstddef>
#include <cstdint>
#include <string>

#include "depthtouch/platform/result.h"

namespace depthtouch::hal {

/// \brief What open() plays: interleaved signed 16-bit samples in host byte order.
struct AudioFormat {
    int sampleRate = 48000; ///< Frames per second, hertz: 8000 .. 192000.
    int channels = 2;       ///< Samples per frame: 1 .. 8 (FFmpeg's channel order).
};

/// \brief The lowest and highest sample rate and the most channels open() takes.
inline constexpr int kMinAudioRate = 8000;
inline constexpr int kMaxAudioRate = 192000;
inline constexpr int kMaxAudioChannels = 8;

/// \brief An audio output device.
class AudioOutput {
public:
    enum class State : std::uint8_t { Closed, Open, Paused, Lost };

    virtual ~AudioOutput() = default;

    /// \return the current state. Any thread.
    [[nodiscard]] virtual State state() const noexcept = 0;

    /// \brief Opens the device for \a format; it starts Open with an empty queue.
    /// \return Errors: InvalidState (not Closed), InvalidArgument (rate or channels outside the
    /// ranges above), NotSupported (the device refuses the format), NoDevice (no device), Io.
    [[nodiscard]] virtual Result<void> open(const AudioFormat &format) = 0;

    /// \brief Queues up to \a frames frames of \a samples (frames × channels interleaved samples)
    /// without blocking, in Open or Paused.
    /// \return the frames taken (0 .. frames: what fits in the buffer). Errors: InvalidState
    /// (Closed), InvalidArgument (\a samples null with frames > 0), NoDevice (unplugged: the state
    /// becomes Lost), Io (a file backend could not write: the sound is lost).
    [[nodiscard]] virtual Result<std::size_t> write(const std::int16_t *samples,
                                                    std::size_t frames) = 0;

    /// \return the frames queued and not yet heard (the presentation delay of a frame written now,
    /// in frames). Errors: InvalidState (Closed), NoDevice (Lost).
    [[nodiscard]] virtual Result<std::size_t> delayFrames() = 0;

    /// \return the size of the device's buffer, frames (what write() can take at most); 0 when
    /// Closed.
    [[nodiscard]] virtual std::size_t bufferFrames() const noexcept = 0;

    /// \return frames played (heard) since open(). Any thread.
    [[nodiscard]] virtual std::uint64_t framesPlayed() const noexcept = 0;

    /// \return underruns since open() (the device ran out of frames while Open). Any thread.
    [[nodiscard]] virtual std::uint64_t underruns() const noexcept = 0;

    /// \brief Pauses (Open → Paused) or resumes (Paused → Open) the device, keeping its queue.
    /// Pausing a paused device or resuming a playing one does nothing.
    /// \return Errors: InvalidState (Closed), NoDevice (Lost).
    [[nodiscard]] virtual Result<void> pause(bool paused) = 0;

    /// \brief Drops the queued frames at once (a seek): delayFrames() becomes 0.
    /// \return the frames dropped: those queued and not yet heard at the moment of the drop, so
    /// that the caller knows the last frame heard without asking delayFrames() first (the device
    /// plays on between the two calls). Errors: InvalidState (Closed), NoDevice (Lost).
    [[nodiscard]] virtual Result<std::size_t> flush() = 0;

    /// \brief Waits on the backend clock until the queued frames are heard (the end of a stream),
    /// in Open. \return Errors: InvalidState (Closed or Paused: a paused device never drains),
    /// NoDevice (Lost).
    [[nodiscard]] virtual Result<void> drain() = 0;

    /// \brief Drops the queue and closes the device (any state; Closed after).
    virtual void close() noexcept = 0;

    /// \brief Why a file output lost what it was given since it was made (it could not be
    /// opened, a write failed, or finishing it at close() did), e.g. "cannot write 'a.wav': No
    /// space left on device": the file is then not under its name. The player reports it as lost
    /// output (exit 1). Empty for a device, or when nothing was lost. Read it after close(), on
    /// the thread that closed the output.
    [[nodiscard]] virtual std::string lostOutput() const { return {}; }
};

/// \return "Closed", "Open", "Paused" or "Lost" (static string; hal/src/state_names.cpp).
const char *toString(AudioOutput::State state) noexcept;

} // namespace depthtouch::hal
