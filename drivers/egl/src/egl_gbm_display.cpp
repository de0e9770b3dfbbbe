#include "depthtouch/drivers/egl/egl_gbm_display.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include <gbm.h>
#include <xf86drm.h>
#include <xf86drmMode.h>

#include "depthtouch/drivers/common/backend_options.h"
#include "depthtouch/drivers/egl/display_settings.h"
#include "depthtouch/drivers/egl/kms_output.h"
#include "depthtouch/drivers/egl/kms_scanout.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/unique_fd.h"
#include "egl_common.h"
#include "libdrm_kms.h"

DT_LOG_CATEGORY(Kms)

namespace depthtouch::drivers {

namespace {

/// Discovery limited to one card path (option `card`, BackendConfig::device).
class OneCardApi final : public DrmApi {
public:
    OneCardApi(std::unique_ptr<DrmApi> api, std::string path)
        : api_(std::move(api)), path_(std::move(path))
    {
    }
    std::vector<std::string> listCards() override
    {
        // A missing path is "no card", as discovery without /dev/dri.
        if (::access(path_.c_str(), F_OK) != 0)
            return {};
        return {path_};
    }
    Result<DrmCardInfo> probeCard(const std::string &path) override
    {
        return api_->probeCard(path);
    }

private:
    std::unique_ptr<DrmApi> api_;
    std::string path_;
};

std::unique_ptr<DrmApi> makeDrmApi(const std::string &card)
{
    std::unique_ptr<DrmApi> api = makeLibdrmApi();
    if (!card.empty())
        api = std::make_unique<OneCardApi>(std::move(api), card);
    return api;
}

/// The DRM framebuffer cached on a gbm_bo, removed with it.
struct BoFramebuffer {
    int fd;
    std::uint32_t id;
};

void destroyBoFramebuffer(gbm_bo *, void *data)
{
    auto *fb = static_cast<BoFramebuffer *>(data);
    if (fb->id != 0)
        drmModeRmFB(fb->fd, fb->id);
    delete fb;
}

/// ScanoutBufferSource on a GBM surface: buffers are gbm_bo, locked with
/// gbm_surface_lock_front_buffer() after eglSwapBuffers().
class GbmBufferSource final : public ScanoutBufferSource {
public:
    GbmBufferSource(int fd, gbm_surface *surface) : fd_(fd), surface_(surface) {}

    Result<ScanoutBuffer> lockFront() override
    {
        gbm_bo *bo = gbm_surface_lock_front_buffer(surface_);
        if (bo == nullptr)
            return unexpected(Errc::OutOfResources, "gbm_surface_lock_front_buffer failed");
        ScanoutBuffer b;
        b.id = reinterpret_cast<std::uintptr_t>(bo);
        b.width = gbm_bo_get_width(bo);
        b.height = gbm_bo_get_height(bo);
        b.format = gbm_bo_get_format(bo);
        const int planes = gbm_bo_get_plane_count(bo);
        b.planes = static_cast<std::uint32_t>(planes >= 1 && planes <= 4 ? planes : 1);
        for (std::uint32_t i = 0; i < b.planes; ++i) {
            const int plane = static_cast<int>(i);
            b.handles[i] = gbm_bo_get_handle_for_plane(bo, plane).u32;
            b.strides[i] = gbm_bo_get_stride_for_plane(bo, plane);
            b.offsets[i] = gbm_bo_get_offset(bo, plane);
        }
        b.modifier = gbm_bo_get_modifier(bo);
        if (const auto *fb = static_cast<const BoFramebuffer *>(gbm_bo_get_user_data(bo)))
            b.framebuffer = fb->id;
        return b;
    }

    void release(std::uintptr_t id) noexcept override
    {
        gbm_surface_release_buffer(surface_, reinterpret_cast<gbm_bo *>(id));
    }

    void cacheFramebuffer(std::uintptr_t id, std::uint32_t framebuffer) override
    {
        gbm_bo_set_user_data(reinterpret_cast<gbm_bo *>(id), new BoFramebuffer{fd_, framebuffer},
                             &destroyBoFramebuffer);
    }

private:
    int fd_;
    gbm_surface *surface_;
};

} // namespace

struct EglGbmDisplay::Kms {
    platform::UniqueFd fd;
    bool master = false;
    gbm_device *gbm = nullptr;
    gbm_surface *surface = nullptr;
    std::unique_ptr<KmsDevice> device;
    std::unique_ptr<GbmBufferSource> source;
    std::unique_ptr<KmsScanout> scanout;

    EGLDisplay display = EGL_NO_DISPLAY;
    EGLSurface eglSurface = EGL_NO_SURFACE;
    EGLContext context = EGL_NO_CONTEXT;
    egl::FrameCopy copy; ///< readback=1: the last presented frame.

    /// Undoes open() in reverse, whatever part of it was done.
    void destroy() noexcept
    {
        // The saved CRTC state goes back first: our buffers must be off screen before they are
        // released and their framebuffers removed.
        if (scanout)
            scanout->end();
        egl::destroyWindowContext(display, eglSurface, context, copy);
        display = EGL_NO_DISPLAY;
        eglSurface = EGL_NO_SURFACE;
        context = EGL_NO_CONTEXT;
        scanout.reset();
        source.reset();
        device.reset();
        if (surface != nullptr)
            gbm_surface_destroy(surface); // removes the buffers' DRM framebuffers
        surface = nullptr;
        if (gbm != nullptr)
            gbm_device_destroy(gbm);
        gbm = nullptr;
        if (master && fd)
            drmDropMaster(fd.get());
        master = false;
        fd.reset();
        copy.forget();
    }
};

Result<EglGbmDisplay::Settings> EglGbmDisplay::Settings::parse(const hal::BackendConfig &cfg)
{
    static constexpr const char *kKeys[] = {"mode", "card", "readback"};
    DT_TRY(rejectUnknownOptions(cfg.options, kKeys, std::size(kKeys),
                                "Unknown kms display option (known: mode, card, readback)"));
    Settings s;
    s.mode = std::string(cfg.options.find("mode").value_or(std::string_view()));
    if (!parseModeSpec(s.mode))
        return unexpected(Errc::InvalidArgument,
                          "Malformed kms mode (CONNECTOR, WxH[@HZ] or CONNECTOR:WxH[@HZ])");
    s.card = std::string(cfg.options.find("card").value_or(cfg.device));
    auto readback = cfg.options.getBool("readback", false);
    if (!readback)
        return unexpected(readback.error());
    s.readback = *readback;
    return s;
}

Result<std::unique_ptr<hal::Display>> EglGbmDisplay::create(const hal::BackendConfig &cfg)
{
    auto settings = Settings::parse(cfg);
    if (!settings)
        return unexpected(settings.error());
    std::unique_ptr<DrmApi> api = makeDrmApi(settings->card);
    auto selection = selectKmsScreenMode(*api, {}, settings->mode);
    if (!selection)
        return unexpected(selection.error());
    // Taking DRM master fails while an X server or a compositor runs on the card: then autoprobe
    // moves on (to x11 on such a desktop).
    platform::UniqueFd fd(::open(selection->card.path.c_str(), O_RDWR | O_CLOEXEC));
    if (!fd)
        return unexpected(Errc::NoDevice, "Failed to open the DRM device", errno);
    const bool wasMaster = drmIsMaster(fd.get()) != 0;
    if (auto m = kms::becomeMaster(fd.get()); !m)
        return unexpected(m.error());
    if (!wasMaster)
        drmDropMaster(fd.get());
    return std::unique_ptr<hal::Display>(
        std::make_unique<EglGbmDisplay>(cfg.clockRef(), std::move(*settings)));
}

EglGbmDisplay::EglGbmDisplay(platform::Clock &clock, Settings settings)
    : clock_(clock), settings_(std::move(settings)), kms_(std::make_unique<Kms>())
{
    caps_.hasGlesContext = true;
    caps_.offscreen = false;
    caps_.readback = settings_.readback;
}

EglGbmDisplay::~EglGbmDisplay()
{
    close();
}

Result<void> EglGbmDisplay::openDevice(const hal::DisplayConfig &cfg)
{
    auto r = openOutput(cfg);
    if (!r) {
        kms_->destroy(); // restores the CRTC when it was saved
        return r;
    }
    frames_ = 0;
    return ok();
}

Result<void> EglGbmDisplay::openOutput(const hal::DisplayConfig &cfg)
{
    std::unique_ptr<DrmApi> api = makeDrmApi(settings_.card);
    auto sel = selectKmsScreenMode(*api, cfg, settings_.mode);
    if (!sel)
        return unexpected(sel.error());
    const DrmConnectorInfo &connector = sel->connectorInfo();
    const DrmModeInfo &mode = sel->modeInfo();
    Kms &k = *kms_;

    k.fd.reset(::open(sel->card.path.c_str(), O_RDWR | O_CLOEXEC));
    if (!k.fd) {
        DT_LOG(Kms, Error, "Failed to open %s: %s", sel->card.path.c_str(), std::strerror(errno));
        return unexpected(Errc::NoDevice, "Failed to open the DRM device", errno);
    }
    DT_TRY(kms::becomeMaster(k.fd.get()));
    k.master = true;
    auto crtc = kms::findCrtc(k.fd.get(), connector.id);
    if (!crtc)
        return unexpected(crtc.error());

    const auto w = static_cast<std::uint32_t>(mode.width);
    const auto h = static_cast<std::uint32_t>(mode.height);
    k.gbm = gbm_create_device(k.fd.get());
    if (k.gbm == nullptr)
        return unexpected(Errc::NoDevice, "Failed to create a GBM device", errno);
    k.surface = gbm_surface_create(k.gbm, w, h, GBM_FORMAT_XRGB8888,
                                   GBM_BO_USE_SCANOUT | GBM_BO_USE_RENDERING);
    if (k.surface == nullptr) {
        DT_LOG(Kms, Error, "Failed to create a %ux%u XRGB8888 GBM surface", w, h);
        return unexpected(Errc::NotSupported, "Failed to create a GBM scan-out surface", errno);
    }
    k.device = kms::makeLibdrmKmsDevice(k.fd.get());
    k.source = std::make_unique<GbmBufferSource>(k.fd.get(), k.surface);
    k.scanout = std::make_unique<KmsScanout>(*k.device, *k.source, clock_,
                                             platform::SteadyClock::instance());
    KmsScanoutConfig sc;
    sc.crtcId = *crtc;
    sc.connectorId = connector.id;
    sc.mode = mode;
    DT_TRY(k.scanout->begin(sc));

    auto display = egl::acquireEglDisplay(EGL_PLATFORM_GBM_KHR, k.gbm);
    if (!display)
        return unexpected(display.error());
    k.display = *display;
    auto config = egl::chooseConfig(k.display, EGL_WINDOW_BIT, GBM_FORMAT_XRGB8888);
    if (!config)
        return unexpected(config.error());
    // EGL_KHR_platform_gbm: the native window is the gbm_surface itself.
    k.eglSurface = egl::createWindowSurface(k.display, *config, k.surface, k.surface);
    if (k.eglSurface == EGL_NO_SURFACE) {
        DT_LOG(Kms, Error, "Failed to create an EGL window surface on the GBM surface: %s",
               egl::eglErrorName(eglGetError()));
        return unexpected(Errc::NotSupported, "Failed to create an EGL surface on GBM");
    }
    auto context = egl::createGles3Context(k.display, *config);
    if (!context)
        return unexpected(context.error());
    k.context = *context;
    if (eglMakeCurrent(k.display, k.eglSurface, k.eglSurface, k.context) == EGL_FALSE) {
        DT_LOG(Kms, Error, "Failed to make the GBM surface context current: %s",
               egl::eglErrorName(eglGetError()));
        return unexpected(Errc::NotSupported, "GBM surface context cannot be made current");
    }
    const int width = mode.width;
    const int height = mode.height;
    if (settings_.readback) {
        if (auto r = k.copy.create({width, height}); !r)
            return r;
    }
    // A black first frame sets the mode now, so that a mode the sink refuses fails open().
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, width, height);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    if (eglSwapBuffers(k.display, k.eglSurface) == EGL_FALSE) {
        DT_LOG(Kms, Error, "Failed to swap the GBM surface: %s", egl::eglErrorName(eglGetError()));
        return unexpected(Errc::NotSupported, "eglSwapBuffers failed on the GBM surface");
    }
    if (auto first = k.scanout->present(); !first) {
        if (first.error().sysErrno == EINVAL)
            return unexpected(Errc::NotSupported, "The display refused the mode",
                              first.error().sysErrno);
        return unexpected(first.error());
    }
    DT_LOG(Kms, Info, "KMS %s on %s (CRTC %u): %dx%d at %.3g Hz on %s", connector.name.c_str(),
           sel->card.path.c_str(), *crtc, width, height, mode.refreshHz,
           reinterpret_cast<const char *>(glGetString(GL_RENDERER)));
    // The context belongs to the render thread, which binds it with makeCurrent().
    eglMakeCurrent(k.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    size_ = {width, height};
    refreshHz_ = mode.refreshHz;
    return ok();
}

void EglGbmDisplay::closeDevice() noexcept
{
    kms_->destroy();
}

void EglGbmDisplay::lose(const char *why) noexcept
{
    if (state() != State::Open)
        return;
    DT_LOG(Kms, Warning, "KMS display lost: %s", why);
    markLost();
}

Result<void> EglGbmDisplay::ensureCurrent()
{
    Kms &k = *kms_;
    auto current = egl::makeWindowCurrent(k.display, k.eglSurface, k.context, kLogCategoryKms,
                                          "GBM surface", "KMS display lost (EGL context gone)");
    if (!current && current.error().code == Errc::NoDevice)
        lose("the EGL context or surface is gone");
    return current;
}

Result<hal::PresentInfo> EglGbmDisplay::presentDevice()
{
    DT_TRY(ensureCurrent());
    Kms &k = *kms_;
    k.copy.keep(size_);
    if (eglSwapBuffers(k.display, k.eglSurface) == EGL_FALSE) {
        const EGLint err = eglGetError();
        DT_LOG(Kms, Error, "Failed to swap the GBM surface: %s", egl::eglErrorName(err));
        if (egl::isSurfaceGone(err)) {
            lose("the EGL context or surface is gone");
            return unexpected(Errc::NoDevice, "KMS display lost (EGL context gone)");
        }
        return unexpected(Errc::Io, "eglSwapBuffers failed");
    }
    auto shown = k.scanout->present();
    if (!shown) {
        if (k.scanout->state() == KmsScanout::State::Lost)
            lose(shown.error().what);
        return unexpected(shown.error());
    }
    k.copy.markPresented();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    hal::PresentInfo info = *shown;
    info.frameCounter = ++frames_; // the black frame of open() does not count
    return info;
}

egl::FrameCopy &EglGbmDisplay::frameCopy() noexcept
{
    return kms_->copy;
}

} // namespace depthtouch::drivers
