#pragma once
/// \file
/// \brief Test support of the sender's tests (encode_test.cpp, encode_holes_test.cpp,
/// encode_faults_test.cpp): frames made on demand (colour, 8-bit nearness, 16-bit metric depth), a
/// FrameSource over them and the fixture with a scratch folder and fast encode options.

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "depthtouch/media/encode_job.h"
#include "depthtouch/media/frame_source.h"
#include "support/temp_dir.h"

namespace depthtouch::media::test {

constexpr int kW = 64;
constexpr int kH = 48;

/// Smooth color that x264 codes well: gradients plus a moving square.
inline Image makeColor(int i, int w = kW, int h = kH)
{
    Image img = Image::make(w, h, PixelFormat::Rgb24);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::uint8_t *p = img.row(y) + 3 * x;
            const bool square = x >= 10 + i && x < 26 + i && y >= 12 && y < 28;
            p[0] = static_cast<std::uint8_t>(square ? 230 : 40 + 2 * x);
            p[1] = static_cast<std::uint8_t>(square ? 220 : 60 + 3 * y);
            p[2] = static_cast<std::uint8_t>(100 + i * 4);
        }
    return img;
}

/// 8-bit nearness with texture and a step edge, different in every frame.
inline Image makeNearness8(int i, int w = kW, int h = kH)
{
    Image img = Image::make(w, h, PixelFormat::Gray8);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            img.row(y)[x] =
                static_cast<std::uint8_t>((x > w / 2 ? 200 : 20) + ((x * 7 + y * 13 + i * 5) % 41));
    return img;
}

/// 16-bit metric depth (mm) between 800 and 2600, a ramp plus a step.
inline Image makeMetric(int i, int w = kW, int h = kH)
{
    Image img = Image::make(w, h, PixelFormat::Gray16);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            img.setSample16(
                x, y, static_cast<std::uint16_t>((x > w / 2 ? 2000 : 900) + 9 * y + 3 * x + i));
    return img;
}

/// A FrameSource over images made on demand (endless when count < 0).
class TestSource final : public FrameSource {
public:
    TestSource(std::function<Image(int)> make, int count, double fps, PixelFormat native)
        : make_(std::move(make)), count_(count)
    {
        const Image first = make_(0);
        info_.width = first.width;
        info_.height = first.height;
        info_.fps = fps;
        info_.nativeFormat = native;
        info_.frameCount = count < 0 ? 0 : count;
        info_.description = "test";
    }
    [[nodiscard]] const SourceInfo &info() const noexcept override { return info_; }
    Result<SourceFrame> next(PixelFormat format, int, int) override
    {
        if (count_ >= 0 && index_ >= count_)
            return unexpected(Errc::EndOfStream, "end");
        SourceFrame f;
        f.image = make_(index_);
        EXPECT_EQ(f.image.format, format) << "the pipeline asked for another layout";
        f.pts = index_ / info_.fps;
        ++index_;
        return f;
    }

private:
    std::function<Image(int)> make_;
    int count_;
    int index_ = 0;
    SourceInfo info_;
};

/// makeColor() frames: \a count of them (-1: endless) at \a fps.
inline TestSource colorSource(int count, double fps = 30.0)
{
    return TestSource([](int i) { return makeColor(i); }, count, fps, PixelFormat::Rgb24);
}

/// makeNearness8() frames: \a count of them (-1: endless) at \a fps.
inline TestSource nearness8Source(int count, double fps = 30.0)
{
    return TestSource([](int i) { return makeNearness8(i); }, count, fps, PixelFormat::Gray8);
}

/// makeMetric() frames: \a count of them (-1: endless) at \a fps.
inline TestSource metricSource(int count, double fps = 30.0)
{
    return TestSource([](int i) { return makeMetric(i); }, count, fps, PixelFormat::Gray16);
}

class EncodeTest : public depthtouch::testing::TempDirTest {
protected:
    EncodeTest() : TempDirTest("dt-encode-test-") {}
    [[nodiscard]] std::vector<std::string> files() const
    {
        std::vector<std::string> out;
        for (const auto &e : std::filesystem::directory_iterator(tmp_.dir()))
            out.push_back(e.path().filename().string());
        return out;
    }
    static EncodeOptions fastOptions(const std::string &output)
    {
        EncodeOptions o;
        o.output = output;
        o.preset = "ultrafast";
        o.threads = 1;
        return o;
    }
};

} // namespace depthtouch::media::test
