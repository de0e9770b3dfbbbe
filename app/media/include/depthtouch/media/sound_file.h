#pragma once
/// \file
/// \brief Writes sound made in memory (a built-in scene's soundtrack) as a WAV file, for the
/// encoder to take as its sound source (EncodeOptions::audioSource).
///
/// Thread-safety: reentrant.

#include <cstdint>
#include <string>
#include <vector>

#include "depthtouch/hal/audio_output.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::media {

/// \brief Writes \a samples (interleaved signed 16-bit PCM of \a format) to \a path as a WAV file
/// (libavformat's wav muxer).
/// \return Errors: InvalidArgument (a format outside hal::AudioOutput's ranges, or samples that
/// are not whole frames), Io (the file cannot be created or written).
Result<void> writeWavFile(const std::string &path, const std::vector<std::int16_t> &samples,
                          const hal::AudioFormat &format);

} // namespace depthtouch::media
