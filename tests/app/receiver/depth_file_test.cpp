// receiver::DepthFile: a file's depth video read frame by frame for `touch`, on the ffmpeg
// backends.
#include "depthtouch/receiver/depth_file.h"

#include <string>

#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"
#include "test_media.h"
#include "test_support.h"

namespace depthtouch::receiver {
namespace {

using receivertest::Clip;
using receivertest::TempDir;

/// A DepthFile on the ffmpeg media source and decoder.
DepthFile onFfmpeg(double fps)
{
    auto source = drivers::createMediaSource("ffmpeg", hal::BackendConfig{});
    auto decoder = drivers::createVideoDecoder("ffmpeg", hal::BackendConfig{});
    EXPECT_TRUE(source && decoder);
    return DepthFile(source ? std::move(*source) : nullptr, decoder ? std::move(*decoder) : nullptr,
                     fps);
}

TEST(DepthFileTest, readsTheDepthStreamOfAColorAndDepthFileFrameByFrame)
{
    // GIVEN the standard layout (color first, then lossless gray depth), 12 frames at 30 fps
    TempDir tmp;
    const std::string path = tmp.path("std.mkv");
    ASSERT_EQ(receivertest::writeClip(path, Clip::standard(64, 48, 12)), "");
    DepthFile file = onFfmpeg(30.0);
    std::string error;
    // WHEN it is opened and its frames read in order
    ASSERT_TRUE(file.open(path, std::nullopt, DepthFile::Metric{}, error)) << error;
    EXPECT_EQ(file.frameCount(), 12u);
    for (std::size_t i = 0; i < 12; ++i) {
        auto f = file.frame(i);
        ASSERT_TRUE(f) << i;
        // THEN each is the depth stream's frame, not the color's: its pattern sample for sample,
        // 8-bit, 64x48, at i/30 s
        EXPECT_EQ(f->width, 64);
        EXPECT_EQ(f->height, 48);
        EXPECT_EQ(f->format, scene::SampleFormat::Gray8);
        EXPECT_NEAR(f->pts, static_cast<double>(i) / 30.0, 1e-3);
        for (const auto &[x, y] : {std::pair{0, 0}, std::pair{31, 17}, std::pair{63, 47}})
            EXPECT_EQ(
                f->data[static_cast<std::size_t>(y) * f->strideBytes + static_cast<std::size_t>(x)],
                receivertest::depthPattern(x, y, static_cast<int>(i)))
                << "frame " << i << " at " << x << "," << y;
    }
    // AND a frame four behind the last is refused, not read from freed memory
    auto old = file.frame(2);
    ASSERT_FALSE(old);
    EXPECT_EQ(old.error().code, Errc::InvalidArgument);
    // AND no reading note: the file says it is nearness
    EXPECT_EQ(file.readingNote(), "");
}

TEST(DepthFileTest, refusesWithOneLineWhatItCannotRead)
{
    TempDir tmp;
    std::string error;
    // GIVEN no backends  THEN open fails and says so
    DepthFile none(nullptr, nullptr, 30.0);
    EXPECT_FALSE(none.open(tmp.path("x.mkv"), std::nullopt, DepthFile::Metric{}, error));
    EXPECT_NE(error.find("no media source"), std::string::npos) << error;
    // GIVEN a missing file  THEN the message names it
    DepthFile missing = onFfmpeg(30.0);
    EXPECT_FALSE(missing.open(tmp.path("none.mkv"), std::nullopt, DepthFile::Metric{}, error));
    EXPECT_NE(error.find("none.mkv"), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    // GIVEN a directory  THEN it is refused before anything waits on it
    DepthFile dir = onFfmpeg(30.0);
    EXPECT_FALSE(dir.open(tmp.path(""), std::nullopt, DepthFile::Metric{}, error));
    EXPECT_NE(error.find("give a file"), std::string::npos) << error;
}

} // namespace
} // namespace depthtouch::receiver
