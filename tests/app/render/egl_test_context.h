#pragma once
/// \file
/// \brief Test support: an OpenGL ES 3 context on Mesa's EGL surfaceless platform
/// (`EGL_PLATFORM_SURFACELESS_MESA`, llvmpipe when there is no GPU), with no window and no
/// surface. Tests and benchmark programs render into a render::RenderTarget (an FBO) instead.
///
/// Thread-safety: thread-bound (the context is current on the thread that created it).

#include <memory>
#include <string>

namespace depthtouch::test {

/// \brief Owns an EGL display (surfaceless platform) and a current GLES 3 context.
class EglTestContext {
public:
    /// \brief Initialises EGL on the surfaceless platform and makes a GLES 3 context current.
    /// \param[out] why on failure: what was missing (e.g. "EGL_MESA_platform_surfaceless
    /// unsupported"), for a GTEST_SKIP message.
    /// \return the context, or nullptr with \a why set.
    static std::unique_ptr<EglTestContext> create(std::string &why);

    ~EglTestContext();
    EglTestContext(const EglTestContext &) = delete;
    EglTestContext &operator=(const EglTestContext &) = delete;

    /// \return GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
    [[nodiscard]] std::string renderer() const;

private:
    EglTestContext() = default;
    void *display_ = nullptr; ///< EGLDisplay
    void *context_ = nullptr; ///< EGLContext
};

} // namespace depthtouch::test

/// Creates `ctx` (a std::unique_ptr<EglTestContext>) or skips the test with the reason.
#define DT_REQUIRE_GLES_CONTEXT(ctx)                                                               \
    std::string ctx##Why;                                                                          \
    auto ctx = ::depthtouch::test::EglTestContext::create(ctx##Why);                               \
    if (!ctx)                                                                                      \
    GTEST_SKIP() << "No GLES 3 context on the EGL surfaceless platform: " << ctx##Why
