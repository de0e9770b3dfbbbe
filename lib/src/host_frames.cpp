/// \file
/// \brief The frames the player hands to the host's thread (builds with EGL): see host_frames.h.

#include "host_frames.h"

#include <EGL/egl.h>
#include <GLES3/gl3.h>

#include <new>

#include "depthtouch/client.h"

namespace depthtouch::client {

namespace {

GLsync syncOf(void *p) noexcept
{
    return static_cast<GLsync>(p);
}

/// Clears the draw framebuffer to black (all of it: glClear ignores the viewport), the scissor
/// test off meanwhile, the clear colour kept.
void clearBlack()
{
    const GLboolean scissor = glIsEnabled(GL_SCISSOR_TEST);
    glDisable(GL_SCISSOR_TEST);
    GLfloat was[4] = {};
    glGetFloatv(GL_COLOR_CLEAR_VALUE, was);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glClearColor(was[0], was[1], was[2], was[3]);
    if (scissor == GL_TRUE)
        glEnable(GL_SCISSOR_TEST);
}

} // namespace

int HostFrames::create(std::shared_ptr<HostFrames> &out)
{
    const EGLContext context = eglGetCurrentContext();
    const EGLDisplay display = eglGetCurrentDisplay();
    if (context == EGL_NO_CONTEXT || display == EGL_NO_DISPLAY)
        return DT_ERROR_UNSUPPORTED;
    if (eglQueryAPI() != EGL_OPENGL_ES_API)
        return DT_ERROR_UNSUPPORTED;
    auto f = std::make_shared<HostFrames>();
    f->eglDisplay_ = display;
    f->eglContext_ = context;
    out = std::move(f);
    return DT_ERROR_SUCCESS;
}

HostFrames::~HostFrames() = default;

int HostFrames::render(std::uint32_t fbo, int width, int height, bool flipY)
{
    (void)glGetError(); // the host's earlier errors are not ours
    int buffer = -1;
    GLuint texture = 0;
    int w = 0;
    int h = 0;
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (attached_ && newest_ >= 0) {
            buffer = newest_;
            reading_ = buffer;
            texture = textures_[static_cast<std::size_t>(buffer)];
            w = width_;
            h = height_;
        }
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    if (glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        const std::lock_guard<std::mutex> lock(mutex_);
        reading_ = -1;
        readDone_.notify_all();
        return DT_ERROR_UNSUPPORTED;
    }
    if (buffer < 0) {
        clearBlack();
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        return glGetError() == GL_NO_ERROR ? DT_ERROR_SUCCESS : DT_ERROR_GENERIC;
    }
    if (readFbo_ == 0)
        glGenFramebuffers(1, &readFbo_);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, readFbo_);
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
    const GLboolean scissor = glIsEnabled(GL_SCISSOR_TEST);
    glDisable(GL_SCISSOR_TEST);
    // At the same size the pixels are copied as they are (GL_NEAREST); scaled, filtered.
    const bool sameSize = width == w && height == h;
    glBlitFramebuffer(0, 0, w, h, 0, flipY ? height : 0, width, flipY ? 0 : height,
                      GL_COLOR_BUFFER_BIT, sameSize ? GL_NEAREST : GL_LINEAR);
    if (scissor == GL_TRUE)
        glEnable(GL_SCISSOR_TEST);
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    const GLenum err = glGetError();
    GLsync done = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    glFlush(); // the render thread waits for the fence: it must reach the GPU
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        void *&slot = readFences_[static_cast<std::size_t>(buffer)];
        if (slot != nullptr)
            glDeleteSync(syncOf(slot));
        slot = done;
        reading_ = -1;
    }
    readDone_.notify_all();
    return err == GL_NO_ERROR ? DT_ERROR_SUCCESS : DT_ERROR_GENERIC;
}

void HostFrames::releaseHost() noexcept
{
    setCallback(nullptr, nullptr);
    if (readFbo_ != 0 && eglGetCurrentContext() == static_cast<EGLContext>(eglContext_))
        glDeleteFramebuffers(1, &readFbo_);
    readFbo_ = 0;
}

void HostFrames::setCallback(Callback cb, void *userdata)
{
    const std::lock_guard<std::mutex> lock(callbackMutex_);
    callback_ = cb;
    userdata_ = userdata;
}

void HostFrames::attach(const std::array<std::uint32_t, kBuffers> &textures, int width, int height)
{
    const std::lock_guard<std::mutex> lock(mutex_);
    textures_ = textures;
    width_ = width;
    height_ = height;
    attached_ = true;
    newest_ = -1;
}

int HostFrames::publish(int drawn, void *&readFence)
{
    int next = 0;
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        newest_ = drawn;
        while (next == newest_ || next == reading_)
            ++next;
        readFence = readFences_[static_cast<std::size_t>(next)];
        readFences_[static_cast<std::size_t>(next)] = nullptr;
    }
    const std::lock_guard<std::mutex> lock(callbackMutex_);
    if (callback_ != nullptr)
        callback_(userdata_);
    return next;
}

std::array<void *, HostFrames::kBuffers> HostFrames::detach()
{
    std::unique_lock<std::mutex> lock(mutex_);
    readDone_.wait(lock, [this] { return reading_ < 0; });
    attached_ = false;
    newest_ = -1;
    textures_ = {};
    std::array<void *, kBuffers> fences = readFences_;
    readFences_ = {};
    return fences;
}

} // namespace depthtouch::client
