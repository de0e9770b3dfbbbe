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

    /// Connects to X server \a name and gets its EGL display. Errors: NoDevice, and EGL's.
    Result<void> connect(const std::string &name);
    /// \return an EGL window config, of the screen's default visual when one fits.
    Result<EGLConfig> chooseConfig();
    /// \return the X visual of \a config (XFree() it). Errors: NotSupported.
    Result<XVisualInfo *> visualOf(EGLConfig config);
    /// \brief Creates the window for \a config, of \a size or covering the screen, and waits for
    /// the server to map it. \return the window's size. Errors: NotSupported, NoDevice.
    Result<hal::Size> createWindow(EGLConfig config, hal::Size size, bool fullscreen);
    /// Sets the window's title, class, WM_DELETE_WINDOW protocol and size or full-screen state.
    void setWindowProperties(hal::Size size, bool fullscreen);
    /// Creates the EGL window surface and the GLES 3 context, and makes them current.
    Result<void> createContext(EGLConfig config);

    void destroy() noexcept
    {
        egl::destroyWindowContext(display, surface, context, copy);
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

Result<void> EglX11Display::X::connect(const std::string &name)
{
    dpy = XOpenDisplay(name.c_str());
    if (dpy == nullptr) {
        DT_LOG(Egl, Error, "Failed to connect to X server '%s'", name.c_str());
        return unexpected(Errc::NoDevice, "No X server: cannot connect to $DISPLAY");
    }
    XSetIOErrorExitHandler(dpy, &X::onIoErrorExit, this);
    auto eglDisplay = egl::acquireEglDisplay(EGL_PLATFORM_X11_KHR, dpy);
    if (!eglDisplay)
        return unexpected(eglDisplay.error());
    display = *eglDisplay;
    return ok();
}

Result<EGLConfig> EglX11Display::X::chooseConfig()
{
    // The default visual (24-bit, no alpha) first: a 32-bit ARGB one would let a compositing
    // desktop blend the window with what is behind it.
    const int screen = DefaultScreen(dpy);
    auto config =
        egl::chooseConfig(display, EGL_WINDOW_BIT,
                          static_cast<EGLint>(XVisualIDFromVisual(DefaultVisual(dpy, screen))));
    if (!config)
        config = egl::chooseConfig(display, EGL_WINDOW_BIT, 0);
    return config;
}

Result<XVisualInfo *> EglX11Display::X::visualOf(EGLConfig config)
{
    EGLint visualId = 0;
    eglGetConfigAttrib(display, config, EGL_NATIVE_VISUAL_ID, &visualId);
    XVisualInfo wanted{};
    wanted.visualid = static_cast<VisualID>(visualId);
    int visualCount = 0;
    XVisualInfo *visual = XGetVisualInfo(dpy, VisualIDMask, &wanted, &visualCount);
    if (visual == nullptr || visualCount < 1) {
        DT_LOG(Egl, Error, "Failed to find X visual 0x%x of the EGL config", visualId);
        return unexpected(Errc::NotSupported, "No X visual for the EGL config");
    }
    return visual;
}

Result<hal::Size> EglX11Display::X::createWindow(EGLConfig config, hal::Size size, bool fullscreen)
{
    auto visual = visualOf(config);
    if (!visual)
        return unexpected(visual.error());
    const int screen = DefaultScreen(dpy);
    const ::Window root = RootWindow(dpy, screen);
    if (fullscreen)
        size = {DisplayWidth(dpy, screen), DisplayHeight(dpy, screen)};
    colormap = XCreateColormap(dpy, root, (*visual)->visual, AllocNone);
    XSetWindowAttributes attrs{};
    attrs.colormap = colormap;
    attrs.background_pixel = 0; // black until the first frame
    attrs.border_pixel = 0;
    attrs.event_mask = StructureNotifyMask;
    window = XCreateWindow(dpy, root, 0, 0, static_cast<unsigned>(size.width),
                           static_cast<unsigned>(size.height), 0, (*visual)->depth, InputOutput,
                           (*visual)->visual,
                           CWColormap | CWBackPixel | CWBorderPixel | CWEventMask, &attrs);
    XFree(*visual);
    setWindowProperties(size, fullscreen);
    XMapWindow(dpy, window);
    XSync(dpy, False);
    if (ioError)
        return unexpected(Errc::NoDevice, "Lost the X server while creating the window");
    return size;
}

void EglX11Display::X::setWindowProperties(hal::Size size, bool fullscreen)
{
    XStoreName(dpy, window, kWindowTitle);
    XClassHint classHint{};
    char resName[] = "depthtouch";
    char resClass[] = "DepthTouch";
    classHint.res_name = resName;
    classHint.res_class = resClass;
    XSetClassHint(dpy, window, &classHint);
    wmProtocols = XInternAtom(dpy, "WM_PROTOCOLS", False);
    wmDeleteWindow = XInternAtom(dpy, "WM_DELETE_WINDOW", False);
    XSetWMProtocols(dpy, window, &wmDeleteWindow, 1);
    if (fullscreen)
        setFullscreen(dpy, window);
    else
        setFixedSize(dpy, window, size.width, size.height);
}

Result<void> EglX11Display::X::createContext(EGLConfig config)
{
    ::Window nativeWindow = window;
    surface =
        egl::createWindowSurface(display, config, &nativeWindow, reinterpret_cast<void *>(window));
    if (surface == EGL_NO_SURFACE) {
        DT_LOG(Egl, Error, "Failed to create an EGL window surface: %s",
               egl::eglErrorName(eglGetError()));
        return unexpected(Errc::NotSupported, "Failed to create an EGL window surface");
    }
    auto created = egl::createGles3Context(display, config);
    if (!created)
        return unexpected(created.error());
    context = *created;
    if (eglMakeCurrent(display, surface, surface, context) == EGL_FALSE) {
        DT_LOG(Egl, Error, "Failed to make the X11 window context current: %s",
               egl::eglErrorName(eglGetError()));
        return unexpected(Errc::NotSupported, "X11 window context cannot be made current");
    }
    return ok();
}

Result<void> EglX11Display::openDevice(const hal::DisplayConfig &cfg)
{
    auto resolved = resolveWindowConfig(cfg, settings_);
    if (!resolved)
        return unexpected(resolved.error());
    installXErrorHandlers();
    // A step that fails leaves what it made in x_, released here (no-op when nothing was made).
    auto size = openWindow(*resolved);
    if (!size) {
        x_->destroy();
        return unexpected(size.error());
    }
    size_ = *size;
    refreshHz_ = resolved->refreshHz;
    pacer_.start(clock_.now(), refreshHz_);
    return ok();
}

Result<hal::Size> EglX11Display::openWindow(const EglDisplaySettings &resolved)
{
    X &x = *x_;
    DT_TRY(x.connect(xDisplayName_));
    auto config = x.chooseConfig();
    if (!config)
        return unexpected(config.error());
    auto size = x.createWindow(*config, {resolved.width, resolved.height}, settings_.fullscreen);
    if (!size)
        return unexpected(size.error());
    DT_TRY(x.createContext(*config));

    // A server on a GPU then holds swaps until its vertical blank; Xvfb and Mesa's software path
    // accept the interval and ignore it, and present() paces those frames itself.
    if (eglSwapInterval(x.display, settings_.swapInterval) == EGL_FALSE)
        DT_LOG(Egl, Warning, "Failed to set swap interval %d: %s", settings_.swapInterval,
               egl::eglErrorName(eglGetError()));

    if (settings_.readback)
        DT_TRY(x.copy.create(*size));
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, size->width, size->height);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    DT_LOG(Egl, Info, "X11 %s %dx%d on '%s' at %.3g Hz, swap interval %d, on %s",
           settings_.fullscreen ? "full-screen window" : "window", size->width, size->height,
           xDisplayName_.c_str(), resolved.refreshHz, settings_.swapInterval,
           reinterpret_cast<const char *>(glGetString(GL_RENDERER)));
    // The context belongs to the render thread, which binds it with makeCurrent(): release it
    // here so that open() may run on another thread.
    eglMakeCurrent(x.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    return size;
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
    auto current = egl::makeWindowCurrent(x.display, x.surface, x.context, kLogCategoryEgl,
                                          "X11 window", "X11 window surface lost");
    if (!current && current.error().code == Errc::NoDevice)
        lose("the window surface is gone");
    return current;
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

egl::FrameCopy &EglX11Display::frameCopy() noexcept
{
    return x_->copy;
}

} // namespace depthtouch::drivers
