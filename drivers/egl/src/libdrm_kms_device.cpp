// KmsDevice on libdrm, the CRTC of a connector and DRM master (the real DRM side of the kms
// display's scan-out).
#include "libdrm_kms.h"

#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <vector>

#include <drm_fourcc.h>
#include <xf86drm.h>
#include <xf86drmMode.h>

#include "depthtouch/drivers/common/poll_input.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/log.h"
#include "libdrm_mode.h"

DT_LOG_CATEGORY(Kms)

namespace depthtouch::drivers::kms {

namespace {

/// \return the errno of a libdrm call that returned \a ret (most return -errno, some -1 + errno).
int errnoOf(int ret) noexcept
{
    return ret < -1 ? -ret : (errno != 0 ? errno : EIO);
}

class LibdrmKmsDevice final : public KmsDevice {
public:
    explicit LibdrmKmsDevice(int fd) : fd_(fd)
    {
        std::uint64_t cap = 0;
        monotonic_ = drmGetCap(fd_, DRM_CAP_TIMESTAMP_MONOTONIC, &cap) == 0 && cap != 0;
        cap = 0;
        modifiers_ = drmGetCap(fd_, DRM_CAP_ADDFB2_MODIFIERS, &cap) == 0 && cap != 0;
        if (!monotonic_)
            DT_LOG(Kms, Info, "DRM event timestamps are not monotonic: using the read time");
    }

    Result<KmsCrtcState> getCrtc(std::uint32_t crtcId) override
    {
        errno = 0;
        drmModeCrtc *c = drmModeGetCrtc(fd_, crtcId);
        if (c == nullptr)
            return unexpected(Errc::NoDevice, "drmModeGetCrtc failed", errno != 0 ? errno : ENOENT);
        KmsCrtcState s;
        s.crtcId = c->crtc_id;
        s.framebuffer = c->buffer_id;
        s.x = c->x;
        s.y = c->y;
        s.modeValid = c->mode_valid != 0;
        if (s.modeValid)
            s.mode = fromDrmMode(c->mode);
        drmModeFreeCrtc(c);
        return s;
    }

    Result<void> setCrtc(const KmsCrtcState &state, std::uint32_t connectorId) override
    {
        errno = 0;
        int ret = 0;
        if (!state.modeValid || state.framebuffer == 0) {
            ret = drmModeSetCrtc(fd_, state.crtcId, 0, 0, 0, nullptr, 0, nullptr);
        } else {
            drmModeModeInfo mode = toDrmMode(state.mode);
            std::uint32_t connector = connectorId;
            ret = drmModeSetCrtc(fd_, state.crtcId, state.framebuffer, state.x, state.y, &connector,
                                 1, &mode);
        }
        if (ret != 0)
            return unexpected(Errc::Io, "drmModeSetCrtc failed", errnoOf(ret));
        return ok();
    }

    Result<std::uint32_t> addFramebuffer(const ScanoutBuffer &b) override
    {
        std::uint32_t handles[4] = {};
        std::uint32_t strides[4] = {};
        std::uint32_t offsets[4] = {};
        std::uint64_t modifiers[4] = {};
        const std::uint32_t planes =
            std::min<std::uint32_t>(std::max<std::uint32_t>(b.planes, 1), 4);
        for (std::uint32_t i = 0; i < planes; ++i) {
            handles[i] = b.handles[i];
            strides[i] = b.strides[i];
            offsets[i] = b.offsets[i];
            modifiers[i] = b.modifier;
        }
        std::uint32_t fb = 0;
        int ret = -EINVAL;
        errno = 0;
        if (modifiers_ && b.modifier != DRM_FORMAT_MOD_INVALID)
            ret = drmModeAddFB2WithModifiers(fd_, b.width, b.height, b.format, handles, strides,
                                             offsets, modifiers, &fb, DRM_MODE_FB_MODIFIERS);
        if (ret != 0)
            ret =
                drmModeAddFB2(fd_, b.width, b.height, b.format, handles, strides, offsets, &fb, 0);
        if (ret != 0 && b.format == DRM_FORMAT_XRGB8888 && planes == 1)
            ret = drmModeAddFB(fd_, b.width, b.height, 24, 32, strides[0], handles[0], &fb);
        if (ret != 0)
            return unexpected(Errc::Io, "drmModeAddFB2 failed", errnoOf(ret));
        return fb;
    }

    Result<void> pageFlip(std::uint32_t crtcId, std::uint32_t framebuffer) override
    {
        flipDone_ = false;
        errno = 0;
        const int ret = drmModePageFlip(fd_, crtcId, framebuffer, DRM_MODE_PAGE_FLIP_EVENT, this);
        if (ret != 0)
            return unexpected(Errc::Io, "drmModePageFlip failed", errnoOf(ret));
        return ok();
    }

    Result<KmsFlipEvent> waitFlip(platform::Duration timeout) override
    {
        platform::Clock &clock = platform::SteadyClock::instance();
        const platform::TimePoint deadline = clock.now() + timeout;
        drmEventContext ctx{};
        ctx.version = 2;
        ctx.page_flip_handler = &LibdrmKmsDevice::onFlip;
        while (!flipDone_) {
            const platform::Duration left = deadline - clock.now();
            if (left <= platform::Duration::zero())
                return unexpected(Errc::Timeout, "No page flip event in time");
            short revents = 0;
            const PollResult polled = pollInput(fd_, left, revents);
            if (polled == PollResult::Failed)
                return unexpected(Errc::Io, "poll on the DRM device failed", errno);
            if (polled != PollResult::Ready)
                continue; // interrupted, or timed out: the deadline check above ends the wait
            if ((revents & (POLLERR | POLLHUP | POLLNVAL)) != 0)
                return unexpected(Errc::NoDevice, "DRM device hung up", ENODEV);
            errno = 0;
            if (drmHandleEvent(fd_, &ctx) != 0)
                return unexpected(Errc::Io, "Failed to read a DRM event", errno != 0 ? errno : EIO);
        }
        KmsFlipEvent e;
        e.sequence = sequence_;
        e.time = monotonic_ ? platform::TimePoint(std::chrono::seconds(seconds_) +
                                                  std::chrono::microseconds(micros_))
                            : clock.now();
        return e;
    }

private:
    static void onFlip(int, unsigned int sequence, unsigned int sec, unsigned int usec, void *data)
    {
        auto *self = static_cast<LibdrmKmsDevice *>(data);
        self->sequence_ = sequence;
        self->seconds_ = sec;
        self->micros_ = usec;
        self->flipDone_ = true;
    }

    int fd_;
    bool monotonic_ = true;
    bool modifiers_ = false;
    bool flipDone_ = false;
    std::uint32_t sequence_ = 0;
    std::uint32_t seconds_ = 0;
    std::uint32_t micros_ = 0;
};

} // namespace

std::unique_ptr<KmsDevice> makeLibdrmKmsDevice(int fd)
{
    return std::make_unique<LibdrmKmsDevice>(fd);
}

Result<std::uint32_t> findCrtc(int fd, std::uint32_t connectorId)
{
    drmModeRes *res = drmModeGetResources(fd);
    if (res == nullptr)
        return unexpected(Errc::NoDevice, "Failed to read the DRM resources", errno);
    drmModeConnector *c = drmModeGetConnector(fd, connectorId);
    if (c == nullptr) {
        drmModeFreeResources(res);
        return unexpected(Errc::NoDevice, "The DRM connector is gone", errno);
    }
    std::vector<DrmEncoderInfo> encoders;
    for (int i = 0; i < c->count_encoders; ++i) {
        drmModeEncoder *e = drmModeGetEncoder(fd, c->encoders[i]);
        if (e == nullptr)
            continue;
        encoders.push_back({e->encoder_id, e->crtc_id, e->possible_crtcs});
        drmModeFreeEncoder(e);
    }
    std::vector<std::uint32_t> crtcs(res->crtcs, res->crtcs + std::max(res->count_crtcs, 0));
    const std::uint32_t crtc = chooseCrtc(c->encoder_id, encoders, crtcs);
    drmModeFreeConnector(c);
    drmModeFreeResources(res);
    if (crtc == 0)
        return unexpected(Errc::NoDevice, "No CRTC can drive the DRM connector");
    return crtc;
}

Result<void> becomeMaster(int fd)
{
    if (drmIsMaster(fd) != 0)
        return ok();
    if (drmSetMaster(fd) == 0)
        return ok();
    const int err = errno;
    DT_LOG(Kms, Info, "Failed to become DRM master: %s", std::strerror(err));
    if (err == EACCES || err == EPERM)
        return unexpected(Errc::Busy,
                          "Another process is DRM master (an X server or Wayland compositor "
                          "runs on the card)",
                          err);
    return unexpected(Errc::Busy, "Failed to become DRM master", err);
}

} // namespace depthtouch::drivers::kms
