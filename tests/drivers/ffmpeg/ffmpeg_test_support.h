#pragma once
/// \file
/// \brief Helpers of the FFmpeg driver tests: a temporary directory, running the `ffmpeg` CLI to
/// make test media at run time, and decoding a whole stream through the HAL backends.

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/hal/media_source.h"
#include "depthtouch/hal/video_decoder.h"
#include "support/temp_dir.h"

namespace depthtouch::ffmpegtest {

using TempDir = testing::TempDir;

/// True when the ffmpeg command-line tool runs.
bool haveFfmpegCli();

/// Runs `ffmpeg -nostdin -v error -y ARGS`. \return true on exit status 0.
bool ffmpeg(const std::string &args);

/// Every frame of one stream, decoded by the `ffmpeg` backends.
struct Decoded {
    hal::StreamInfo stream;
    std::vector<std::vector<std::uint8_t>> frames; ///< Tightly packed pixels.
    std::vector<hal::Pts> pts;
    std::vector<bool> corrupt;
    hal::DecoderStats stats;
    int packets = 0;
    Errc readEnd = Errc::EndOfStream; ///< How reading stopped.
};

/// Decodes the stream of kind \a kind (or the only stream) of \a url; bounded loops (a stuck
/// decoder fails the test instead of hanging). \a mutate may damage packet payloads;
/// \a decoderOptions are the ffmpeg decoder's (e.g. "hwaccel=none"); \a sourceClock the media
/// source's clock (nullptr: the steady clock).
Decoded decodeAll(const std::string &url, hal::StreamKind kind,
                  const std::string &sourceOptions = "",
                  bool (*mutate)(int index, std::vector<std::uint8_t> &bytes) = nullptr,
                  const std::string &decoderOptions = "", platform::Clock *sourceClock = nullptr);

/// \return the bytes of a file ("" when unreadable).
std::vector<std::uint8_t> readBytes(const std::string &path);

} // namespace depthtouch::ffmpegtest
