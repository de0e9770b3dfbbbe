#include "depthtouch/drivers/ffmpeg/wav_audio_output.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "depthtouch/av/wav_file.h"
#include "depthtouch/platform/message_text.h"
#include "ffmpeg_common.h"

namespace depthtouch::drivers {

namespace {

constexpr const char *kDefaultPath = "depthtouch-audio.wav";
constexpr int kIoBufferBytes = 32 * 1024;

/// \return why \a err (an AVERROR, or errno \a sysErrno when set) failed, for a message.
std::string errorText(int err, int sysErrno)
{
    if (sysErrno == ETIMEDOUT)
        return "the FIFO's reader does not take the sound";
    if (sysErrno != 0)
        return std::strerror(sysErrno);
    char buf[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(err, buf, sizeof buf);
    return buf;
}

} // namespace

std::string wavOutputPath(std::string_view options, std::string_view device)
{
    const hal::OptionList list(options);
    std::string path(list.find("path").value_or(device));
    return path.empty() ? std::string(kDefaultPath) : path;
}

Result<std::unique_ptr<hal::AudioOutput>> WavAudioOutput::create(const hal::BackendConfig &cfg)
{
    auto s = parsePacedAudioSettings(cfg.options, PacedAudioBackend::Wav);
    if (!s)
        return unexpected(s.error());
    return std::unique_ptr<hal::AudioOutput>(std::make_unique<WavAudioOutput>(
        cfg.clockRef(), *s, wavOutputPath(cfg.options.text(), cfg.device)));
}

WavAudioOutput::WavAudioOutput(platform::Clock &clock, const PacedAudioSettings &settings,
                               std::string path)
    : PacedAudioOutput(clock, settings), path_(std::move(path))
{
}

WavAudioOutput::~WavAudioOutput()
{
    close();
}

void WavAudioOutput::fail(const char *what, const std::string &why)
{
    failed_ = true;
    if (lost_.empty())
        lost_ = std::string(what) + " " + platform::quotedText(path_, 120) + ": " + why;
}

void WavAudioOutput::freeIo() noexcept
{
    if (io_ == nullptr)
        return;
    av_freep(&io_->buffer);
    avio_context_free(&io_);
}

int WavAudioOutput::writeBytes(void *self, std::uint8_t *buf, int size) noexcept
{
    auto &w = *static_cast<WavAudioOutput *>(self);
    int done = 0;
    while (done < size) {
        const ssize_t n = ::write(w.fd_, buf + done, static_cast<std::size_t>(size - done));
        if (n > 0) {
            done += static_cast<int>(n);
            continue;
        }
        const int err = n < 0 ? errno : EIO;
        if (err == EINTR)
            continue;
        if (err == EAGAIN) { // a FIFO whose pipe is full: its reader gets a bounded wait
            pollfd p{w.fd_, POLLOUT, 0};
            const int r = ::poll(&p, 1, kFifoWaitMs);
            if (r > 0 || (r < 0 && errno == EINTR))
                continue;
            w.writeErrno_ = r == 0 ? ETIMEDOUT : errno;
            return AVERROR(EAGAIN);
        }
        w.writeErrno_ = err;
        return AVERROR(err);
    }
    return size;
}

std::int64_t WavAudioOutput::seekBytes(void *self, std::int64_t offset, int whence) noexcept
{
    const int fd = static_cast<WavAudioOutput *>(self)->fd_;
    if ((whence & AVSEEK_SIZE) != 0) {
        struct stat st {};
        return ::fstat(fd, &st) == 0 ? static_cast<std::int64_t>(st.st_size) : AVERROR(errno);
    }
    const off_t at = ::lseek(fd, static_cast<off_t>(offset), whence & ~AVSEEK_FORCE);
    return at < 0 ? AVERROR(errno) : static_cast<std::int64_t>(at);
}

Result<void> WavAudioOutput::openDevice(const hal::AudioFormat &format)
{
    ffmpeg::quietLibav();
    failed_ = false;
    writeErrno_ = 0;
    // Never blocks: a FIFO without a reader is refused (O_NONBLOCK: ENXIO), a file is made new.
    auto file = platform::OutputFile::open(path_);
    if (!file) {
        char why[160];
        fail("cannot open the WAV file", file.error().format(why, sizeof why));
        return unexpected(Errc::Io, "cannot open the WAV file");
    }
    file_ = std::move(*file);
    fd_ = ::fileno(file_.stream());
    const bool seekable = !file_.tempPath().empty(); // a FIFO or a device is streamed
    if (!seekable) {
        const int flags = ::fcntl(fd_, F_GETFL);
        if (flags >= 0)
            (void)::fcntl(fd_, F_SETFL, flags | O_NONBLOCK); // writes wait kFifoWaitMs at most
    }
    auto *buffer = static_cast<unsigned char *>(av_malloc(kIoBufferBytes));
    io_ = buffer == nullptr ? nullptr
                            : avio_alloc_context(buffer, kIoBufferBytes, 1, this, nullptr,
                                                 &WavAudioOutput::writeBytes,
                                                 seekable ? &WavAudioOutput::seekBytes : nullptr);
    if (io_ == nullptr)
        av_free(buffer);
    else
        io_->seekable = seekable ? AVIO_SEEKABLE_NORMAL : 0;
    const int err = io_ == nullptr
                        ? AVERROR(ENOMEM)
                        : av::openWavMuxer(out_, io_, nullptr, format.sampleRate, format.channels);
    if (err < 0) {
        fail("cannot write the WAV file", errorText(err, writeErrno_));
        freeIo();
        file_.abort();
        return unexpected(Errc::Io, "cannot create the WAV file");
    }
    kept_ = 0;
    return PacedAudioOutput::openDevice(format);
}

Result<void> WavAudioOutput::keep(const std::int16_t *samples, std::size_t frames)
{
    if (out_ == nullptr || failed_)
        return unexpected(Errc::InvalidState, "no WAV file");
    if (const int err = av::writeWavFrames(out_, samples, frames, format().channels, kept_);
        err < 0) {
        fail("cannot write the WAV file", errorText(err, writeErrno_));
        return unexpected(Errc::Io, "cannot write the WAV file");
    }
    kept_ += static_cast<std::int64_t>(frames);
    return ok();
}

void WavAudioOutput::closeDevice() noexcept
{
    (void)catchUp(); // what was heard by now; the rest of the queue never is
    if (out_ != nullptr) {
        const int err = av::closeWavFile(out_); // the RIFF sizes, then a flush
        if (err < 0 && !failed_)
            fail("cannot write the WAV file", errorText(err, writeErrno_));
    }
    freeIo();
    if (!file_.isOpen())
        return;
    if (failed_) {
        file_.abort(); // the temporary file removed: nothing cut under the name
        return;
    }
    if (auto c = file_.commit(); !c) { // synced, then renamed onto the name
        char why[160];
        fail("cannot finish the WAV file", c.error().format(why, sizeof why));
    }
}

} // namespace depthtouch::drivers
