/// \file
/// \brief The player's display of the render API (builds with EGL): a context in the host's share
/// group drawing into textures the host reads. See host_frames.h.

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>

#include <array>
#include <utility>

#include "depthtouch/drivers/common/vsync_pacer.h"
#include "depthtouch/drivers/egl/display_settings.h"
#include "depthtouch/hal/display_base.h"
#include "depthtouch/platform/log.h"
#include "host_frames.h"

DT_LOG_CATEGORY(Client)

namespace depthtouch::client {

namespace {

/// How long closing waits for a copy of the host's still running, ns.
constexpr GLuint64 kCopyWaitNs = 1'000'000'000;

/// \return the config of the host's \a context on \a display, or EGL_NO_CONFIG_KHR when it was
/// made without one (EGL_KHR_no_config_context).
EGLConfig configOf(EGLDisplay display, EGLContext context)
{
    EGLint id = 0;
    if (eglQueryContext(display, context, EGL_CONFIG_ID, &id) == EGL_FALSE || id == 0)
        return EGL_NO_CONFIG_KHR;
    const EGLint attribs[] = {EGL_CONFIG_ID, id, EGL_NONE};
    EGLConfig config = EGL_NO_CONFIG_KHR;
    EGLint n = 0;
    if (eglChooseConfig(display, attribs, &config, 1, &n) == EGL_FALSE || n != 1)
        return EGL_NO_CONFIG_KHR;
    return config;
}

/// See host_frames.h.
class HostDisplay final : public hal::DisplayBase {
public:
    HostDisplay(std::shared_ptr<HostFrames> frames, platform::Clock &clock,
                const drivers::EglDisplaySettings &settings)
        : frames_(std::move(frames)), clock_(clock), settings_(settings)
    {
        caps_.hasGlesContext = true;
        caps_.offscreen = true;
    }
    ~HostDisplay() override { close(); }
    HostDisplay(const HostDisplay &) = delete;
    HostDisplay &operator=(const HostDisplay &) = delete;

protected:
    Result<void> openDevice(const hal::DisplayConfig &cfg) override;
    void closeDevice() noexcept override;
    Result<void> makeCurrentDevice() override
    {
        DT_TRY(ensureCurrent());
        glBindFramebuffer(GL_FRAMEBUFFER, framebufferDevice());
        glViewport(0, 0, size_.width, size_.height);
        return ok();
    }
    Result<hal::PresentInfo> presentDevice() override;
    [[nodiscard]] std::uint32_t framebufferDevice() const noexcept override
    {
        return fbo_[static_cast<std::size_t>(back_)];
    }

private:
    Result<void> ensureCurrent();
    Result<void> makeBuffers(int width, int height);
    void destroy() noexcept;

    std::shared_ptr<HostFrames> frames_;
    platform::Clock &clock_;
    const drivers::EglDisplaySettings settings_;
    drivers::VsyncPacer pacer_;
    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
    EGLSurface surface_ = EGL_NO_SURFACE; ///< A 1x1 pbuffer when surfaceless is not there.
    std::array<GLuint, HostFrames::kBuffers> fbo_{};
    std::array<GLuint, HostFrames::kBuffers> texture_{};
    std::array<GLuint, HostFrames::kBuffers> depth_{};
    int back_ = 0; ///< The buffer drawn into.
};

Result<void> HostDisplay::openDevice(const hal::DisplayConfig &cfg)
{
    auto resolved = drivers::resolveWindowConfig(cfg, settings_);
    if (!resolved)
        return unexpected(resolved.error());
    display_ = static_cast<EGLDisplay>(frames_->eglDisplay());
    const auto share = static_cast<EGLContext>(frames_->eglContext());
    const EGLConfig config = configOf(display_, share);
    eglBindAPI(EGL_OPENGL_ES_API);
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_NONE};
    context_ = eglCreateContext(display_, config, share, attribs);
    if (context_ == EGL_NO_CONTEXT) {
        DT_LOG(Client, Error, "Cannot make a context in the host's share group (EGL error 0x%x)",
               static_cast<unsigned>(eglGetError()));
        return unexpected(Errc::NotSupported, "no GL context shared with the host's");
    }
    if (eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) == EGL_FALSE &&
        config != EGL_NO_CONFIG_KHR) {
        const EGLint pb[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
        surface_ = eglCreatePbufferSurface(display_, config, pb);
        (void)eglMakeCurrent(display_, surface_, surface_, context_);
    }
    if (eglGetCurrentContext() != context_) {
        destroy();
        return unexpected(Errc::NotSupported, "the render API's context cannot be made current");
    }
    if (auto b = makeBuffers(resolved->width, resolved->height); !b) {
        destroy();
        return b;
    }
    size_ = {resolved->width, resolved->height};
    refreshHz_ = resolved->refreshHz;
    frames_->attach(texture_, size_.width, size_.height);
    pacer_.start(clock_.now(), refreshHz_);
    DT_LOG(Client, Info, "Render API display %dx%d at %.3g Hz on %s", size_.width, size_.height,
           refreshHz_, reinterpret_cast<const char *>(glGetString(GL_RENDERER)));
    return ok();
}

Result<void> HostDisplay::makeBuffers(int width, int height)
{
    glGenFramebuffers(HostFrames::kBuffers, fbo_.data());
    glGenTextures(HostFrames::kBuffers, texture_.data());
    glGenRenderbuffers(HostFrames::kBuffers, depth_.data());
    for (std::size_t i = 0; i < fbo_.size(); ++i) {
        glBindTexture(GL_TEXTURE_2D, texture_[i]);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, width, height);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glBindRenderbuffer(GL_RENDERBUFFER, depth_[i]);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width, height);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_[i]);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture_[i], 0);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                                  depth_[i]);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE ||
            glGetError() != GL_NO_ERROR)
            return unexpected(Errc::OutOfResources, "render API framebuffer incomplete");
        glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    back_ = 0;
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_[0]);
    glViewport(0, 0, width, height);
    return ok();
}

Result<void> HostDisplay::ensureCurrent()
{
    if (eglGetCurrentContext() == context_)
        return ok();
    if (eglMakeCurrent(display_, surface_, surface_, context_) == EGL_TRUE)
        return ok();
    if (eglGetError() == EGL_CONTEXT_LOST) {
        markLost();
        return unexpected(Errc::NoDevice, "GL context lost");
    }
    return unexpected(Errc::Io, "eglMakeCurrent failed");
}

Result<hal::PresentInfo> HostDisplay::presentDevice()
{
    DT_TRY(ensureCurrent());
    // The frame is whole before the host may read it, as a screen shows a frame once drawn.
    glFinish();
    void *readFence = nullptr;
    back_ = frames_->publish(back_, readFence);
    if (readFence != nullptr) {
        // The host's copy of this buffer's last frame comes before it is drawn over.
        glWaitSync(static_cast<GLsync>(readFence), 0, GL_TIMEOUT_IGNORED);
        glDeleteSync(static_cast<GLsync>(readFence));
    }
    glBindFramebuffer(GL_FRAMEBUFFER, framebufferDevice());
    return pacer_.next(clock_);
}

void HostDisplay::closeDevice() noexcept
{
    destroy();
}

void HostDisplay::destroy() noexcept
{
    const std::array<void *, HostFrames::kBuffers> fences = frames_->detach();
    if (context_ != EGL_NO_CONTEXT) {
        if (eglMakeCurrent(display_, surface_, surface_, context_) == EGL_TRUE) {
            // The host's copies finish before their textures go (at most a second each).
            for (void *f : fences) {
                if (f == nullptr)
                    continue;
                (void)glClientWaitSync(static_cast<GLsync>(f), GL_SYNC_FLUSH_COMMANDS_BIT,
                                       kCopyWaitNs);
                glDeleteSync(static_cast<GLsync>(f));
            }
            glDeleteFramebuffers(HostFrames::kBuffers, fbo_.data());
            glDeleteTextures(HostFrames::kBuffers, texture_.data());
            glDeleteRenderbuffers(HostFrames::kBuffers, depth_.data());
        }
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
    }
    if (surface_ != EGL_NO_SURFACE)
        eglDestroySurface(display_, surface_);
    surface_ = EGL_NO_SURFACE;
    context_ = EGL_NO_CONTEXT;
    fbo_ = {};
    texture_ = {};
    depth_ = {};
}

} // namespace

Result<std::unique_ptr<hal::Display>> makeHostDisplay(std::shared_ptr<HostFrames> frames,
                                                      platform::Clock &clock,
                                                      const std::string &displayOptions)
{
    auto settings = drivers::EglDisplaySettings::parse(hal::OptionList(displayOptions));
    if (!settings)
        return unexpected(settings.error());
    return std::unique_ptr<hal::Display>(
        std::make_unique<HostDisplay>(std::move(frames), clock, *settings));
}

} // namespace depthtouch::client
