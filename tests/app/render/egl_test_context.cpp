#include "app/render/egl_test_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>

#include <cstring>

namespace depthtouch::test {

namespace {

bool hasExtension(const char *list, const char *name)
{
    if (list == nullptr)
        return false;
    const std::size_t n = std::strlen(name);
    for (const char *p = std::strstr(list, name); p != nullptr; p = std::strstr(p + n, name))
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return true;
    return false;
}

} // namespace

std::unique_ptr<EglTestContext> EglTestContext::create(std::string &why)
{
    const char *clientExts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!hasExtension(clientExts, "EGL_MESA_platform_surfaceless")) {
        why = "EGL_MESA_platform_surfaceless unsupported";
        return nullptr;
    }
    auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (getPlatformDisplay == nullptr) {
        why = "eglGetPlatformDisplayEXT missing";
        return nullptr;
    }
    EGLDisplay dpy =
        getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0;
    EGLint minor = 0;
    if (dpy == EGL_NO_DISPLAY || eglInitialize(dpy, &major, &minor) != EGL_TRUE) {
        why = "eglInitialize failed on the surfaceless platform";
        return nullptr;
    }
    std::unique_ptr<EglTestContext> ctx(new EglTestContext);
    ctx->display_ = dpy;
    if (eglBindAPI(EGL_OPENGL_ES_API) != EGL_TRUE) {
        why = "eglBindAPI(EGL_OPENGL_ES_API) failed";
        return nullptr;
    }
    const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT, EGL_SURFACE_TYPE, 0,
                                    EGL_NONE};
    EGLConfig config = nullptr;
    EGLint count = 0;
    const bool haveConfig =
        eglChooseConfig(dpy, configAttribs, &config, 1, &count) == EGL_TRUE && count > 0;
    const bool noConfig =
        hasExtension(eglQueryString(dpy, EGL_EXTENSIONS), "EGL_KHR_no_config_context");
    if (!haveConfig && !noConfig) {
        why = "no EGL config for GLES 3";
        return nullptr;
    }
    const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 0,
                                     EGL_NONE};
    EGLContext context = eglCreateContext(dpy, haveConfig ? config : EGL_NO_CONFIG_KHR,
                                          EGL_NO_CONTEXT, contextAttribs);
    if (context == EGL_NO_CONTEXT) {
        why = "eglCreateContext(GLES 3) failed";
        return nullptr;
    }
    ctx->context_ = context;
    if (eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, context) != EGL_TRUE) {
        why = "eglMakeCurrent without a surface failed";
        return nullptr;
    }
    return ctx;
}

EglTestContext::~EglTestContext()
{
    if (display_ == nullptr)
        return;
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_ != nullptr)
        eglDestroyContext(display_, context_);
    eglTerminate(display_);
}

std::string EglTestContext::renderer() const
{
    const auto *s = reinterpret_cast<const char *>(glGetString(GL_RENDERER));
    return s != nullptr ? s : "";
}

} // namespace depthtouch::test
