#include "depthtouch/drivers/egl/egl_x11_display.h"

#include <cstdlib>
#include <mutex>
#include <vector>

#include <X11/Xatom.h>
#include <X11/Xlib.h>
#include <X11/Xutil.h>

#include "depthtouch/platform/log.h"
#include "egl_common.h"

DT_LOG_CATEGORY(Egl)

namespace depthtouch::drivers {

namespace {

constexpr const char *kWindowTitle = "DepthTouch";

/// X protocol errors (a request on a window the user destroyed, ...) end the process under Xlib's
/// default handler; here they are logged, and the events that follow them (DestroyNotify) or a
/// failing swap make the display Lost.
int onXError(Display *, XErrorEvent *e)
{
    DT_LOG(Egl, Warning, "X protocol error %d (request %d.%d, resource 0x%lx)",
           static_cast<int>(e->error_code), static_cast<int>(e->request_code),
           static_cast<int>(e->minor_code), e->resourceid);
    return 0;
}

/// Xlib's default I/O error handler ends the process before the per-display exit handler runs.
/// This one returns, so each connection's exit handler decides: ours marks the display Lost; the
/// default one of any other connection in the process still exits.
int onXIoError(Display *dpy)
{
    DT_LOG(Egl, Warning, "Lost the connection to X server '%s'", DisplayString(dpy));
    return 0;
}

std::once_flag gErrorHandlersOnce;

void installXErrorHandlers()
{
    std::call_once(gErrorHandlersOnce, [] {
        XSetErrorHandler(&onXError);
        XSetIOErrorHandler(&onXIoError);
    });
}

} // namespace

struct EglX11Display::X {
    ::Display *dpy = nullptr;
    ::Window window = 0;
    Colormap colormap = 0;
    Atom wmProtocols = 0;
    Atom wmDeleteWindow = 0;
    bool ioError = false;      ///< Set by the I/O error exit handler: the connection is gone.
    bool closedByUser = false; ///< WM_DELETE_WINDOW arrived.
    bool destroyed = false;    ///< DestroyNotify for the window arrived.

    EGLDisplay display = EGL_NO_DISPLAY;
    EGLSurface surface = EGL_NO_SURFACE;
    EGLContext context = EGL_NO_CONTEXT;
    egl::FrameCopy copy; ///< readback=1: the last presented frame.

    /// Called by Xlib on an I/O error of this connection (after the global I/O error handler);
    /// returning keeps the process alive, and Xlib leaves the connection unusable.
    static void onIoErrorExit(::Display *, void *self) { static_cast<X *>(self)->ioError = true; }

    void destroy() noexcept
    {
        if (display != EGL_NO_DISPLAY) {
            if (context != EGL_NO_CONTEXT) {
                if (copy.created() &&
                    eglMakeCurrent(display, surface, surface, context) == EGL_TRUE)
                    copy.destroy();
                eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
                eglDestroyContext(display, context);
            }
            if (surface != EGL_NO_SURFACE)
                eglDestroySurface(display, surface);
            egl::releaseEglDisplay(display);
        }
        context = EGL_NO_CONTEXT;
        surface = EGL_NO_SURFACE;
        display = EGL_NO_DISPLAY;
        if (dpy != nullptr) {
            if (!ioError) {
                if (window != 0 && !destroyed)
                    XDestroyWindow(dpy, window);
                if (colormap != 0)
                    XFreeColormap(dpy, colormap);
            }
            XCloseDisplay(dpy);
        }
        dpy = nullptr;
        window = 0;
        colormap = 0;
        ioError = false;
        closedByUser = false;
        destroyed = false;
        copy.forget();
    }
};

namespace {

/// \return the X display name of \a cfg: its device, else $DISPLAY; empty when neither is set.
std::string xDisplayNameOf(const hal::BackendConfig &cfg)
{
    if (!cfg.device.empty())
        return std::string(cfg.device);
    const char *env = std::getenv("DISPLAY");
    return env != nullptr ? std::string(env) : std::string();
}

/// Sets the window's WM_NORMAL_HINTS to a fixed size (the surface does not follow resizes).
void setFixedSize(::Display *dpy, ::Window window, int w, int h)
{
    XSizeHints *hints = XAllocSizeHints();
    if (hints == nullptr)
        return;
    hints->flags = PMinSize | PMaxSize;
    hints->min_width = hints->max_width = w;
    hints->min_height = hints->max_height = h;
    XSetWMNormalHints(dpy, window, hints);
    XFree(hints);
}

/// Asks the window manager (EWMH) to show the window full screen, without decorations.
void setFullscreen(::Display *dpy, ::Window window)
{
    const Atom state = XInternAtom(dpy, "_NET_WM_STATE", False);
    Atom fullscreen = XInternAtom(dpy, "_NET_WM_STATE_FULLSCREEN", False);
    XChangeProperty(dpy, window, state, XA_ATOM, 32, PropModeReplace,
                    reinterpret_cast<unsigned char *>(&fullscreen), 1);
}

} // namespace

Result<std::unique_ptr<hal::Display>> EglX11Display::create(const hal::BackendConfig &cfg)
{
    auto settings = EglDisplaySettings::parse(cfg.options, /*window=*/true);
    if (!settings)
        return unexpected(settings.error());
    // Probe the server now, quietly: autoprobe on a machine without a screen moves on.
    std::string name = xDisplayNameOf(cfg);
    if (name.empty())
        return unexpected(Errc::NoDevice, "No X server: $DISPLAY is not set");
    ::Display *dpy = XOpenDisplay(name.c_str());
    if (dpy == nullptr) {
        DT_LOG(Egl, Debug, "Failed to connect to X server '%s'", name.c_str());
        return unexpected(Errc::NoDevice, "No X server: cannot connect to $DISPLAY");
    }
    auto display = egl::acquireEglDisplay(EGL_PLATFORM_X11_KHR, dpy);
    if (display)
        egl::releaseEglDisplay(*display);
    XCloseDisplay(dpy);
    if (!display)
        return unexpected(display.error());
    return std::unique_ptr<hal::Display>(
        std::make_unique<EglX11Display>(cfg.clockRef(), *settings, std::move(name)));
}

EglX11Display::EglX11Display(platform::Clock &clock, const EglDisplaySettings &settings,
                             std::string xDisplayName)
    : clock_(clock), settings_(settings), xDisplayName_(std::move(xDisplayName)),
      x_(std::make_unique<X>())
{
    caps_.hasGlesContext = true;
    caps_.offscreen = false;
    caps_.readback = settings_.readback;
}

EglX11Display::~EglX11Display()
{
    close();
}

Result<void> EglX11Display::openDevice(const hal::DisplayConfig &cfg)
{
    auto resolved = resolveWindowConfig(cfg, settings_);
    if (!resolved)
        return unexpected(resolved.error());

    installXErrorHandlers();
    X &x = *x_;
    x.dpy = XOpenDisplay(xDisplayName_.c_str());
    if (x.dpy == nullptr) {
        DT_LOG(Egl, Error, "Failed to connect to X server '%s'", xDisplayName_.c_str());
        return unexpected(Errc::NoDevice, "No X server: cannot connect to $DISPLAY");
    }
    XSetIOErrorExitHandler(x.dpy, &X::onIoErrorExit, &x);

    auto display = egl::acquireEglDisplay(EGL_PLATFORM_X11_KHR, x.dpy);
    if (!display) {
        x.destroy();
        return unexpected(display.error());
    }
    x.display = *display;
    // The default visual (24-bit, no alpha) first: a 32-bit ARGB one would let a compositing
    // desktop blend the window with what is behind it.
    const int screen = DefaultScreen(x.dpy);
    auto config =
        egl::chooseConfig(x.display, EGL_WINDOW_BIT,
                          static_cast<EGLint>(XVisualIDFromVisual(DefaultVisual(x.dpy, screen))));
    if (!config)
        config = egl::chooseConfig(x.display, EGL_WINDOW_BIT, 0);
    if (!config) {
        x.destroy();
        return unexpected(config.error());
    }
    EGLint visualId = 0;
    eglGetConfigAttrib(x.display, *config, EGL_NATIVE_VISUAL_ID, &visualId);
    XVisualInfo wanted{};
    wanted.visualid = static_cast<VisualID>(visualId);
    int visualCount = 0;
    XVisualInfo *visual = XGetVisualInfo(x.dpy, VisualIDMask, &wanted, &visualCount);
    if (visual == nullptr || visualCount < 1) {
        DT_LOG(Egl, Error, "Failed to find X visual 0x%x of the EGL config", visualId);
        x.destroy();
        return unexpected(Errc::NotSupported, "No X visual for the EGL config");
    }

    const ::Window root = RootWindow(x.dpy, screen);
    int w = resolved->width;
    int h = resolved->height;
    if (settings_.fullscreen) {
        w = DisplayWidth(x.dpy, screen);
        h = DisplayHeight(x.dpy, screen);
    }
    x.colormap = XCreateColormap(x.dpy, root, visual->visual, AllocNone);
    XSetWindowAttributes attrs{};
    attrs.colormap = x.colormap;
    attrs.background_pixel = 0; // black until the first frame
    attrs.border_pixel = 0;
    attrs.event_mask = StructureNotifyMask;
    x.window = XCreateWindow(x.dpy, root, 0, 0, static_cast<unsigned>(w), static_cast<unsigned>(h),
                             0, visual->depth, InputOutput, visual->visual,
                             CWColormap | CWBackPixel | CWBorderPixel | CWEventMask, &attrs);
    XFree(visual);
    XStoreName(x.dpy, x.window, kWindowTitle);
    XClassHint classHint{};
    char resName[] = "depthtouch";
    char resClass[] = "DepthTouch";
    classHint.res_name = resName;
    classHint.res_class = resClass;
    XSetClassHint(x.dpy, x.window, &classHint);
    x.wmProtocols = XInternAtom(x.dpy, "WM_PROTOCOLS", False);
    x.wmDeleteWindow = XInternAtom(x.dpy, "WM_DELETE_WINDOW", False);
    XSetWMProtocols(x.dpy, x.window, &x.wmDeleteWindow, 1);
    if (settings_.fullscreen)
        setFullscreen(x.dpy, x.window);
    else
        setFixedSize(x.dpy, x.window, w, h);
    XMapWindow(x.dpy, x.window);
    XSync(x.dpy, False);
    if (x.ioError) {
        x.destroy();
        return unexpected(Errc::NoDevice, "Lost the X server while creating the window");
    }

    auto createSurface = reinterpret_cast<PFNEGLCREATEPLATFORMWINDOWSURFACEEXTPROC>(
        eglGetProcAddress("eglCreatePlatformWindowSurfaceEXT"));
    ::Window nativeWindow = x.window;
    x.surface = createSurface != nullptr
                    ? createSurface(x.display, *config, &nativeWindow, nullptr)
                    : eglCreateWindowSurface(x.display, *config,
                                             static_cast<EGLNativeWindowType>(x.window), nullptr);
    if (x.surface == EGL_NO_SURFACE) {
        DT_LOG(Egl, Error, "Failed to create an EGL window surface: %s",
               egl::eglErrorName(eglGetError()));
        x.destroy();
        return unexpected(Errc::NotSupported, "Failed to create an EGL window surface");
    }
    auto context = egl::createGles3Context(x.display, *config);
    if (!context) {
        x.destroy();
        return unexpected(context.error());
    }
    x.context = *context;
    if (eglMakeCurrent(x.display, x.surface, x.surface, x.context) == EGL_FALSE) {
        DT_LOG(Egl, Error, "Failed to make the X11 window context current: %s",
               egl::eglErrorName(eglGetError()));
        x.destroy();
        return unexpected(Errc::NotSupported, "X11 window context cannot be made current");
    }

    // A server on a GPU then holds swaps until its vertical blank; Xvfb and Mesa's software path
    // accept the interval and ignore it, and present() paces those frames itself.
    if (eglSwapInterval(x.display, settings_.swapInterval) == EGL_FALSE)
        DT_LOG(Egl, Warning, "Failed to set swap interval %d: %s", settings_.swapInterval,
               egl::eglErrorName(eglGetError()));

    if (settings_.readback) {
        if (auto r = x.copy.create({w, h}); !r) {
            x.destroy();
            return r;
        }
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, w, h);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    DT_LOG(Egl, Info, "X11 %s %dx%d on '%s' at %.3g Hz, swap interval %d, on %s",
           settings_.fullscreen ? "full-screen window" : "window", w, h, xDisplayName_.c_str(),
           resolved->refreshHz, settings_.swapInterval,
           reinterpret_cast<const char *>(glGetString(GL_RENDERER)));
    // The context belongs to the render thread, which binds it with makeCurrent(): release it
    // here so that open() may run on another thread.
    eglMakeCurrent(x.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);

    size_ = {w, h};
    refreshHz_ = resolved->refreshHz;
    pacer_.start(clock_.now(), refreshHz_);
    return ok();
}

void EglX11Display::closeDevice() noexcept
{
    x_->destroy();
}

unsigned long EglX11Display::window() const noexcept
{
    return state() == State::Closed ? 0ul : x_->window;
}

void EglX11Display::lose(const char *why) noexcept
{
    if (state() != State::Open)
        return;
    DT_LOG(Egl, Warning, "X11 display lost: %s", why);
    markLost();
}

void EglX11Display::pumpEvents() noexcept
{
    X &x = *x_;
    // XPending() flushes, reads what arrived and notices a broken connection (ioError).
    while (!x.ioError && XPending(x.dpy) > 0) {
        XEvent ev;
        XNextEvent(x.dpy, &ev);
        if (ev.type == ClientMessage && ev.xclient.message_type == x.wmProtocols &&
            static_cast<Atom>(ev.xclient.data.l[0]) == x.wmDeleteWindow)
            x.closedByUser = true;
        else if (ev.type == DestroyNotify && ev.xdestroywindow.window == x.window)
            x.destroyed = true;
    }
    if (x.ioError)
        lose("the connection to the X server was lost");
    else if (x.destroyed)
        lose("the window was destroyed");
    else if (x.closedByUser)
        lose("the window was closed");
}

Result<void> EglX11Display::ensureCurrent()
{
    pumpEvents();
    if (state() == State::Lost)
        return unexpected(Errc::NoDevice, "X11 display lost (window closed or X server gone)");
    X &x = *x_;
    if (eglGetCurrentContext() == x.context)
        return ok();
    if (eglMakeCurrent(x.display, x.surface, x.surface, x.context) == EGL_FALSE) {
        const EGLint err = eglGetError();
        DT_LOG(Egl, Error, "Failed to make the X11 window context current: %s",
               egl::eglErrorName(err));
        if (err == EGL_CONTEXT_LOST || err == EGL_BAD_NATIVE_WINDOW || err == EGL_BAD_SURFACE) {
            lose("the window surface is gone");
            return unexpected(Errc::NoDevice, "X11 window surface lost");
        }
        return unexpected(Errc::Io, "eglMakeCurrent failed");
    }
    return ok();
}

Result<void> EglX11Display::makeCurrentDevice()
{
    DT_TRY(ensureCurrent());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, size_.width, size_.height);
    return ok();
}

Result<hal::PresentInfo> EglX11Display::presentDevice()
{
    DT_TRY(ensureCurrent());
    X &x = *x_;
    x.copy.keep(size_);
    if (eglSwapBuffers(x.display, x.surface) == EGL_FALSE) {
        const EGLint err = eglGetError();
        pumpEvents();
        if (state() == State::Open && (err == EGL_BAD_NATIVE_WINDOW || err == EGL_BAD_SURFACE ||
                                      err == EGL_CONTEXT_LOST || err == EGL_BAD_ALLOC))
            lose("the window surface is gone");
        DT_LOG(Egl, Error, "Failed to swap the X11 window buffers: %s", egl::eglErrorName(err));
        if (state() == State::Lost)
            return unexpected(Errc::NoDevice, "X11 display lost (window closed or X server gone)");
        return unexpected(Errc::Io, "eglSwapBuffers failed");
    }
    // A swap to a connection that broke meanwhile "succeeds": look before reporting the frame.
    pumpEvents();
    if (state() == State::Lost)
        return unexpected(Errc::NoDevice, "X11 display lost (window closed or X server gone)");
    x.copy.markPresented();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return pacer_.follow(clock_, static_cast<unsigned>(settings_.swapInterval));
}

Result<void> EglX11Display::readPixelsDevice(const hal::ImageView &out)
{
    DT_TRY(ensureCurrent());
    return x_->copy.read(out, size_);
}

} // namespace depthtouch::drivers
