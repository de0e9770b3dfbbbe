#include "depthtouch/drivers/egl/kms_scanout.h"

#include <cerrno>
#include <cmath>
#include <cstring>

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Kms)

namespace depthtouch::drivers {

bool isKmsLossErrno(int err) noexcept
{
    switch (err) {
    case EACCES: // DRM master taken by another process (VT switch, a compositor started)
    case EPERM:
    case ENODEV: // card removed, driver unbound
    case ENXIO:
    case ENOENT: // connector or CRTC object gone (hot-unplug of an MST connector)
    case EINVAL: // connector unplugged under the mode, or the mode rejected
        return true;
    default:
        return false;
    }
}

KmsScanout::KmsScanout(KmsDevice &device, ScanoutBufferSource &source, platform::Clock &clock,
                       platform::Clock &eventClock) noexcept
    : device_(device), source_(source), clock_(clock), eventClock_(eventClock)
{
}

KmsScanout::~KmsScanout()
{
    end();
}

Result<void> KmsScanout::begin(const KmsScanoutConfig &cfg)
{
    if (state_ != State::Idle) {
        DT_LOG(Kms, Error, "In state %s trying begin() requiring Idle",
               state_ == State::Running ? "Running" : "Lost");
        return unexpected(Errc::InvalidState, "begin() requires an idle scan-out");
    }
    if (cfg.crtcId == 0 || cfg.connectorId == 0 || cfg.mode.width <= 0 || cfg.mode.height <= 0)
        return unexpected(Errc::InvalidArgument, "Scan-out needs a CRTC, a connector and a mode");
    auto saved = device_.getCrtc(cfg.crtcId);
    if (!saved) {
        DT_LOG(Kms, Error, "Failed to read CRTC %u: %s", cfg.crtcId,
               std::strerror(saved.error().sysErrno));
        return unexpected(Errc::NoDevice, "Failed to read the CRTC state", saved.error().sysErrno);
    }
    cfg_ = cfg;
    saved_ = *saved;
    shown_ = 0;
    pending_ = 0;
    lastSequence_.reset();
    lastVsync_ = {};
    frames_ = 0;
    state_ = State::Running;
    return ok();
}

Error KmsScanout::fail(const Error &e, const char *what, bool lost) noexcept
{
    lost = lost || e.code == Errc::Timeout || e.code == Errc::NoDevice ||
           (e.sysErrno != 0 && isKmsLossErrno(e.sysErrno));
    DT_LOG(Kms, Error, "Failed to %s: %s (%s)", what, e.what,
           e.sysErrno != 0 ? std::strerror(e.sysErrno) : errcName(e.code));
    if (!lost)
        return Error(Errc::Io, "DRM scan-out failed; the previous frame stays", e.sysErrno);
    if (state_ == State::Running)
        DT_LOG(Kms, Warning, "KMS display lost");
    state_ = State::Lost;
    return Error(Errc::NoDevice,
                 e.code == Errc::Timeout ? "KMS display lost: no page flip event"
                                         : "KMS display lost (unplugged, or DRM master taken)",
                 e.sysErrno);
}

Result<std::uint32_t> KmsScanout::framebufferOf(ScanoutBuffer &buffer)
{
    if (buffer.framebuffer != 0)
        return buffer.framebuffer;
    auto fb = device_.addFramebuffer(buffer);
    if (!fb)
        return unexpected(fb.error());
    source_.cacheFramebuffer(buffer.id, *fb);
    buffer.framebuffer = *fb;
    return *fb;
}

platform::TimePoint KmsScanout::toBackendClock(platform::TimePoint eventTime) const noexcept
{
    const platform::TimePoint now = clock_.now();
    const platform::Duration age = eventClock_.now() - eventTime;
    // An event stamped "in the future" of its clock (never seen) counts as now.
    return age > platform::Duration::zero() ? now - age : now;
}

Result<hal::PresentInfo> KmsScanout::present()
{
    if (state_ == State::Idle)
        return unexpected(Errc::InvalidState, "present() before begin()");
    if (state_ == State::Lost)
        return unexpected(Errc::NoDevice, "KMS display lost");
    auto buffer = source_.lockFront();
    if (!buffer) {
        DT_LOG(Kms, Error, "Failed to lock the rendered buffer: %s", buffer.error().what);
        return unexpected(Errc::Io, "No rendered buffer to show");
    }
    auto fb = framebufferOf(*buffer);
    if (!fb) {
        source_.release(buffer->id);
        return unexpected(fail(fb.error(), "create a DRM framebuffer"));
    }

    hal::PresentInfo info;
    if (shown_ == 0) {
        KmsCrtcState set;
        set.crtcId = cfg_.crtcId;
        set.framebuffer = *fb;
        set.modeValid = true;
        set.mode = cfg_.mode;
        if (auto r = device_.setCrtc(set, cfg_.connectorId); !r) {
            source_.release(buffer->id);
            return unexpected(fail(r.error(), "set the CRTC mode"));
        }
        shown_ = buffer->id;
        info.vsyncTime = clock_.now();
        info.skippedVsyncs = 0;
    } else {
        if (auto r = device_.pageFlip(cfg_.crtcId, *fb); !r) {
            source_.release(buffer->id);
            return unexpected(fail(r.error(), "queue a page flip"));
        }
        auto event = device_.waitFlip(cfg_.flipTimeout);
        if (!event) {
            // Whether the flip completes is unknown, so no other can be queued: lost. The
            // buffer stays locked until end().
            pending_ = buffer->id;
            return unexpected(fail(event.error(), "wait for the page flip", /*lost=*/true));
        }
        // The new buffer is on screen: its predecessor may be rendered into again.
        source_.release(shown_);
        shown_ = buffer->id;
        info.vsyncTime = toBackendClock(event->time);
        if (lastSequence_) {
            const std::uint32_t periods = event->sequence - *lastSequence_; // wraps
            info.skippedVsyncs = periods > 0 ? periods - 1 : 0;
        } else {
            const double hz = cfg_.mode.refreshHz > 0.0 ? cfg_.mode.refreshHz : 60.0;
            const double periods =
                std::round(platform::toSeconds(info.vsyncTime - lastVsync_) * hz);
            info.skippedVsyncs = periods > 1.0 ? static_cast<std::uint32_t>(periods - 1.0) : 0;
        }
        lastSequence_ = event->sequence;
    }
    lastVsync_ = info.vsyncTime;
    info.frameCounter = ++frames_;
    return info;
}

void KmsScanout::end() noexcept
{
    if (state_ == State::Idle)
        return;
    if (saved_) {
        const KmsCrtcState saved = *saved_;
        saved_.reset();
        if (auto r = device_.setCrtc(saved, cfg_.connectorId); !r)
            DT_LOG(Kms, Warning, "Failed to restore CRTC %u: %s", saved.crtcId,
                   r.error().sysErrno != 0 ? std::strerror(r.error().sysErrno) : r.error().what);
    }
    // The CRTC scans out the restored framebuffer now: ours may go, oldest first.
    if (shown_ != 0)
        source_.release(shown_);
    if (pending_ != 0)
        source_.release(pending_);
    shown_ = 0;
    pending_ = 0;
    state_ = State::Idle;
}

} // namespace depthtouch::drivers
