#pragma once
/// \file
/// \brief AudioOutputBase: the hal::AudioOutput contract in one place, for every backend.
///
/// A backend derives from AudioOutputBase and implements only the device steps (the protected
/// `...Device()` hooks); the public methods are `final` and do the contract around them, as
/// HapticDeviceBase and DisplayBase do (libcamera's queueRequest() → queueRequestDevice()):
/// - open(): Closed required (InvalidState), the format's rate and channels in range
///   (InvalidArgument), then openDevice(format); Open after, with the counts at zero.
/// - write(), delayFrames(), pause(), flush(), drain(): InvalidState when Closed, NoDevice when
///   Lost; a hook that returns NoDevice (unplugged) makes the state Lost. write() of 0 frames
///   returns 0 without the device; a null \a samples with frames > 0 is InvalidArgument; the
///   frames the device takes are counted (framesWritten()). pause() only calls the device when the
///   state changes. drain() is refused while Paused (a paused device never drains).
/// - close(): closeDevice() (any state but Closed), then Closed.
/// Thread-safety: as hal::AudioOutput; state(), framesPlayed() and underruns() read atomics.

#include <atomic>
#include <cstddef>
#include <cstdint>

#include "depthtouch/hal/audio_output.h"

namespace depthtouch::hal {

/// \brief The base of every audio output backend: owns the state and the contract (see the file
/// comment); the backend implements the hooks and publishes its counts with setPlayed() and
/// countUnderrun().
class AudioOutputBase : public AudioOutput {
public:
    ~AudioOutputBase() override = default;

    [[nodiscard]] State state() const noexcept final
    {
        return state_.load(std::memory_order_acquire);
    }
    [[nodiscard]] Result<void> open(const AudioFormat &format) final;
    [[nodiscard]] Result<std::size_t> write(const std::int16_t *samples, std::size_t frames) final;
    [[nodiscard]] Result<std::size_t> delayFrames() final;
    [[nodiscard]] std::size_t bufferFrames() const noexcept final
    {
        return state() == State::Closed ? 0 : bufferFramesDevice();
    }
    [[nodiscard]] std::uint64_t framesPlayed() const noexcept final
    {
        return played_.load(std::memory_order_relaxed);
    }
    [[nodiscard]] std::uint64_t underruns() const noexcept final
    {
        return underruns_.load(std::memory_order_relaxed);
    }
    [[nodiscard]] Result<void> pause(bool paused) final;
    [[nodiscard]] Result<std::size_t> flush() final;
    [[nodiscard]] Result<void> drain() final;
    void close() noexcept final;

    /// \return the format of the last open() (valid while not Closed).
    [[nodiscard]] const AudioFormat &format() const noexcept { return format_; }
    /// \return frames the device took since open().
    [[nodiscard]] std::uint64_t framesWritten() const noexcept { return written_; }

protected:
    AudioOutputBase() = default;

    /// \brief Opens the device for \a format (valid: checked by open()).
    /// \return Errors: NotSupported, NoDevice, Io; the state stays Closed.
    [[nodiscard]] virtual Result<void> openDevice(const AudioFormat &format) = 0;
    /// \brief Queues what fits of \a frames frames (\a samples non-null, frames > 0).
    /// \return the frames taken. Errors: NoDevice (Lost after), Io.
    [[nodiscard]] virtual Result<std::size_t> writeDevice(const std::int16_t *samples,
                                                          std::size_t frames) = 0;
    /// \return frames queued and not yet heard. Errors: NoDevice.
    [[nodiscard]] virtual Result<std::size_t> delayDevice() = 0;
    /// \return the buffer size, frames (called when not Closed).
    [[nodiscard]] virtual std::size_t bufferFramesDevice() const noexcept = 0;
    /// \brief Holds (\a paused) or releases the queue. Called only on a change. Errors: NoDevice.
    [[nodiscard]] virtual Result<void> pauseDevice(bool paused) = 0;
    /// \brief Drops the queue. \return the frames dropped (queued, not yet heard, at the drop).
    /// Errors: NoDevice.
    [[nodiscard]] virtual Result<std::size_t> flushDevice() = 0;
    /// \brief Plays out the queue (called Open). Errors: NoDevice.
    [[nodiscard]] virtual Result<void> drainDevice() = 0;
    /// \brief Closes the device (called in Open, Paused or Lost). noexcept.
    virtual void closeDevice() noexcept = 0;

    /// Publishes the frames played since open() (the backend's own count).
    void setPlayed(std::uint64_t frames) noexcept
    {
        played_.store(frames, std::memory_order_relaxed);
    }
    /// Counts one underrun.
    void countUnderrun() noexcept { underruns_.fetch_add(1, std::memory_order_relaxed); }

private:
    /// InvalidState when Closed, NoDevice when Lost.
    [[nodiscard]] Result<void> checkUsable() const noexcept;
    /// \return \a r, entering Lost when it is NoDevice.
    template <class T> [[nodiscard]] Result<T> noteLoss(Result<T> r) noexcept;

    std::atomic<State> state_{State::Closed};
    std::atomic<std::uint64_t> played_{0};
    std::atomic<std::uint64_t> underruns_{0};
    std::uint64_t written_ = 0;
    AudioFormat format_{};
};

} // namespace depthtouch::hal
