#include "egl_common.h"

#include <cstdint>
#include <cstring>
#include <mutex>

#include "depthtouch/platform/log.h"
#include "depthtouch/platform/memory_lock.h"

DT_LOG_CATEGORY(Egl)

namespace depthtouch::drivers::egl {

namespace {

struct DisplayRef {
    EGLDisplay display;
    int count;
};

std::mutex gDisplaysMutex;
std::vector<DisplayRef> gDisplays; // Guarded by gDisplaysMutex.

bool hasExtension(const char *list, const char *name) noexcept
{
    if (list == nullptr)
        return false;
    const std::size_t n = std::strlen(name);
    for (const char *p = std::strstr(list, name); p != nullptr; p = std::strstr(p + 1, name))
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return true;
    return false;
}

} // namespace

const char *eglErrorName(EGLint error) noexcept
{
    switch (error) {
    case EGL_SUCCESS:
        return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
        return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
        return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
        return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
        return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
        return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
        return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE:
        return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY:
        return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
        return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP:
        return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW:
        return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER:
        return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
        return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST:
        return "EGL_CONTEXT_LOST";
    default:
        return "EGL error";
    }
}

Result<EGLDisplay> acquireEglDisplay(EGLenum platform, void *nativeDisplay)
{
    // Mesa maps about 1 GiB of address space (its threads' stacks and code: VmPeak of a headless
    // play 1.0 GiB, 0.33 GiB with the mock display). Below that it fails inside the driver, with
    // a crash or a hang that nothing recovers from: refuse before loading it.
    constexpr std::uint64_t kNeededBytes = std::uint64_t{1} << 30;
    if (const std::uint64_t limit = platform::addressSpaceLimitBytes();
        limit != 0 && limit < kNeededBytes) {
        DT_LOG(Egl, Error, "The address space limit is %llu MiB, the EGL driver needs about %llu",
               static_cast<unsigned long long>(limit >> 20),
               static_cast<unsigned long long>(kNeededBytes >> 20));
        return unexpected(Errc::OutOfResources,
                          "the address space limit (ulimit -v) is below the 1 GiB that the EGL "
                          "driver maps (its threads and code): raise it");
    }
    const char *client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!hasExtension(client, "EGL_EXT_platform_base")) {
        DT_LOG(Egl, Error, "Failed to find EGL_EXT_platform_base (client extensions: %s)",
               client != nullptr ? client : "none");
        return unexpected(Errc::NoDevice, "EGL has no platform extension");
    }
    const char *wanted = platform == EGL_PLATFORM_SURFACELESS_MESA ? "EGL_MESA_platform_surfaceless"
                         : platform == EGL_PLATFORM_GBM_KHR        ? "EGL_KHR_platform_gbm"
                                                                   : "EGL_EXT_platform_x11";
    if (!hasExtension(client, wanted) &&
        !(platform == EGL_PLATFORM_GBM_KHR && hasExtension(client, "EGL_MESA_platform_gbm")) &&
        !(platform == EGL_PLATFORM_X11_KHR && hasExtension(client, "EGL_KHR_platform_x11"))) {
        DT_LOG(Egl, Error, "Failed to find EGL platform extension %s", wanted);
        return unexpected(Errc::NoDevice, "EGL platform not available");
    }
    auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (getPlatformDisplay == nullptr)
        return unexpected(Errc::NoDevice, "eglGetPlatformDisplayEXT missing");
    EGLDisplay display = getPlatformDisplay(platform, nativeDisplay, nullptr);
    if (display == EGL_NO_DISPLAY) {
        DT_LOG(Egl, Error, "Failed to get EGL display for %s: %s", wanted,
               eglErrorName(eglGetError()));
        return unexpected(Errc::NoDevice, "No EGL display on this platform");
    }
    std::lock_guard<std::mutex> lock(gDisplaysMutex);
    for (DisplayRef &ref : gDisplays) {
        if (ref.display == display) {
            ++ref.count;
            return display;
        }
    }
    EGLint major = 0;
    EGLint minor = 0;
    if (eglInitialize(display, &major, &minor) == EGL_FALSE) {
        DT_LOG(Egl, Error, "Failed to initialise EGL display for %s: %s", wanted,
               eglErrorName(eglGetError()));
        return unexpected(Errc::NoDevice, "Failed to initialise EGL display");
    }
    DT_LOG(Egl, Debug, "EGL %d.%d on %s, vendor %s", major, minor, wanted,
           eglQueryString(display, EGL_VENDOR));
    gDisplays.push_back({display, 1});
    return display;
}

void releaseEglDisplay(EGLDisplay display) noexcept
{
    if (display == EGL_NO_DISPLAY)
        return;
    std::lock_guard<std::mutex> lock(gDisplaysMutex);
    for (auto it = gDisplays.begin(); it != gDisplays.end(); ++it) {
        if (it->display == display) {
            if (--it->count == 0) {
                eglTerminate(display);
                gDisplays.erase(it);
            }
            return;
        }
    }
}

Result<EGLConfig> chooseConfig(EGLDisplay display, EGLint surfaceType, EGLint visualId)
{
    const EGLint attribs[] = {EGL_RED_SIZE,        8,
                              EGL_GREEN_SIZE,      8,
                              EGL_BLUE_SIZE,       8,
                              EGL_ALPHA_SIZE,      0,
                              EGL_DEPTH_SIZE,      24,
                              EGL_STENCIL_SIZE,    8,
                              EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT,
                              EGL_SURFACE_TYPE,    surfaceType,
                              EGL_NONE};
    EGLint count = 0;
    if (eglChooseConfig(display, attribs, nullptr, 0, &count) == EGL_FALSE || count <= 0)
        return unexpected(Errc::NotSupported, "No EGL config for OpenGL ES 3 with depth 24");
    std::vector<EGLConfig> configs(static_cast<std::size_t>(count));
    if (eglChooseConfig(display, attribs, configs.data(), count, &count) == EGL_FALSE)
        return unexpected(Errc::NotSupported, "eglChooseConfig failed");
    for (EGLint i = 0; i < count; ++i) {
        const EGLConfig c = configs[static_cast<std::size_t>(i)];
        EGLint id = 0;
        EGLint r = 0;
        EGLint g = 0;
        EGLint b = 0;
        eglGetConfigAttrib(display, c, EGL_NATIVE_VISUAL_ID, &id);
        eglGetConfigAttrib(display, c, EGL_RED_SIZE, &r);
        eglGetConfigAttrib(display, c, EGL_GREEN_SIZE, &g);
        eglGetConfigAttrib(display, c, EGL_BLUE_SIZE, &b);
        if ((visualId == 0 || id == visualId) && r == 8 && g == 8 && b == 8)
            return c;
    }
    return unexpected(Errc::NotSupported, "No EGL config matches the native visual");
}

Result<EGLContext> createGles3Context(EGLDisplay display, EGLConfig config)
{
    if (eglBindAPI(EGL_OPENGL_ES_API) == EGL_FALSE)
        return unexpected(Errc::NotSupported, "EGL cannot bind the OpenGL ES API");
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 0,
                              EGL_NONE};
    EGLContext ctx = eglCreateContext(display, config, EGL_NO_CONTEXT, attribs);
    if (ctx == EGL_NO_CONTEXT) {
        DT_LOG(Egl, Error, "Failed to create an OpenGL ES 3 context: %s",
               eglErrorName(eglGetError()));
        return unexpected(Errc::NotSupported, "Failed to create an OpenGL ES 3 context");
    }
    return ctx;
}

EGLSurface createWindowSurface(EGLDisplay display, EGLConfig config, void *platformWindow,
                               void *nativeWindow)
{
    auto createSurface = reinterpret_cast<PFNEGLCREATEPLATFORMWINDOWSURFACEEXTPROC>(
        eglGetProcAddress("eglCreatePlatformWindowSurfaceEXT"));
    return createSurface != nullptr
               ? createSurface(display, config, platformWindow, nullptr)
               : eglCreateWindowSurface(
                     display, config, reinterpret_cast<EGLNativeWindowType>(nativeWindow), nullptr);
}

Result<void> checkReadTarget(const hal::ImageView &out, hal::Size size) noexcept
{
    if (out.format != hal::PixelFormat::Rgba8 && out.format != hal::PixelFormat::Rgb24)
        return unexpected(Errc::InvalidArgument, "readPixels() writes Rgba8 or Rgb24");
    if (out.width != size.width || out.height != size.height)
        return unexpected(Errc::InvalidArgument,
                          "readPixels() image size differs from the display");
    const int bpp = out.format == hal::PixelFormat::Rgba8 ? 4 : 3;
    if (out.planes[0].data == nullptr || out.planes[0].strideBytes < out.width * bpp)
        return unexpected(Errc::InvalidArgument, "readPixels() image has no room for a row");
    return ok();
}

Result<void> readFramebuffer(GLuint fbo, hal::Size size, const hal::ImageView &out,
                             std::vector<std::uint8_t> &staging)
{
    const auto w = static_cast<std::size_t>(size.width);
    const auto h = static_cast<std::size_t>(size.height);
    staging.resize(w * h * 4);
    GLint previous = 0;
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &previous);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, size.width, size.height, GL_RGBA, GL_UNSIGNED_BYTE, staging.data());
    const GLenum err = glGetError();
    glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(previous));
    if (err != GL_NO_ERROR) {
        DT_LOG(Egl, Error, "Failed to read the framebuffer: GL error 0x%x", err);
        return unexpected(Errc::Io, "glReadPixels failed");
    }
    // GL rows run bottom to top; images run top to bottom.
    for (std::size_t y = 0; y < h; ++y) {
        const std::uint8_t *src = staging.data() + (h - 1 - y) * w * 4;
        std::uint8_t *dst = out.row(0, static_cast<int>(y));
        if (out.format == hal::PixelFormat::Rgba8) {
            std::memcpy(dst, src, w * 4);
        } else {
            for (std::size_t x = 0; x < w; ++x) {
                dst[3 * x] = src[4 * x];
                dst[3 * x + 1] = src[4 * x + 1];
                dst[3 * x + 2] = src[4 * x + 2];
            }
        }
    }
    return ok();
}

Result<void> FrameCopy::create(hal::Size size)
{
    glGenFramebuffers(1, &fbo_);
    glGenRenderbuffers(1, &color_);
    glBindRenderbuffer(GL_RENDERBUFFER, color_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, size.width, size.height);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE || glGetError() != GL_NO_ERROR) {
        DT_LOG(Egl, Error, "Failed to create a %dx%d readback framebuffer (status 0x%x)",
               size.width, size.height, status);
        destroy();
        return unexpected(Errc::OutOfResources, "Readback framebuffer incomplete");
    }
    return {};
}

void FrameCopy::keep(hal::Size size) noexcept
{
    if (fbo_ != 0) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_);
        glBlitFramebuffer(0, 0, size.width, size.height, 0, 0, size.width, size.height,
                          GL_COLOR_BUFFER_BIT, GL_NEAREST);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
}

Result<void> FrameCopy::read(const hal::ImageView &out, hal::Size size)
{
    if (!presented_)
        return unexpected(Errc::InvalidState, "readPixels() needs a presented frame");
    DT_TRY(checkReadTarget(out, size));
    return readFramebuffer(fbo_, size, out, staging_);
}

void FrameCopy::destroy() noexcept
{
    if (fbo_ != 0)
        glDeleteFramebuffers(1, &fbo_);
    if (color_ != 0)
        glDeleteRenderbuffers(1, &color_);
    forget();
}

void FrameCopy::forget() noexcept
{
    fbo_ = 0;
    color_ = 0;
    presented_ = false;
    staging_.clear();
    staging_.shrink_to_fit();
}

EGLint makeCurrentUnlessCurrent(EGLDisplay display, EGLSurface surface, EGLContext context) noexcept
{
    if (eglGetCurrentContext() == context)
        return EGL_SUCCESS;
    if (eglMakeCurrent(display, surface, surface, context) == EGL_FALSE)
        return eglGetError();
    return EGL_SUCCESS;
}

bool isSurfaceGone(EGLint error) noexcept
{
    return error == EGL_CONTEXT_LOST || error == EGL_BAD_NATIVE_WINDOW || error == EGL_BAD_SURFACE;
}

Result<void> makeWindowCurrent(EGLDisplay display, EGLSurface surface, EGLContext context,
                               const platform::LogCategory &category, const char *what,
                               const char *lostWhat) noexcept
{
    const EGLint err = makeCurrentUnlessCurrent(display, surface, context);
    if (err == EGL_SUCCESS)
        return ok();
    if (category.enabled(platform::LogLevel::Error))
        platform::logMessage(category, platform::LogLevel::Error,
                             "Failed to make the %s context current: %s", what, eglErrorName(err));
    if (isSurfaceGone(err))
        return unexpected(Errc::NoDevice, lostWhat);
    return unexpected(Errc::Io, "eglMakeCurrent failed");
}

void bindDrawTarget(GLuint fbo, hal::Size size) noexcept
{
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, size.width, size.height);
}

void destroyWindowContext(EGLDisplay display, EGLSurface surface, EGLContext context,
                          FrameCopy &copy) noexcept
{
    if (display == EGL_NO_DISPLAY)
        return;
    if (context != EGL_NO_CONTEXT) {
        if (copy.created() && eglMakeCurrent(display, surface, surface, context) == EGL_TRUE)
            copy.destroy();
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display, context);
    }
    if (surface != EGL_NO_SURFACE)
        eglDestroySurface(display, surface);
    releaseEglDisplay(display);
}

} // namespace depthtouch::drivers::egl
