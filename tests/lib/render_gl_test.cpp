/// \file
/// \brief libdepthtouch's render API (depthtouch/render_gl.h; label gl): on a GLES 3 context of the
/// EGL surfaceless platform (Mesa llvmpipe without a GPU) the test makes a framebuffer object, the
/// example of docs/embedding.md (render_gl_example.c) plays a one-frame mock clip with the
/// simulated hand and draws it there on the frame-ready callback, and the picture read back matches
/// the snapshot `depthtouch play` writes of the same frame (mean absolute difference under 2 of
/// 255). Also every call's errors. No judgement by the wall clock.

#include <EGL/egl.h>
#include <GLES3/gl3.h>
#include <sys/wait.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/render/egl_test_context.h"
#include "depthtouch/client.h"
#include "depthtouch/media/image_io.h"
#include "depthtouch/render_gl.h"
#include "lib/render_gl_example.h"
#include "support/temp_dir.h"

namespace {

using depthtouch::testing::TempDir;

constexpr int kWidth = 320; ///< The output size of both players (--size), pixels.
constexpr int kHeight = 120;
/// A clip of one frame, colour and depth (drivers/mock: the same picture in both runs).
constexpr const char *kClip = "mock://clip?frames=1&fps=30";

/// The options both players share: mock source and decoder, no sound, the simulated hand.
const char *const kOptions[] = {"source",         "mock",         "decoder", "mock",
                                "no-audio",       "yes",          "size",    "320x120",
                                "haptic-options", "intent=press", nullptr};

/// A framebuffer object with an RGBA8 colour renderbuffer, in the current context.
class Fbo {
public:
    Fbo(int width, int height)
    {
        glGenFramebuffers(1, &fbo_);
        glGenRenderbuffers(1, &color_);
        glBindRenderbuffer(GL_RENDERBUFFER, color_);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_);
        glClearColor(1.0f, 0.0f, 1.0f, 1.0f); // magenta: a picture not drawn shows
        glClear(GL_COLOR_BUFFER_BIT);
    }
    ~Fbo()
    {
        glDeleteFramebuffers(1, &fbo_);
        glDeleteRenderbuffers(1, &color_);
    }
    Fbo(const Fbo &) = delete;
    Fbo &operator=(const Fbo &) = delete;

    [[nodiscard]] GLuint name() const { return fbo_; }
    [[nodiscard]] bool complete() const
    {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
        return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    }
    /// \return its pixels as RGB, top row first (as a PNG).
    [[nodiscard]] std::vector<std::uint8_t> readRgb(int width, int height) const
    {
        std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width * height * 4));
        glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
        std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width * height * 3));
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                for (int c = 0; c < 3; ++c)
                    rgb[static_cast<std::size_t>(((height - 1 - y) * width + x) * 3 + c)] =
                        rgba[static_cast<std::size_t>((y * width + x) * 4 + c)];
        return rgb;
    }

private:
    GLuint fbo_ = 0;
    GLuint color_ = 0;
};

/// Runs `depthtouch play` on kClip with kOptions (and --haptic sim) on the headless display,
/// a snapshot of every frame into \a dir. \return its exit code.
int playWithSnapshot(const std::string &dir)
{
    std::string cmd = std::string(DT_DEPTHTOUCH_EXE) + " play --display headless --haptic sim";
    for (int i = 0; kOptions[i] != nullptr; i += 2) {
        cmd += std::string(" --") + kOptions[i]; // a flag's "yes" is the flag alone
        if (std::string(kOptions[i + 1]) != "yes")
            cmd += std::string(" ") + kOptions[i + 1];
    }
    cmd += " --snapshot-every 1 --snapshot-dir '" + dir + "' '" + kClip + "' >/dev/null 2>&1";
    const int rc = std::system(cmd.c_str());
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

/// \return the mean absolute difference of \a a and \a b, of 255.
double meanAbsoluteDifference(const std::vector<std::uint8_t> &a,
                              const std::vector<std::uint8_t> &b)
{
    double sum = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
        sum += std::abs(static_cast<int>(a[i]) - static_cast<int>(b[i]));
    return a.empty() ? 255.0 : sum / static_cast<double>(a.size());
}

TEST(RenderGlTest, drawsIntoTheHostsFramebufferWhatPlaysSnapshotShows)
{
    DT_REQUIRE_GLES_CONTEXT(gl);
    TempDir tmp("dt-render-gl-test-");
    ASSERT_EQ(playWithSnapshot(tmp.dir().string()), 0) << "depthtouch play failed";
    auto snapshot = depthtouch::media::readImage(tmp.path("frame-000000.png"),
                                                 depthtouch::media::PixelFormat::Rgb24);
    ASSERT_TRUE(snapshot) << snapshot.error().what;
    ASSERT_EQ(snapshot->width, kWidth);
    ASSERT_EQ(snapshot->height, kHeight);
    std::vector<std::uint8_t> expected;
    for (int y = 0; y < kHeight; ++y)
        expected.insert(expected.end(), snapshot->row(y), snapshot->row(y) + kWidth * 3);

    // The snapshot is a picture (the stereo view and the on-screen display), not a black frame.
    ASSERT_GT(meanAbsoluteDifference(expected, std::vector<std::uint8_t>(expected.size(), 0)),
              10.0);

    Fbo fbo(kWidth, kHeight);
    ASSERT_TRUE(fbo.complete());
    const int callbacks = dt_example_render(kClip, kOptions, fbo.name(), kWidth, kHeight, 1);
    ASSERT_GE(callbacks, 1) << dt_error_string(callbacks);
    const std::vector<std::uint8_t> drawn = fbo.readRgb(kWidth, kHeight);
    const double mad = meanAbsoluteDifference(drawn, expected);
    std::printf("render API vs play's snapshot: mean absolute difference %.3f of 255, %d "
                "frame-ready callbacks\n",
                mad, callbacks);
    EXPECT_LT(mad, 2.0);
}

/// Counts the frame-ready callbacks (the render thread calls it).
void countFrame(void *userdata)
{
    static_cast<std::atomic<int> *>(userdata)->fetch_add(1);
}

/// The pixel at (x, y) of \a rgb (top row first, \a width wide).
std::array<int, 3> pixelAt(const std::vector<std::uint8_t> &rgb, int width, int x, int y)
{
    const auto i = static_cast<std::size_t>((y * width + x) * 3);
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

TEST(RenderGlTest, drawsFrameAfterFrameScaledAndFlippedAndStopsCallingWhenFreed)
{
    DT_REQUIRE_GLES_CONTEXT(gl);
    const dt_render_param opengl[] = {
        {DT_RENDER_PARAM_API_TYPE, const_cast<char *>(DT_RENDER_API_TYPE_OPENGL)},
        {DT_RENDER_PARAM_INVALID, nullptr}};
    dt_handle *h = dt_create();
    ASSERT_NE(h, nullptr);
    for (int i = 0; kOptions[i] != nullptr; i += 2)
        ASSERT_EQ(dt_set_option_string(h, kOptions[i], kOptions[i + 1]), 0);
    ASSERT_EQ(dt_set_option_string(h, "haptic", "sim"), 0);
    ASSERT_EQ(dt_set_option_string(h, "loop", "yes"), 0);
    dt_render_context *ctx = nullptr;
    ASSERT_EQ(dt_render_context_create(&ctx, h, opengl), 0);
    std::atomic<int> ready{0};
    dt_render_context_set_update_callback(ctx, countFrame, &ready);
    ASSERT_EQ(dt_initialize(h), 0);
    const char *load[] = {"loadfile", "mock://clip?frames=30&fps=30", nullptr};
    ASSERT_EQ(dt_command(h, load), 0);
    // Half the size, twice as often as the three buffers turn: each texture is read, fenced and
    // drawn again; every copy is a picture.
    constexpr int kW = kWidth / 2;
    constexpr int kH = kHeight / 2;
    Fbo up(kW, kH);
    Fbo flipped(kW, kH);
    int copies = 0;
    for (int polls = 0; polls < 6000 && copies < 8; ++polls) {
        dt_wait_event(h, 0.01);
        if (ready.load() <= copies)
            continue;
        ASSERT_EQ(dt_render_context_render(ctx, up.name(), kW, kH, 0), 0);
        ASSERT_EQ(dt_render_context_render(ctx, flipped.name(), kW, kH, DT_RENDER_FLAG_FLIP_Y), 0);
        ++copies;
    }
    ASSERT_EQ(copies, 8) << "fewer frames than asked for";
    const std::vector<std::uint8_t> a = up.readRgb(kW, kH);
    const std::vector<std::uint8_t> b = flipped.readRgb(kW, kH);
    EXPECT_GT(meanAbsoluteDifference(a, std::vector<std::uint8_t>(a.size(), 0)), 10.0);
    // The same frame upside down (the two copies of the last turn read the same texture unless a
    // new frame came between them: compare rows well inside, a bound not a match).
    int same = 0;
    for (int y = 0; y < kH; ++y)
        same += pixelAt(a, kW, kW / 4, y) == pixelAt(b, kW, kW / 4, kH - 1 - y) ? 1 : 0;
    EXPECT_GT(same, kH / 2);
    dt_render_context_free(ctx);
    const int atFree = ready.load();
    for (int i = 0; i < 20; ++i)
        dt_wait_event(h, 0.01); // the player goes on drawing, for nobody
    EXPECT_EQ(ready.load(), atFree) << "a callback after dt_render_context_free()";
    dt_terminate_destroy(h);
}

TEST(RenderGlTest, refusesBadArgumentsAndWorksOnlyBeforeInitialize)
{
    DT_REQUIRE_GLES_CONTEXT(gl);
    const dt_render_param opengl[] = {
        {DT_RENDER_PARAM_API_TYPE, const_cast<char *>(DT_RENDER_API_TYPE_OPENGL)},
        {DT_RENDER_PARAM_INVALID, nullptr}};
    const dt_render_param vulkan[] = {{DT_RENDER_PARAM_API_TYPE, const_cast<char *>("vulkan")},
                                      {DT_RENDER_PARAM_INVALID, nullptr}};
    const dt_render_param none[] = {{DT_RENDER_PARAM_INVALID, nullptr}};
    dt_render_context *ctx = nullptr;
    EXPECT_EQ(dt_render_context_create(nullptr, nullptr, opengl), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_render_context_create(&ctx, nullptr, opengl), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(ctx, nullptr);
    EXPECT_EQ(dt_render_context_render(nullptr, 0, 16, 16, 0), DT_ERROR_INVALID_PARAMETER);
    dt_render_context_set_update_callback(nullptr, nullptr, nullptr); // no crash
    dt_render_context_free(nullptr);

    dt_handle *h = dt_create();
    ASSERT_NE(h, nullptr);
    EXPECT_EQ(dt_render_context_create(&ctx, h, nullptr), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_render_context_create(&ctx, h, none), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_render_context_create(&ctx, h, vulkan), DT_ERROR_NOT_IMPLEMENTED);
    // No context current on this thread: nothing to share with.
    const EGLDisplay display = eglGetCurrentDisplay();
    const EGLContext context = eglGetCurrentContext();
    ASSERT_EQ(eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT), EGL_TRUE);
    EXPECT_EQ(dt_render_context_create(&ctx, h, opengl), DT_ERROR_UNSUPPORTED);
    ASSERT_EQ(eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context), EGL_TRUE);

    ASSERT_EQ(dt_render_context_create(&ctx, h, opengl), DT_ERROR_SUCCESS);
    ASSERT_NE(ctx, nullptr);
    dt_render_context *second = nullptr;
    EXPECT_EQ(dt_render_context_create(&second, h, opengl), DT_ERROR_INVALID_PARAMETER);
    Fbo fbo(16, 16);
    EXPECT_EQ(dt_render_context_render(ctx, fbo.name(), 0, 16, 0), DT_ERROR_INVALID_PARAMETER);
    EXPECT_EQ(dt_render_context_render(ctx, fbo.name(), 16, 16, 2), DT_ERROR_INVALID_PARAMETER);
    // No frame yet: black.
    EXPECT_EQ(dt_render_context_render(ctx, fbo.name(), 16, 16, DT_RENDER_FLAG_FLIP_Y), 0);
    const std::vector<std::uint8_t> black = fbo.readRgb(16, 16);
    EXPECT_EQ(meanAbsoluteDifference(black, std::vector<std::uint8_t>(black.size(), 0)), 0.0);
    // Not a framebuffer of this context.
    EXPECT_EQ(dt_render_context_render(ctx, 12345, 16, 16, 0), DT_ERROR_UNSUPPORTED);
    dt_render_context_free(ctx);
    dt_terminate_destroy(h);

    // After dt_initialize() it is too late (the player opened its own display).
    dt_handle *running = dt_create();
    ASSERT_NE(running, nullptr);
    for (int i = 0; kOptions[i] != nullptr; i += 2)
        ASSERT_EQ(dt_set_option_string(running, kOptions[i], kOptions[i + 1]), 0);
    ASSERT_EQ(dt_set_option_string(running, "display", "headless"), 0);
    ASSERT_EQ(dt_initialize(running), 0);
    EXPECT_EQ(dt_render_context_create(&ctx, running, opengl), DT_ERROR_INVALID_PARAMETER);
    dt_terminate_destroy(running);
}

} // namespace
