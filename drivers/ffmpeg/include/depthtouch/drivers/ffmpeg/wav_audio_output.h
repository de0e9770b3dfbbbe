#pragma once
/// \file
/// \brief WavAudioOutput (backend `wav`): an audio output that writes what it plays into a WAV
/// file (libavformat's wav muxer, PCM s16le, bit-exact header), keeping time like a sound card
/// (drivers::PacedAudioOutput: the file holds every frame as it is heard, in order, and
/// framesPlayed()/delayFrames() say when; frames dropped by flush() or still queued at close() are
/// not in it, as a speaker would not have played them). For tests, for hearing joins (seek, pause)
/// as a listener would, and for measuring A/V sync by analysing the file against the presented
/// frames' times.
///
/// Device: BackendConfig::device, or option `path=FILE` (default `depthtouch-audio.wav`), written
/// as every output of the player is (platform::OutputFile): a regular file or a new path under a
/// temporary name beside it (`FILE.tmp.PID`), renamed onto FILE at close() only when complete (its
/// RIFF sizes written); a character device or a FIFO with a reader in place (streamed: sizes
/// 0xFFFFFFFF). Nothing at open() blocks: a FIFO without a reader is refused at once (ENXIO), and a
/// FIFO's reader that takes nothing for kFifoWaitMs fails the write. The command line checks the
/// path before playing (audioOutputFilePath(), platform::checkOutputPath()). Options: `buffer` as
/// the `null` backend.
///
/// Errors: open() Io when the file cannot be made or opened; write() Io when a write fails (the
/// sound is lost: the caller reports it). Every failure is also kept for lostOutput(): the
/// temporary file is removed, nothing is left under FILE, and the player exits 1.
/// Thread-safety: as hal::AudioOutput.

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "depthtouch/drivers/common/paced_audio_output.h"
#include "depthtouch/hal/backends.h"
#include "depthtouch/platform/file_access.h"

struct AVFormatContext;
struct AVIOContext;

namespace depthtouch::drivers {

/// \return the file the `wav` backend writes with options \a options and device \a device: its
/// `path=`, else \a device, else `depthtouch-audio.wav`.
std::string wavOutputPath(std::string_view options, std::string_view device);

class WavAudioOutput final : public PacedAudioOutput {
public:
    /// The longest a write waits for a FIFO's reader to take bytes, ms (its pipe is full: about
    /// 0.34 s of 48 kHz stereo behind): a reader that stopped reading fails the output instead of
    /// holding the audio thread, so stop still ends the player at once.
    static constexpr int kFifoWaitMs = 50;

    /// Backend factory. Errors: InvalidArgument (options).
    static Result<std::unique_ptr<hal::AudioOutput>> create(const hal::BackendConfig &cfg);

    WavAudioOutput(platform::Clock &clock, const PacedAudioSettings &settings, std::string path);
    ~WavAudioOutput() override;

    /// \return the first loss since the output was made, e.g. "cannot write the WAV file 'a.wav':
    /// No space left on device"; empty when none (see hal::AudioOutput::lostOutput()).
    [[nodiscard]] std::string lostOutput() const override { return lost_; }

protected:
    [[nodiscard]] Result<void> openDevice(const hal::AudioFormat &format) override;
    void closeDevice() noexcept override;
    [[nodiscard]] Result<void> keep(const std::int16_t *samples, std::size_t frames) override;

private:
    /// AVIOContext callbacks on fd_: every byte written (bounded waits on a FIFO), and a seek of
    /// the temporary file (AVSEEK_SIZE: its size). \return bytes, offset, or an AVERROR.
    static int writeBytes(void *self, std::uint8_t *buf, int size) noexcept;
    static std::int64_t seekBytes(void *self, std::int64_t offset, int whence) noexcept;

    /// Marks this open's file failed and keeps "\a what 'path': \a why" as the loss (the first).
    void fail(const char *what, const std::string &why);
    /// Frees the muxer's AVIOContext (the file stays open).
    void freeIo() noexcept;

    std::string path_;
    platform::OutputFile file_; ///< This open's file (its temporary name while written).
    AVIOContext *io_ = nullptr;
    AVFormatContext *out_ = nullptr;
    int fd_ = -1;           ///< file_'s descriptor.
    int writeErrno_ = 0;    ///< errno of the last failed write (ETIMEDOUT: a FIFO's reader).
    bool failed_ = false;   ///< This open's file is lost: removed at close(), not renamed.
    std::int64_t kept_ = 0; ///< Frames in the file.
    std::string lost_;      ///< See lostOutput().
};

} // namespace depthtouch::drivers
