// The `synthetic:` and `v4l2:` frame sources of the depthtouch executable (app/cli/
// source_providers.h, over media/camera_source.h and synthetic/synthetic_source.h): the spec
// grammar, the synthetic head through makeSourceProviders() on the headless EGL display (color and
// depth of the same frames, nearness tags), a camera source on the mock RGB-D camera, and
// `depthtouch encode --color synthetic:head --depth synthetic:head` end to end, read back with
// libavformat. The GL cases skip when there is no headless display.
#include <sys/wait.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/media/readback.h"
#include "depthtouch/drivers/backends.h"
#include "depthtouch/media/camera_source.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/synthetic/synthetic_source.h"
#include "source_providers.h"
#include "support/temp_dir.h"

namespace depthtouch::cli {
namespace {

using media::openCameraSource;
using media::parseCameraSpec;
using media::PixelFormat;
using media::shareCamera;
using synthetic::parseSyntheticSpec;
using synthetic::SyntheticSourceFactory;

media::SourceOptions optionsFor(const std::string &title)
{
    media::SourceOptions o;
    o.streamTitle = title;
    return o;
}

/// Mean of the Gray8 samples in the rectangle [x0, x1) × [y0, y1).
double meanGray8(const media::Image &img, int x0, int y0, int x1, int y1)
{
    double sum = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            sum += img.row(y)[x];
    return sum / static_cast<double>((x1 - x0) * (y1 - y0));
}

// ---------------------------------------------------------------------------------------------
// Grammar (no GL)

/// Expects \a spec to be \a scene at \a width × \a height pixels, \a fps frames per second and
/// \a frames frames, the depth stream when \a depth (else color).
void expectSpec(const synthetic::SyntheticSpec &spec, const std::string &scene, int width,
                int height, double fps, long long frames, bool depth)
{
    EXPECT_EQ(spec.scene, scene);
    EXPECT_EQ(spec.width, width);
    EXPECT_EQ(spec.height, height);
    EXPECT_DOUBLE_EQ(spec.fps, fps);
    EXPECT_EQ(spec.frames, frames);
    EXPECT_EQ(spec.depth, depth);
}

TEST(SyntheticSpecTest, defaultsComeFromTheSourceOptions)
{
    // GIVEN a bare scene name and the options encode passes for its depth input at 25 fps
    media::SourceOptions o = optionsFor("depth");
    o.fps = 25.0;
    // WHEN parsed
    auto spec = parseSyntheticSpec("head", o);
    // THEN 720×486, the options' rate, 4 s of frames, the depth stream
    ASSERT_TRUE(spec) << spec.error().what;
    expectSpec(*spec, "head", 720, 486, 25.0, 100, true);

    // A color title, videoSize and loop: that size, endless
    media::SourceOptions c = optionsFor("color");
    c.videoSize = "320x240";
    c.loop = true;
    auto looped = parseSyntheticSpec("spheres", c);
    ASSERT_TRUE(looped);
    EXPECT_FALSE(looped->depth);
    EXPECT_EQ(looped->width, 320);
    EXPECT_EQ(looped->height, 240);
    EXPECT_EQ(looped->frames, 0);
}

TEST(SyntheticSpecTest, optionsAfterTheNameWin)
{
    media::SourceOptions o = optionsFor("color");
    o.videoSize = "320x240";
    auto spec = parseSyntheticSpec("cut,size=160x120,fps=12.5,frames=7,stream=depth", o);
    ASSERT_TRUE(spec) << spec.error().what;
    expectSpec(*spec, "cut", 160, 120, 12.5, 7, true);
    auto endless = parseSyntheticSpec("head,frames=0", o);
    ASSERT_TRUE(endless);
    EXPECT_EQ(endless->frames, 0);
}

TEST(SyntheticSpecTest, badSpecsAreInvalidArguments)
{
    const media::SourceOptions o;
    // An unknown scene names the scenes there are.
    auto unknown = parseSyntheticSpec("hed", o);
    ASSERT_FALSE(unknown);
    EXPECT_EQ(unknown.error().code, Errc::InvalidArgument);
    EXPECT_NE(std::string(unknown.error().what).find("head, spheres, cut"), std::string::npos)
        << unknown.error().what;
    EXPECT_NE(std::string(unknown.error().what).find("'hed'"), std::string::npos);
    for (const char *bad :
         {"", "head,colour=1", "head,size=160", "head,size=8x8", "head,size=0x120", "head,fps=0",
          "head,fps=abc", "head,frames=-1", "head,frames=1.5", "head,stream=left"}) {
        auto r = parseSyntheticSpec(bad, o);
        ASSERT_FALSE(r) << bad;
        EXPECT_EQ(r.error().code, Errc::InvalidArgument) << bad;
    }
    media::SourceOptions raw;
    raw.format = "rawvideo";
    EXPECT_FALSE(parseSyntheticSpec("head", raw));
}

TEST(CameraSpecTest, deviceOptionsAndBackendOptionsAreSplit)
{
    media::SourceOptions o = optionsFor("depth");
    o.fps = 15.0;
    auto spec =
        parseCameraSpec("/dev/video4,color=/dev/video6,size=640x480,pool=6,stream=color", o);
    ASSERT_TRUE(spec) << spec.error().what;
    EXPECT_EQ(spec->device, "/dev/video4");
    EXPECT_EQ(spec->backendOptions, "color=/dev/video6,pool=6");
    EXPECT_EQ(spec->width, 640);
    EXPECT_EQ(spec->height, 480);
    EXPECT_DOUBLE_EQ(spec->fps, 0.0);
    EXPECT_DOUBLE_EQ(spec->preferredFps, 15.0);
    EXPECT_FALSE(spec->depth);
    EXPECT_FALSE(parseCameraSpec(",size=640x480", o));
    EXPECT_FALSE(parseCameraSpec("/dev/video0,size=big", o));
    EXPECT_FALSE(parseCameraSpec("/dev/video0,fps=-3", o));
}

TEST(CameraSourceTest, missingDeviceIsNoDevice)
{
    auto providers = makeSourceProviders();
    ASSERT_TRUE(providers.v4l2);
    auto s = media::openFrameSource("v4l2:/dev/dt-no-such-video", optionsFor("depth"), providers);
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error().code, Errc::NoDevice);
    EXPECT_NE(std::string(s.error().what).find("/dev/dt-no-such-video"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// The camera source on the mock RGB-D camera (sphere 0.7 m in front of a wall at 1.2 m)

TEST(CameraSourceTest, colorAndDepthSourcesShareOneCameraAndItsCaptures)
{
    // GIVEN the mock camera shared by a color and a depth source, 160×120 asked
    auto camera = drivers::createDepthCamera("mock", hal::BackendConfig{});
    ASSERT_TRUE(camera);
    media::SourceOptions o;
    auto spec = parseCameraSpec("mock,size=160x120", o);
    ASSERT_TRUE(spec);
    auto share = shareCamera(std::move(*camera), *spec);
    ASSERT_TRUE(share) << share.error().what;
    auto color = openCameraSource(*share, false);
    auto depth = openCameraSource(*share, true);
    ASSERT_TRUE(color && depth);
    EXPECT_EQ((*color)->info().width, 160);
    EXPECT_EQ((*depth)->info().height, 120);
    EXPECT_EQ((*color)->info().nativeFormat, PixelFormat::Rgb24);
    EXPECT_EQ((*depth)->info().nativeFormat, PixelFormat::Gray16); // Z16: metric millimetres

    // WHEN pairs are read as encode reads them (color, then depth)
    double lastPts = -1.0;
    for (int i = 0; i < 4; ++i) {
        auto c = (*color)->next(PixelFormat::Rgb24);
        auto d = (*depth)->next(PixelFormat::Gray16);
        ASSERT_TRUE(c) << c.error().what;
        ASSERT_TRUE(d) << d.error().what;
        // THEN each pair comes from one capture: the same PTS, rising, starting at 0
        EXPECT_DOUBLE_EQ(c->pts, d->pts);
        if (i == 0) {
            EXPECT_DOUBLE_EQ(c->pts, 0.0);
        }
        EXPECT_GT(c->pts, lastPts);
        lastPts = c->pts;
        // and the depth is the scene's: the wall at 1.2 m, the sphere nearer
        const std::uint16_t corner = d->image.sample16(2, 2);
        EXPECT_NEAR(corner, 1200, 120);
        std::uint16_t nearest = 65535;
        for (int y = 0; y < 120; ++y)
            for (int x = 0; x < 160; ++x)
                if (const std::uint16_t v = d->image.sample16(x, y); v > 0)
                    nearest = std::min(nearest, v);
        EXPECT_LT(nearest, 700);
        EXPECT_EQ(c->image.width, 160);
        EXPECT_EQ(c->image.format, PixelFormat::Rgb24);
    }
    // A layout and size other than the camera's are converted.
    auto small = (*depth)->next(PixelFormat::Gray8, 80, 60);
    ASSERT_TRUE(small);
    EXPECT_EQ(small->image.width, 80);
    EXPECT_EQ(small->image.format, PixelFormat::Gray8);
}

TEST(CameraSourceTest, noModeOfTheSizeAskedIsNotSupported)
{
    auto camera = drivers::createDepthCamera("mock", hal::BackendConfig{});
    ASSERT_TRUE(camera);
    auto spec = parseCameraSpec("mock,size=100x100", media::SourceOptions{});
    ASSERT_TRUE(spec);
    auto share = shareCamera(std::move(*camera), *spec);
    ASSERT_FALSE(share);
    EXPECT_EQ(share.error().code, Errc::NotSupported);
}

// ---------------------------------------------------------------------------------------------
// Synthetic scenes on the headless display

/// Opens \a spec for \a title through \a providers; skips the test without GL.
#define OPEN_OR_SKIP(var, providers, spec, title)                                                  \
    auto var##Result = media::openFrameSource(spec, optionsFor(title), providers);                 \
    if (!var##Result && var##Result.error().code == Errc::NotSupported)                            \
        GTEST_SKIP() << "No OpenGL ES: " << var##Result.error().what;                              \
    ASSERT_TRUE(var##Result) << var##Result.error().what;                                          \
    std::unique_ptr<media::FrameSource> var = std::move(*var##Result)

TEST(SyntheticSourceTest, colorAndDepthShowTheSameFramesWithNearnessTags)
{
    // GIVEN the head's color and depth sources opened through one set of providers
    const auto providers = makeSourceProviders();
    ASSERT_TRUE(providers.synthetic);
    const std::string spec = "synthetic:head,size=160x120,frames=6";
    OPEN_OR_SKIP(color, providers, spec, "color");
    OPEN_OR_SKIP(depth, providers, spec, "depth");

    // THEN they describe the clip, and the depth carries the planes and the mapping
    EXPECT_EQ(color->info().width, 160);
    EXPECT_EQ(color->info().height, 120);
    EXPECT_DOUBLE_EQ(color->info().fps, 30.0);
    EXPECT_EQ(color->info().frameCount, 6);
    EXPECT_EQ(color->info().nativeFormat, PixelFormat::Rgb24);
    EXPECT_EQ(depth->info().nativeFormat, PixelFormat::Gray8); // nearness, not metric
    ASSERT_NE(depth->info().tag("depth_near"), nullptr);
    ASSERT_NE(depth->info().tag("depth_far"), nullptr);
    ASSERT_NE(depth->info().tag("depth_mapping"), nullptr);
    EXPECT_EQ(*depth->info().tag("depth_near"), "0.5");
    EXPECT_EQ(*depth->info().tag("depth_far"), "1.5");
    EXPECT_EQ(*depth->info().tag("depth_mapping"), "inverse_z");

    // AND an independent renderer (other providers) draws the same frames, so sharing changes
    // nothing but the cost
    const auto others = makeSourceProviders();
    OPEN_OR_SKIP(lone, others, spec, "color");
    OPEN_OR_SKIP(loneDepth, others, spec, "depth");

    // WHEN every frame is read (color, then depth, as encode does)
    std::vector<media::Image> nearness;
    for (int i = 0; i < 6; ++i) {
        auto c = color->next(PixelFormat::Rgb24);
        auto d = depth->next(PixelFormat::Gray8);
        auto l = lone->next(PixelFormat::Rgb24);
        auto ld = loneDepth->next(PixelFormat::Gray8);
        ASSERT_TRUE(c && d && l && ld);
        EXPECT_DOUBLE_EQ(c->pts, i / 30.0);
        EXPECT_DOUBLE_EQ(d->pts, c->pts);
        EXPECT_EQ(c->image.data, l->image.data) << "frame " << i;
        EXPECT_EQ(d->image.data, ld->image.data) << "frame " << i;
        nearness.push_back(d->image);
    }
    // THEN the clip ends after its 6 frames, on both streams
    auto end = color->next(PixelFormat::Rgb24);
    ASSERT_FALSE(end);
    EXPECT_EQ(end.error().code, Errc::EndOfStream);
    auto endDepth = depth->next(PixelFormat::Gray8);
    ASSERT_FALSE(endDepth);
    EXPECT_EQ(endDepth.error().code, Errc::EndOfStream);

    // AND the head (centre) is nearer than the curtain (corners), and it moves
    const media::Image &first = nearness.front();
    EXPECT_GT(meanGray8(first, 70, 40, 90, 70), meanGray8(first, 0, 0, 12, 12) + 40.0);
    EXPECT_NE(nearness.front().data, nearness.back().data);
}

TEST(SyntheticSourceTest, colorAndDepthOfOneSceneDrawEachFrameOnce)
{
    // GIVEN the color and depth sources of one scene from one factory
    SyntheticSourceFactory factory(
        [] { return drivers::createDisplay("headless", hal::BackendConfig{}); });
    auto color = factory.open("head,size=64x48,frames=6", optionsFor("color"));
    if (!color && color.error().code == Errc::NotSupported)
        GTEST_SKIP() << "No OpenGL ES: " << color.error().what;
    ASSERT_TRUE(color) << color.error().what;
    auto depth = factory.open("head,size=64x48,frames=6", optionsFor("depth"));
    ASSERT_TRUE(depth);
    // WHEN all six pairs are read, color then depth, as encode does
    for (int i = 0; i < 6; ++i)
        ASSERT_TRUE((*color)->next(PixelFormat::Rgb24) && (*depth)->next(PixelFormat::Gray8));
    // THEN six frames were drawn, not twelve (the frame drawn ahead is never drawn again)
    EXPECT_EQ(factory.framesDrawn(), 6u);

    // AND a scene of another size gets a renderer of its own
    auto other = factory.open("head,size=32x24,frames=2", optionsFor("color"));
    ASSERT_TRUE(other);
    ASSERT_TRUE((*other)->next(PixelFormat::Rgb24));
    EXPECT_EQ((*other)->info().width, 32);
    EXPECT_GE(factory.framesDrawn(), 7u);
}

TEST(SyntheticSourceTest, sixteenBitNearnessAndOtherLayoutsOnRequest)
{
    const auto providers = makeSourceProviders();
    OPEN_OR_SKIP(depth, providers, "synthetic:spheres,size=64x48,frames=2,stream=depth", "");
    OPEN_OR_SKIP(color, providers, "synthetic:spheres,size=64x48,frames=2", "");
    auto d16 = depth->next(PixelFormat::Gray16);
    auto c = color->next(PixelFormat::Gray8, 32, 24);
    ASSERT_TRUE(d16 && c);
    EXPECT_EQ(d16->image.format, PixelFormat::Gray16);
    EXPECT_EQ(d16->image.width, 64);
    std::uint16_t lo = 65535;
    std::uint16_t hi = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            lo = std::min(lo, d16->image.sample16(x, y));
            hi = std::max(hi, d16->image.sample16(x, y));
        }
    EXPECT_GT(hi - lo, 1000); // spheres nearer than the wall, in more than 8 bits of levels
    EXPECT_EQ(c->image.format, PixelFormat::Gray8);
    EXPECT_EQ(c->image.width, 32);
    EXPECT_EQ(c->image.height, 24);
}

// ---------------------------------------------------------------------------------------------
// depthtouch encode end to end

struct CommandRun {
    int exitCode = -1;
    std::string err;
};

CommandRun runDepthtouch(const std::string &args, const testing::TempDir &tmp)
{
    const std::string errFile = tmp.path("stderr.txt");
    const std::string cmd = std::string(DT_DEPTHTOUCH_EXE) + " " + args + " >" +
                            tmp.path("stdout.txt") + " 2>" + errFile;
    const int status = std::system(cmd.c_str());
    CommandRun r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(errFile);
    r.err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return r;
}

bool haveGl()
{
    auto d = drivers::createDisplay("headless", hal::BackendConfig{});
    return d && (*d)->open(hal::DisplayConfig{64, 64, 0.0, {}});
}

TEST(EncodeSyntheticTest, headColorAndDepthMakeAPlayableFileWithDepthTags)
{
    if (!haveGl())
        GTEST_SKIP() << "No headless OpenGL ES display";
    // GIVEN the head, 8 frames of 160×120, as color and depth
    testing::TempDir tmp("dt-synthetic-encode-");
    const std::string out = tmp.path("head.mkv");
    const std::string spec = "synthetic:head,size=160x120,frames=8";
    // WHEN encoded
    const CommandRun run = runDepthtouch(
        "encode --color " + spec + " --depth " + spec + " -o " + out + " --preset ultrafast", tmp);
    ASSERT_EQ(run.exitCode, 0) << run.err;

    // THEN the file has a color and a depth stream of 8 frames each
    const media::test::FileReadback file = media::test::readBack(out);
    ASSERT_TRUE(file.ok) << file.error;
    ASSERT_EQ(file.streams.size(), 2u);
    EXPECT_EQ(file.streams[0].tags.at("title"), "color");
    EXPECT_EQ(file.streams[1].tags.at("title"), "depth");
    EXPECT_EQ(file.streams[0].frames.size(), 8u);
    EXPECT_EQ(file.streams[1].frames.size(), 8u);
    EXPECT_EQ(file.decodeErrors, 0);
    EXPECT_EQ(file.streams[1].width, 160);
    // AND the scene's planes with the inverse-Z mapping
    EXPECT_EQ(file.tags.at("depth_near"), "0.5");
    EXPECT_EQ(file.tags.at("depth_far"), "1.5");
    EXPECT_EQ(file.tags.at("depth_mapping"), "inverse_z");
    EXPECT_EQ(file.streams[1].tags.at("depth_mapping"), "inverse_z");
    // AND the decoded depth is the head in front of the curtain, not a flat picture
    const media::Image &d = file.streams[1].frames[0];
    ASSERT_EQ(d.format, PixelFormat::Gray8);
    EXPECT_GT(meanGray8(d, 70, 40, 90, 70), meanGray8(d, 0, 0, 12, 12) + 40.0);
}

TEST(EncodeSyntheticTest, unknownSceneIsBadInputWithoutAnOutputFile)
{
    testing::TempDir tmp("dt-synthetic-encode-");
    const std::string out = tmp.path("bad.mkv");
    const CommandRun run =
        runDepthtouch("encode --color synthetic:heads --depth synthetic:heads -o " + out, tmp);
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_FALSE(std::filesystem::exists(out));
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_NE(run.err.find("head, spheres, cut"), std::string::npos) << run.err;
}

TEST(EncodeSyntheticTest, noGlIsOneClearErrorLine)
{
    // GIVEN an EGL loader that finds no vendor library (libglvnd reads this variable)
    testing::TempDir tmp("dt-synthetic-encode-");
    const std::string out = tmp.path("nogl.mkv");
    ASSERT_EQ(setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/dev/null", 1), 0);
    const CommandRun noGl = runDepthtouch(
        "encode --color synthetic:head,frames=1 --depth synthetic:head,frames=1 -o " + out, tmp);
    unsetenv("__EGL_VENDOR_LIBRARY_FILENAMES");
    // THEN exit 2, no file, one line naming the display problem
    EXPECT_EQ(noGl.exitCode, 2) << noGl.err;
    EXPECT_FALSE(std::filesystem::exists(out));
    EXPECT_EQ(std::count(noGl.err.begin(), noGl.err.end(), '\n'), 1) << noGl.err;
    EXPECT_NE(noGl.err.find("No OpenGL ES display"), std::string::npos) << noGl.err;
}

} // namespace
} // namespace depthtouch::cli
