/// \file
/// \brief Sound made in memory written as a WAV file: see sound_file.h.

#include "depthtouch/media/sound_file.h"

#include "depthtouch/av/wav_file.h"
#include "media_libav.h"

namespace depthtouch::media {

Result<void> writeWavFile(const std::string &path, const std::vector<std::int16_t> &samples,
                          const hal::AudioFormat &format)
{
    if (format.sampleRate < hal::kMinAudioRate || format.sampleRate > hal::kMaxAudioRate ||
        format.channels < 1 || format.channels > hal::kMaxAudioChannels ||
        samples.size() % static_cast<std::size_t>(format.channels) != 0)
        return unexpected(Errc::InvalidArgument, "Not a sound format a WAV file is written in");
    detail::quietFfmpegLog();
    AVFormatContext *out = nullptr;
    if (av::openWavFile(out, path.c_str(), format.sampleRate, format.channels) < 0)
        return unexpected(Errc::Io, "Cannot create the WAV file");
    const std::size_t frames = samples.size() / static_cast<std::size_t>(format.channels);
    const int written =
        frames == 0 ? 0 : av::writeWavFrames(out, samples.data(), frames, format.channels, 0);
    const int closed = av::closeWavFile(out);
    if (written < 0 || closed < 0)
        return unexpected(Errc::Io, "Cannot write the WAV file (disk full?)");
    return ok();
}

} // namespace depthtouch::media
