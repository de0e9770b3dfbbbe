/// \file
/// \brief The ffmpeg source's open of a device or a FIFO is interruptible (issue 60, class 6):
/// /dev/ptmx (a device nobody writes) and a FIFO without a writer, opened under a 10-minute I/O
/// time-out, return Errc::Timeout once interrupt() is called from another thread, instead of
/// blocking in read(2) or open(2) where libavformat never asks its interrupt callback. The
/// device is opened by the source itself (one descriptor on it appears) before the interrupt.
/// Judged by the outcome; the waits are bounded polls against a hang. No media needed.

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <future>
#include <memory>
#include <string>
#include <system_error>
#include <thread>

#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"
#include "device_input.h"
#include "support/temp_dir.h"

namespace depthtouch::drivers {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

/// \return how many of this process's descriptors name \a path.
int descriptorsOn(const std::string &path)
{
    std::error_code ec;
    int n = 0;
    for (fs::directory_iterator it("/proc/self/fd", ec), end; !ec && it != end; it.increment(ec)) {
        std::error_code linkError;
        if (fs::read_symlink(it->path(), linkError).string() == path)
            ++n;
    }
    return n;
}

/// Opens \a path on an ffmpeg source with a 10-minute time-out on another thread, interrupts it
/// once the source holds a descriptor on \a path, and checks that the open ends with Timeout. The
/// thread is detached and owns the source: an open that does not end fails the test, not hangs it.
void expectOpenInterrupted(const std::string &path)
{
    hal::BackendConfig cfg;
    cfg.options = hal::OptionList("timeout_ms=600000");
    auto made = createMediaSource("ffmpeg", cfg);
    ASSERT_TRUE(made);
    const std::shared_ptr<hal::MediaSource> src(std::move(*made));
    const int before = descriptorsOn(path);
    auto task = std::make_shared<std::packaged_task<Result<void>()>>(
        [src, path] { return src->open(path.c_str()); });
    std::future<Result<void>> opening = task->get_future();
    std::thread([task] { (*task)(); }).detach();
    for (int i = 0; i < 2000 && descriptorsOn(path) == before; ++i)
        std::this_thread::sleep_for(5ms);
    EXPECT_GT(descriptorsOn(path), before) << path << ": the source never opened it";
    src->interrupt();
    ASSERT_EQ(opening.wait_for(60s), std::future_status::ready)
        << path << ": the open did not end at the interrupt (blocked in the kernel)";
    const Result<void> r = opening.get();
    ASSERT_FALSE(r) << path;
    EXPECT_EQ(r.error().code, Errc::Timeout) << path << ": " << r.error().what;
    src->close();
    EXPECT_EQ(descriptorsOn(path), before) << path << ": close() kept its descriptor";
}

TEST(FfmpegDeviceInputTest, anOpenOfADeviceNobodyWritesEndsAtTheInterrupt)
{
    if (::access("/dev/ptmx", R_OK) != 0)
        GTEST_SKIP() << "no /dev/ptmx here";
    expectOpenInterrupted("/dev/ptmx");
}

TEST(FfmpegDeviceInputTest, anOpenOfAFifoWithoutAWriterEndsAtTheInterrupt)
{
    testing::TempDir tmp("dt-device-input-");
    const std::string fifo = (tmp.dir() / "in.fifo").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    expectOpenInterrupted(fifo);
}

TEST(FfmpegDeviceInputTest, devicesAndFifosAreReadNonBlockingUnlessTheFormatOpensThem)
{
    using platform::PathKind;
    EXPECT_TRUE(ffmpeg::isDeviceInput(PathKind::Fifo, false));
    EXPECT_TRUE(ffmpeg::isDeviceInput(PathKind::CharDevice, false));
    EXPECT_FALSE(ffmpeg::isDeviceInput(PathKind::CharDevice, true)) << "video4linux2 opens its own";
    EXPECT_FALSE(ffmpeg::isDeviceInput(PathKind::Regular, false));
    EXPECT_FALSE(ffmpeg::isDeviceInput(PathKind::Missing, false));
}

} // namespace
} // namespace depthtouch::drivers
