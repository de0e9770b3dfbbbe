/// \file
/// \brief The sender (app/media) against hostile outputs and sources: an output path
/// that is not a regular file is never replaced, sizes and rates outside what H.264 encodes are
/// refused before any frame is read, an image sequence with a gap is followed across it, a silent
/// FIFO source gives up in its time.

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include <sys/stat.h>

#include <gtest/gtest.h>

#include "depthtouch/media/encode_job.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/image_io.h"
#include "encode_sources.h"
#include "support/temp_dir.h"

namespace depthtouch::media {
namespace {

using test::colorSource;
using test::nearness8Source;

class EncodeFaultsTest : public testing::TempDirTest {
protected:
    static EncodeOptions options(const std::string &output)
    {
        EncodeOptions o;
        o.output = output;
        o.preset = "ultrafast";
        o.container = Container::Matroska;
        return o;
    }
    static bool isKind(const std::string &p, mode_t kind)
    {
        struct stat st {};
        return ::stat(p.c_str(), &st) == 0 && (st.st_mode & S_IFMT) == kind;
    }
};

TEST_F(EncodeFaultsTest, onlyARegularFileOrANewPathIsReplaced)
{
    // GIVEN outputs that are a directory and a FIFO without a reader
    ASSERT_EQ(::mkdir(path("dir").c_str(), 0700), 0);
    ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0600), 0);
    for (const char *name : {"dir", "fifo"}) {
        auto color = colorSource(3);
        auto depth = nearness8Source(3);
        // WHEN encoding THEN each is refused as bad input
        auto s = encodeStreams(color, depth, options(path(name)));
        ASSERT_FALSE(s) << name;
        EXPECT_EQ(s.error().code, Errc::InvalidArgument) << name;
    }
    // AND both are still what they were (once: the temporary file was renamed over them)
    EXPECT_TRUE(isKind(path("dir"), S_IFDIR));
    EXPECT_TRUE(isKind(path("fifo"), S_IFIFO));
    // AND a character device is written in place
    auto color = colorSource(3);
    auto depth = nearness8Source(3);
    auto s = encodeStreams(color, depth, options("/dev/null"));
    ASSERT_TRUE(s) << s.error().what;
    EXPECT_TRUE(isKind("/dev/null", S_IFCHR));
    // AND a write that fails is lost output (Io), the device left as it is
    auto color2 = colorSource(3);
    auto depth2 = nearness8Source(3);
    auto full = encodeStreams(color2, depth2, options("/dev/full"));
    ASSERT_FALSE(full);
    EXPECT_EQ(full.error().code, Errc::Io);
    EXPECT_TRUE(isKind("/dev/full", S_IFCHR));
}

TEST_F(EncodeFaultsTest, ratesAndSizesOutsideWhatH264EncodesAreRefusedAtOnce)
{
    // GIVEN a color source at 1e-9 frames/s (once: a duration of -9223372036.855 s)
    auto slow = colorSource(3, 1e-9);
    auto depth = nearness8Source(3);
    auto s = encodeStreams(slow, depth, options(path("out.mkv")));
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error().code, Errc::InvalidArgument);
    // AND --size 16384x16384 (once: 8 s and 3.9 GB before failing), checked without a frame
    EncodeOptions o = options(path("out.mkv"));
    o.width = o.height = 16384;
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_FALSE(o.validate());
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(1));
    o.width = 8192;
    o.height = 4368;
    EXPECT_FALSE(o.validate());
    o.height = 4352;
    EXPECT_TRUE(o.validate());
    EXPECT_FALSE(isEncodableSize(0, 48));
    EXPECT_TRUE(isEncodableSize(64, 48));
    EXPECT_FALSE(std::filesystem::exists(path("out.mkv")));
}

TEST_F(EncodeFaultsTest, anImageSequenceWithAGapIsFollowedAcrossIt)
{
    // GIVEN frames 0-4 and 10-14 of a printf-pattern sequence (once: 5 were read, silently)
    for (const int i : {0, 1, 2, 3, 4, 10, 11, 12, 13, 14}) {
        Image img = Image::make(test::kW, test::kH, PixelFormat::Gray8);
        std::fill(img.data.begin(), img.data.end(), static_cast<std::uint8_t>(10 * i));
        char name[32];
        std::snprintf(name, sizeof name, "f-%03d.png", i);
        ASSERT_TRUE(writePng(path(name), img));
    }
    SourceOptions so;
    so.fps = 10.0;
    auto src = openFfmpegFrameSource(path("f-%03d.png"), so);
    ASSERT_TRUE(src) << src.error().what;
    EXPECT_EQ((*src)->info().frameCount, 10);
    // WHEN read to the end
    int n = 0;
    for (;;) {
        auto f = (*src)->next(PixelFormat::Gray8);
        if (!f) {
            EXPECT_EQ(f.error().code, Errc::EndOfStream) << f.error().what;
            break;
        }
        // THEN all 10 come, in order, at consecutive times
        const int number = n < 5 ? n : n + 5;
        EXPECT_EQ(f->image.data[0], 10 * number) << n;
        EXPECT_NEAR(f->pts, n / 10.0, 1e-9) << n;
        ++n;
    }
    EXPECT_EQ(n, 10);
}

TEST_F(EncodeFaultsTest, aFifoSourceWithoutAWriterGivesUpInItsTime)
{
    // GIVEN a FIFO nobody writes and a 300 ms I/O timeout
    ASSERT_EQ(::mkfifo(path("in").c_str(), 0600), 0);
    SourceOptions so;
    so.ioTimeoutMs = 300;
    const auto t0 = std::chrono::steady_clock::now();
    // WHEN opened THEN it fails with Timeout instead of blocking in open(2)
    auto src = openFfmpegFrameSource(path("in"), so);
    ASSERT_FALSE(src);
    EXPECT_EQ(src.error().code, Errc::Timeout);
    // It waited for the writer as long as it was told (less the millisecond the wait rounds down),
    // and gave up well before the 10 s default (the bound tells the option from the default; it is
    // no speed goal).
    const auto waited = std::chrono::steady_clock::now() - t0;
    EXPECT_GE(waited, std::chrono::milliseconds(299));
    EXPECT_LT(waited, std::chrono::seconds(10));
}

} // namespace
} // namespace depthtouch::media
