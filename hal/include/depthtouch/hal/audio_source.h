#pragma once
/// \file
/// \brief AudioSource: the decoded sound of an input, as the player's audio thread pulls it: blocks
/// of interleaved 16-bit PCM, each with its media time (docs/devices.md, "Sound output").
///
/// Timeline: media time 0 is the input's start, the zero of the video packets' Pts
/// (MediaSource), so a block's start is compared with a frame's PTS directly. Blocks come in
/// order; a gap between one block's end and the next one's start is sound the input does not
/// have (the player plays silence there), an overlap is repeated sound (the player drops it).
///
/// Thread-safety: thread-bound (the audio thread). Not real-time safe (file I/O, decoding). Never
/// called from the haptic thread. The header is C++17-clean.

#include <cstddef>
#include <cstdint>

#include "depthtouch/hal/audio_output.h"
#include "depthtouch/hal/media_source.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::hal {

/// The sample rates an AudioSource takes from a sound's header, Hz: 8 kHz (narrow-band telephony)
/// to 384 kHz (the highest of studio PCM). A stream outside is refused as bad audio (a damaged or
/// lying header): played as is it would be resampled by any ratio, with buffers sized by it (1 Hz
/// to 48 kHz took 3.95 GB for 8 channels).
inline constexpr int kMinSourceRate = 8000;
inline constexpr int kMaxSourceRate = 384000;

/// \brief What one AudioSource::read() gave.
struct PcmBlock {
    std::size_t frames = 0; ///< Frames written to the caller's buffer; 0 at the end of the sound.
    double start = 0.0;     ///< Media time of the first frame, s (see the file comment).
    /// With frames 0: not the end, a live input has no more sound yet (read again later).
    bool pending = false;
};

/// \brief A decoded audio stream.
class AudioSource {
public:
    virtual ~AudioSource() = default;

    /// \return the format of every block: the rate and channels an AudioOutput opens with.
    [[nodiscard]] virtual AudioFormat format() const noexcept = 0;

    /// \brief Decodes up to \a frames frames into \a samples (frames × channels interleaved).
    /// \return the block (frames 0: the sound has ended; it stays ended until seek()). Errors:
    /// InvalidArgument (\a samples null with frames > 0), Io (the input cannot be read: the sound
    /// ends there). A damaged packet is skipped, not an error.
    [[nodiscard]] virtual Result<PcmBlock> read(std::int16_t *samples, std::size_t frames) = 0;

    /// \brief Moves the read position: the next block starts at the first frame at or after media
    /// time \a seconds (sample-accurate; later when the sound starts later).
    /// \return Errors: NotSupported (the input cannot seek), Io.
    [[nodiscard]] virtual Result<void> seek(double seconds) = 0;
};

/// \brief Where a demuxer's thread hands the packets of a live input's audio stream
/// (MediaSource::deliverAudio()) for an AudioSource on the audio thread to decode.
class AudioPacketSink {
public:
    virtual ~AudioPacketSink() = default;
    /// \brief Takes a copy of \a packet (its data is the source's). Never blocks; what does not
    /// fit is dropped. Thread-safety: one pushing thread, beside the AudioSource's reader.
    virtual void push(const Packet &packet) noexcept = 0;
};

} // namespace depthtouch::hal
