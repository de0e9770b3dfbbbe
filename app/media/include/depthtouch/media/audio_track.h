#pragma once
/// \file
/// \brief The sender's sound: the first audio stream of a source carried into the
/// output beside color and depth, on the picture's timeline.
///
/// The audio is copied as it is when the output's container carries its codec (AAC, Opus, MP3,
/// AC-3, FLAC in MKV, ...: libavformat's avformat_query_codec()), else decoded, converted by
/// libswresample and coded as AAC (libavcodec's native encoder, 128 kbit/s per two channels) at
/// the source's rate and channel layout. Timeline: output time 0 is the picture's first frame;
/// for audio taken from the color source, the source's audio and video keep their relation (the
/// audio's PTS minus the color stream's start time), for another file its audio starts with the
/// picture. Audio before the picture's start is left out, and so is audio after the picture's end
/// (finish()). Thread-safety: one thread (the encode job's).

#include <memory>
#include <string>

#include "depthtouch/media/encoder.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::media {

/// \brief One audio stream of an output, fed from a source file.
class AudioTrack {
public:
    ~AudioTrack();
    AudioTrack(const AudioTrack &) = delete;
    AudioTrack &operator=(const AudioTrack &) = delete;

    /// \brief Opens the first audio stream of \a source (a file or URL FFmpeg reads) and adds its
    /// stream to \a muxer. \a pictureSource: whether \a source is also the color input (its video
    /// stream's start is output time 0). \pre muxer not started.
    /// \return the track; nullptr when \a source opens but has no audio stream;
    ///         Errc::InvalidArgument when it does not open as media or the container refuses the
    ///         stream, Errc::NotSupported when its codec cannot be decoded or AAC cannot be
    ///         encoded. A read error later ends the sound early (description() says so).
    static Result<std::unique_ptr<AudioTrack>> open(const std::string &source, bool pictureSource,
                                                    Muxer &muxer);

    /// \brief Writes the source's audio up to output time \a seconds (call after each picture).
    /// \return Errc::Io on a read or write error (a damaged audio packet is skipped).
    Result<void> writeUntil(double seconds);

    /// \brief Writes the audio up to \a endSeconds (the picture's end), drops the rest and drains
    /// the encoder. \pre the video encoders flushed, the muxer not finished.
    Result<void> finish(double endSeconds);

    /// \return "aac 48000 Hz 2 ch, copied" or "pcm_s16le 44100 Hz 1 ch, coded as aac".
    [[nodiscard]] const std::string &description() const noexcept;
    /// \return audio bytes written so far.
    [[nodiscard]] long long bytes() const noexcept;

    struct Impl;

private:
    AudioTrack();
    std::unique_ptr<Impl> impl_;
};

} // namespace depthtouch::media
