#include "depthtouch/drivers/egl/egl_headless_display.h"

#include <array>
#include <vector>

#include "depthtouch/platform/log.h"
#include "egl_common.h"

DT_LOG_CATEGORY(Egl)

namespace depthtouch::drivers {

struct EglHeadlessDisplay::Gl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    std::array<GLuint, 2> fbo{};
    std::array<GLuint, 2> color{};
    std::array<GLuint, 2> depth{};
    int back = 0;           ///< Index of the buffer drawn into; the other one was presented.
    bool presented = false; ///< A frame was presented since open().
    std::vector<std::uint8_t> staging;

    void destroy() noexcept
    {
        if (context != EGL_NO_CONTEXT) {
            if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context) == EGL_TRUE) {
                glDeleteFramebuffers(2, fbo.data());
                glDeleteRenderbuffers(2, color.data());
                glDeleteRenderbuffers(2, depth.data());
            }
            eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            eglDestroyContext(display, context);
        }
        fbo = {};
        color = {};
        depth = {};
        context = EGL_NO_CONTEXT;
        egl::releaseEglDisplay(display);
        display = EGL_NO_DISPLAY;
        staging.clear();
        staging.shrink_to_fit();
    }
};

Result<std::unique_ptr<hal::Display>> EglHeadlessDisplay::create(const hal::BackendConfig &cfg)
{
    auto settings = EglDisplaySettings::parse(cfg.options);
    if (!settings)
        return unexpected(settings.error());
    // Probe the platform now so autoprobe moves on when it is missing.
    auto display = egl::acquireEglDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY);
    if (!display)
        return unexpected(display.error());
    egl::releaseEglDisplay(*display);
    return std::unique_ptr<hal::Display>(
        std::make_unique<EglHeadlessDisplay>(cfg.clockRef(), *settings));
}

EglHeadlessDisplay::EglHeadlessDisplay(platform::Clock &clock, const EglDisplaySettings &settings)
    : clock_(clock), settings_(settings), gl_(std::make_unique<Gl>())
{
    caps_.hasGlesContext = true;
    caps_.offscreen = true;
    caps_.readback = true;
}

EglHeadlessDisplay::~EglHeadlessDisplay()
{
    close();
}

Result<void> EglHeadlessDisplay::openDevice(const hal::DisplayConfig &cfg)
{
    auto resolved = resolveWindowConfig(cfg, settings_);
    if (!resolved)
        return unexpected(resolved.error());

    auto display = egl::acquireEglDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY);
    if (!display)
        return unexpected(display.error());
    Gl &gl = *gl_;
    gl.display = *display;
    auto context = egl::createGles3Context(gl.display, EGL_NO_CONFIG_KHR);
    if (!context) {
        gl.destroy();
        return unexpected(context.error());
    }
    gl.context = *context;
    if (eglMakeCurrent(gl.display, EGL_NO_SURFACE, EGL_NO_SURFACE, gl.context) == EGL_FALSE) {
        DT_LOG(Egl, Error, "Failed to make the surfaceless context current: %s",
               egl::eglErrorName(eglGetError()));
        gl.destroy();
        return unexpected(Errc::NotSupported, "Surfaceless context cannot be made current");
    }
    const int w = resolved->width;
    const int h = resolved->height;
    glGenFramebuffers(2, gl.fbo.data());
    glGenRenderbuffers(2, gl.color.data());
    glGenRenderbuffers(2, gl.depth.data());
    for (std::size_t i = 0; i < 2; ++i) {
        glBindRenderbuffer(GL_RENDERBUFFER, gl.color[i]);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
        glBindRenderbuffer(GL_RENDERBUFFER, gl.depth[i]);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, w, h);
        glBindFramebuffer(GL_FRAMEBUFFER, gl.fbo[i]);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                  gl.color[i]);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                                  gl.depth[i]);
        const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE || glGetError() != GL_NO_ERROR) {
            DT_LOG(Egl, Error, "Failed to create a %dx%d offscreen framebuffer (status 0x%x)", w,
                   h, status);
            gl.destroy();
            return unexpected(Errc::OutOfResources, "Offscreen framebuffer incomplete");
        }
        glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    }
    gl.back = 0;
    gl.presented = false;
    glBindFramebuffer(GL_FRAMEBUFFER, gl.fbo[0]);
    glViewport(0, 0, w, h);
    DT_LOG(Egl, Info, "Headless display %dx%d at %.3g Hz on %s", w, h, resolved->refreshHz,
           reinterpret_cast<const char *>(glGetString(GL_RENDERER)));
    size_ = {w, h};
    refreshHz_ = resolved->refreshHz;
    pacer_.start(clock_.now(), refreshHz_);
    return ok();
}

void EglHeadlessDisplay::closeDevice() noexcept
{
    gl_->destroy();
}

std::uint32_t EglHeadlessDisplay::framebufferDevice() const noexcept
{
    return gl_->fbo[static_cast<std::size_t>(gl_->back)];
}

Result<void> EglHeadlessDisplay::ensureCurrent()
{
    const EGLint err = egl::makeCurrentUnlessCurrent(gl_->display, EGL_NO_SURFACE, gl_->context);
    if (err == EGL_SUCCESS)
        return ok();
    DT_LOG(Egl, Error, "Failed to make the headless context current: %s", egl::eglErrorName(err));
    if (err == EGL_CONTEXT_LOST) {
        markLost();
        return unexpected(Errc::NoDevice, "GL context lost");
    }
    return unexpected(Errc::Io, "eglMakeCurrent failed");
}

Result<void> EglHeadlessDisplay::makeCurrentDevice()
{
    DT_TRY(ensureCurrent());
    egl::bindDrawTarget(framebuffer(), size_);
    return ok();
}

Result<hal::PresentInfo> EglHeadlessDisplay::presentDevice()
{
    DT_TRY(ensureCurrent());
    // A screen shows a frame only once it is drawn: wait for the GPU like a flip does.
    glFinish();
    gl_->back = 1 - gl_->back;
    gl_->presented = true;
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer());
    return pacer_.next(clock_);
}

Result<void> EglHeadlessDisplay::readPixelsDevice(const hal::ImageView &out)
{
    DT_TRY(ensureCurrent());
    if (!gl_->presented)
        return unexpected(Errc::InvalidState, "readPixels() needs a presented frame");
    DT_TRY(egl::checkReadTarget(out, size_));
    const GLuint front = gl_->fbo[static_cast<std::size_t>(1 - gl_->back)];
    return egl::readFramebuffer(front, size_, out, gl_->staging);
}

} // namespace depthtouch::drivers
