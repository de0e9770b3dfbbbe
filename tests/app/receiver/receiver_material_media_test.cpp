// The material track in real files made by the ffmpeg CLI (libx264rgb, qp 0: H.264 4:4:4 RGB that
// decodes as gbrp): found by title (MKV) and by MP4 handler name, decoded to Rgb24 bit-exact.
// Skips (exit 77) without the ffmpeg CLI.
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_media.h"

namespace depthtouch::receivertest {
namespace {

constexpr int kWidth = 64;
constexpr int kHeight = 48;
constexpr int kFrames = 10;
const char *const kSource = "testsrc=size=64x48:rate=25:duration=0.4";

bool haveFfmpeg()
{
    return std::system("command -v ffmpeg >/dev/null 2>&1") == 0;
}

int run(const std::string &cmd)
{
    return std::system(("ffmpeg -nostdin -hide_banner -v error -y " + cmd).c_str());
}

/// Color (yuv420p H.264), depth (gray H.264) and material (libx264rgb qp 0) into \a path, titled
/// with \a tag ("title" or "handler_name").
int writeMaterialClip(const std::string &path, const std::string &tag)
{
    const std::string src = std::string("-f lavfi -i ") + kSource;
    return run(src + " " + src + " " + src + " -map 0 -map 1 -map 2" +
               " -c:v:0 libx264 -preset ultrafast -pix_fmt:v:0 yuv420p" +
               " -c:v:1 libx264 -preset ultrafast -pix_fmt:v:1 gray" +
               " -c:v:2 libx264rgb -preset ultrafast -qp:v:2 0 -pix_fmt:v:2 rgb24" +
               " -metadata:s:v:0 " + tag + "=color -metadata:s:v:1 " + tag + "=depth" +
               " -metadata:s:v:2 " + tag + "=material '" + path + "'");
}

std::vector<std::uint8_t> readAll(const std::string &path)
{
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void checkMaterialFile(const std::string &path, const char *reason,
                       const std::vector<std::uint8_t> &reference)
{
    auto r = openFfmpeg(path);
    ASSERT_TRUE(r) << r.error().what;
    const receiver::ReceiverInfo &info = (*r)->info();
    ASSERT_TRUE(info.hasMaterial) << path;
    EXPECT_STREQ(info.roles.materialReason, reason);
    EXPECT_EQ(info.mode, receiver::ReceiverMode::ColorAndDepth);
    const std::size_t frameBytes = static_cast<std::size_t>(kWidth) * kHeight * 3;
    int count = 0;
    for (;; ++count) {
        receiver::PairedFrame f;
        auto n = (*r)->next(f);
        ASSERT_TRUE(n) << n.error().what;
        if (!*n)
            break;
        ASSERT_TRUE(f.material) << count;
        const hal::ImageView &m = f.material->image;
        ASSERT_EQ(m.format, hal::PixelFormat::Rgb24);
        ASSERT_EQ(m.width, kWidth);
        ASSERT_EQ(m.height, kHeight);
        EXPECT_EQ(f.material->pts, f.depth->pts);
        // THEN gbrp → rgb24 is bit-exact: the codes are the source's RGB bytes
        const auto k = static_cast<std::size_t>(count);
        ASSERT_GE(reference.size(), (k + 1) * frameBytes);
        const std::uint8_t *want = reference.data() + k * frameBytes;
        int diff = 0;
        for (int y = 0; y < kHeight; ++y)
            diff += std::memcmp(m.row(0, y), want + static_cast<std::size_t>(y) * kWidth * 3,
                                static_cast<std::size_t>(kWidth) * 3) != 0
                        ? 1
                        : 0;
        EXPECT_EQ(diff, 0) << "frame " << count << ": rows differ";
    }
    EXPECT_EQ(count, kFrames);
    const auto s = (*r)->stats();
    EXPECT_EQ(s.materialFrames, static_cast<std::uint64_t>(kFrames));
    EXPECT_EQ(s.materialHeld, 0u);
    EXPECT_EQ(s.materialMissing, 0u);
}

TEST(ReceiverMaterialMediaTest, gbrpMaterialTrackIsFoundAndDecodedBitExact)
{
    if (!haveFfmpeg())
        GTEST_SKIP() << "no ffmpeg CLI on PATH";
    TempDir tmp("dt-material-");
    const std::string ref = tmp.path("ref.rgb");
    ASSERT_EQ(
        run(std::string("-f lavfi -i ") + kSource + " -pix_fmt rgb24 -f rawvideo '" + ref + "'"),
        0);
    const auto reference = readAll(ref);
    ASSERT_EQ(reference.size(), static_cast<std::size_t>(kWidth) * kHeight * 3 * kFrames);

    // GIVEN an MKV with the material stream titled `material`
    const std::string mkv = tmp.path("clip.mkv");
    ASSERT_EQ(writeMaterialClip(mkv, "title"), 0);
    checkMaterialFile(mkv, "title", reference);
    // AND an MP4 naming it by handler name
    const std::string mp4 = tmp.path("clip.mp4");
    ASSERT_EQ(writeMaterialClip(mp4, "handler_name"), 0);
    checkMaterialFile(mp4, "MP4 handler name", reference);
}

} // namespace
} // namespace depthtouch::receivertest
