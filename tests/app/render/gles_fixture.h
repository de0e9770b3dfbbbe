#pragma once
/// \file
/// \brief The base fixtures of the renderer tests that draw: a GLES 3 context on the EGL
/// surfaceless platform (the test skipped without one), a stereo renderer on it, and the read-back
/// of a drawn frame.
/// Thread-safety: test code, one thread.

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "app/render/egl_test_context.h"
#include "depthtouch/render/render_target.h"
#include "depthtouch/render/renderer.h"

namespace depthtouch::test {

/// \brief Draws the current frame of \a r into a new \a w × \a h render target (pixels).
/// \return the target's pixels as RenderTarget::readRgb() gives them, 3 bytes (R, G, B) each; a
/// target not made, a frame not drawn or pixels not read fail the test (not fatally).
inline std::vector<std::uint8_t> drawRgb(render::StereoRenderer &r, int w, int h)
{
    auto t = render::RenderTarget::create(w, h);
    EXPECT_TRUE(t);
    EXPECT_TRUE(r.render(*t));
    std::vector<std::uint8_t> rgb;
    EXPECT_TRUE(t->readRgb(rgb));
    return rgb;
}

/// \brief Makes a GLES 3 context current for each test, or skips the test with the reason. Its
/// members outlive a derived fixture's, so the context outlives their GL objects.
class GlesTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        std::string why;
        ctx_ = EglTestContext::create(why);
        if (!ctx_)
            GTEST_SKIP() << "No GLES 3 context on the EGL surfaceless platform: " << why;
    }

    std::unique_ptr<EglTestContext> ctx_;
};

/// \brief GlesTest with one stereo renderer, renderer_, made by setUpRenderer().
class GlesRendererTest : public GlesTest {
protected:
    /// Makes the context current and renderer_ with options \a o. Skips the test without a
    /// context; fails it fatally when the options are refused. Either way renderer_ stays null.
    void setUpRenderer(const render::RendererOptions &o)
    {
        GlesTest::SetUp();
        if (IsSkipped())
            return;
        auto r = render::StereoRenderer::create(o);
        ASSERT_TRUE(r) << r.error().what;
        renderer_ = std::move(*r);
    }

    std::unique_ptr<render::StereoRenderer> renderer_;
};

} // namespace depthtouch::test
