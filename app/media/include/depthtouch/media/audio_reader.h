#pragma once
/// \file
/// \brief AudioReader: the receiver's sound, a hal::AudioSource that decodes the first audio stream
/// of a file with libavformat and libavcodec and converts it with libswresample to interleaved
/// signed 16-bit PCM (docs/playing.md, "Sound").
///
/// The input is opened a second time beside the player's MediaSource (a demuxer of its own that
/// reads only the audio stream), so only inputs that can be read twice have sound: files and
/// seekable URLs (Playback asks for it only when its MediaSource can seek). Format: the stream's
/// own rate and channel layout (up to 8 channels, FFmpeg's order); a rate of 192..384 kHz is
/// resampled to 48 kHz, more channels are down-mixed to stereo. A rate outside
/// hal::kMinSourceRate..kMaxSourceRate (8..384 kHz), in the header or in a decoded frame, is bad
/// audio: refused (open(), fromPackets()) or the end of the sound (read()). Frames are converted
/// 16 384 samples at a time, so that the converted sound held stays bounded (6 MiB at most)
/// whatever a frame's length. Timeline: media time 0 is the
/// input's start (AVFormatContext::start_time), as the video packets' Pts of the ffmpeg
/// MediaSource. Decoded frames without a timestamp follow the previous one, and so do frames
/// within 2 ms of its end (a container's rounded timestamps: MKV's are in milliseconds).
///
/// A live input cannot be opened twice: fromPackets() decodes the packets its one demuxer delivers
/// instead.
///
/// Thread-safety: thread-bound (the audio thread); open() and fromPackets() on any thread; the
/// packet sink's push() on the demuxer's thread.

#include <memory>
#include <string>

#include "depthtouch/hal/audio_source.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::media {

/// See the file comment.
class AudioReader final : public hal::AudioSource {
public:
    ~AudioReader() override;
    AudioReader(const AudioReader &) = delete;
    AudioReader &operator=(const AudioReader &) = delete;

    /// \brief Opens the first audio stream of \a url (a file or URL FFmpeg reads).
    /// \return the reader; nullptr when \a url opens but has no audio stream. Errors:
    /// InvalidArgument (not readable as media, or a sample rate outside 8..384 kHz), NotSupported
    /// (no decoder for the codec), OutOfResources.
    static Result<std::unique_ptr<AudioReader>> open(const std::string &url);

    /// \brief A reader of a live input's sound: it decodes the packets the demuxer's thread hands
    /// to packetSink() (MediaSource::deliverAudio(), receiver::Receiver::setAudioSink()), in
    /// order; read() says PcmBlock::pending while none has come, and seek() is NotSupported.
    /// Media time: the packets' Pts. \return the reader. Errors: NotSupported (no decoder for
    /// \a stream's codec, or it refuses the stream), InvalidArgument (a sample rate outside
    /// 8..384 kHz), OutOfResources.
    static Result<std::unique_ptr<AudioReader>> fromPackets(const hal::AudioStreamInfo &stream);
    /// \return fromPackets()'s queue (about 10 s of packets; the oldest dropped when full),
    /// shared with the demuxer's thread; nullptr for a reader of a file.
    [[nodiscard]] std::shared_ptr<hal::AudioPacketSink> packetSink() const;

    [[nodiscard]] hal::AudioFormat format() const noexcept override;
    [[nodiscard]] Result<hal::PcmBlock> read(std::int16_t *samples, std::size_t frames) override;
    [[nodiscard]] Result<void> seek(double seconds) override;

    /// \return e.g. "aac 48000 Hz 2 ch" (the stream as coded).
    [[nodiscard]] const std::string &description() const noexcept;

    struct Impl;

private:
    AudioReader();
    std::unique_ptr<Impl> impl_;
};

} // namespace depthtouch::media
