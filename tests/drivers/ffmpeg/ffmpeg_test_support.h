#pragma once
/// \file
/// \brief Helpers of the FFmpeg driver tests: a temporary directory, running the `ffmpeg` CLI to
/// make test media at run time, a fixture for the tests that need it, decoding a whole stream
/// through the HAL backends, and a live stream written into a FIFO.

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

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

/// \brief A fixture for the tests whose media the ffmpeg CLI makes at run time: each test skips
/// where the CLI does not run, and has a scratch folder of its own (tmp_).
class FfmpegCliTest : public ::testing::Test {
protected:
    /// \param prefix start of the scratch folder's name (TempDir).
    explicit FfmpegCliTest(const std::string &prefix) : tmp_(prefix) {}
    /// Skips the test without the ffmpeg CLI; fails it (fatally) without a scratch folder.
    void SetUp() override
    {
        if (!haveFfmpegCli())
            GTEST_SKIP() << "The ffmpeg command-line tool is not on PATH: no test media";
        ASSERT_FALSE(tmp_.dir().empty());
    }

    TempDir tmp_;
};

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

/// \brief A live stream on a FIFO: a thread of its own opens the FIFO for writing once a reader
/// has it open, writes the whole clip once, and once more each time sendAgain() asks, then keeps
/// the FIFO open and silent until stop() (or the destructor).
class LiveFifo {
public:
    /// Starts the writer of \a clip into the FIFO at \a path (made by the caller).
    LiveFifo(std::string path, std::vector<std::uint8_t> clip);
    ~LiveFifo();
    LiveFifo(const LiveFifo &) = delete;
    LiveFifo &operator=(const LiveFifo &) = delete;

    /// Asks the writer to send the clip once more.
    void sendAgain() { ++sends_; }
    /// Closes the FIFO's writing end and ends the writer.
    void stop();

private:
    void run();
    void writeClip(int fd) const;

    std::string path_;
    std::vector<std::uint8_t> clip_;
    std::atomic<int> sends_{1};
    std::atomic<bool> quit_{false};
    std::thread thread_; ///< Last: starts once the members it reads exist.
};

} // namespace depthtouch::ffmpegtest
