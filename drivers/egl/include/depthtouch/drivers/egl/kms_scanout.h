#pragma once
/// \file
/// \brief KmsScanout: the scan-out logic of the `kms` display (mode set, page flips paced by the
/// flip events, buffer release order, loss and restore of the previous CRTC state), behind two
/// seams so it is tested against fakes: KmsDevice (the few DRM calls it makes) and
/// ScanoutBufferSource (the buffers rendered into: a GBM surface's lock/release). The real ones
/// are on libdrm and GBM (EglGbmDisplay); tests use fakes.
///
/// One scan-out, after the renderer has filled a buffer of the source (eglSwapBuffers):
/// \verbatim
///   begin()      reads the CRTC's current state (KmsDevice::getCrtc) and keeps it for end()
///   present() 1  locks the buffer, gets its framebuffer, sets the CRTC to it in the chosen mode
///                (KmsDevice::setCrtc, which returns when the mode is set)
///   present() n  page flip to the new buffer's framebuffer, then waits for the flip event (at
///                most KmsScanoutConfig::flipTimeout); only then the previous buffer is released
///   end()        restores the saved CRTC state, then releases every buffer still locked
/// \endverbatim
/// At most two buffers are locked at a time, and between two present() calls only the one on
/// screen. A buffer is released only after its successor is on screen, in the order they were
/// locked, and never while the CRTC scans it out. Each buffer's DRM framebuffer is created once
/// (KmsDevice::addFramebuffer) and cached on the buffer (ScanoutBufferSource::cacheFramebuffer);
/// the source removes it when it destroys the buffer.
///
/// Loss: a flip event that does not come within flipTimeout (or reading it fails), or a DRM call
/// failing with EACCES or EPERM (DRM master lost: another process took the display), ENODEV or
/// ENXIO (card gone), ENOENT or EINVAL (connector or CRTC gone, or the mode rejected) makes the
/// scan-out Lost: present() returns NoDevice from then on, without waiting. A buffer whose flip
/// never completed stays locked until end(). Other failures (e.g. EBUSY, ENOMEM, no free buffer)
/// return Io, release the buffer of that frame and keep the last frame on screen.
///
/// end() restores the saved CRTC state exactly once per begin(), whatever happened since: after
/// a loss (the display may be back), and after a first present() that failed. It never throws.
///
/// Time: PresentInfo::vsyncTime is on the backend clock. A flip event's timestamp is on the
/// event clock (CLOCK_MONOTONIC, platform::SteadyClock, for DRM); it is moved to the backend
/// clock by the difference of the two clocks read when the event is handled. The first frame's
/// time is when setCrtc() returned. skippedVsyncs is the difference of the events' vertical blank
/// sequence numbers minus one; for the first flip after the mode set (no sequence before it) it is
/// estimated from the times and the mode's refresh rate.
/// Thread-safety: thread-bound (the render thread of the display that owns it).

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>

#include "depthtouch/drivers/egl/kms_output.h"
#include "depthtouch/hal/display.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers {

/// \brief The state of a CRTC (what drmModeGetCrtc() reports), to put it back later.
struct KmsCrtcState {
    std::uint32_t crtcId = 0;
    std::uint32_t framebuffer = 0; ///< Framebuffer scanned out; 0 when none.
    std::uint32_t x = 0;           ///< Position of the scanned area in the framebuffer, pixels.
    std::uint32_t y = 0;
    bool modeValid = false; ///< False: the CRTC is off (restoring it turns it off).
    DrmModeInfo mode;       ///< The mode it drives, when modeValid.

    friend bool operator==(const KmsCrtcState &, const KmsCrtcState &) = default;
};

/// \brief A page flip completed: the CRTC scans out the new framebuffer from this vertical blank.
struct KmsFlipEvent {
    std::uint32_t sequence = 0; ///< Vertical blank counter of the CRTC (wraps at 2^32).
    platform::TimePoint time{}; ///< When that blank started, on the event clock.
};

/// \brief A buffer locked from a ScanoutBufferSource: what a DRM framebuffer needs.
struct ScanoutBuffer {
    std::uintptr_t id = 0;                  ///< Identifies the buffer (the gbm_bo); never 0.
    std::uint32_t width = 0;                ///< Pixels.
    std::uint32_t height = 0;               ///< Pixels.
    std::uint32_t format = 0;               ///< DRM fourcc, e.g. DRM_FORMAT_XRGB8888.
    std::uint32_t planes = 1;               ///< Planes used in the arrays below (1..4).
    std::array<std::uint32_t, 4> handles{}; ///< GEM handles.
    std::array<std::uint32_t, 4> strides{}; ///< Bytes per row.
    std::array<std::uint32_t, 4> offsets{}; ///< Bytes.
    std::uint64_t modifier = 0;    ///< Format modifier; DRM_FORMAT_MOD_INVALID when unknown.
    std::uint32_t framebuffer = 0; ///< Framebuffer cached on the buffer; 0 when none yet.
};

/// \brief The DRM calls of a scan-out (the seam for tests). Errors carry the errno of the failed
/// call in Error::sysErrno.
class KmsDevice {
public:
    virtual ~KmsDevice() = default;
    /// \return the current state of CRTC \a crtcId (drmModeGetCrtc).
    virtual Result<KmsCrtcState> getCrtc(std::uint32_t crtcId) = 0;
    /// \brief Sets CRTC state.crtcId to scan out state.framebuffer at (x, y) in state.mode on
    /// connector \a connectorId; turns the CRTC off when !state.modeValid or framebuffer is 0
    /// (drmModeSetCrtc). Returns when done.
    virtual Result<void> setCrtc(const KmsCrtcState &state, std::uint32_t connectorId) = 0;
    /// \return a new DRM framebuffer for \a buffer (drmModeAddFB2, else drmModeAddFB).
    virtual Result<std::uint32_t> addFramebuffer(const ScanoutBuffer &buffer) = 0;
    /// \brief Queues a flip of CRTC \a crtcId to \a framebuffer at the next vertical blank,
    /// asking for an event (drmModePageFlip with DRM_MODE_PAGE_FLIP_EVENT). Does not wait.
    virtual Result<void> pageFlip(std::uint32_t crtcId, std::uint32_t framebuffer) = 0;
    /// \brief Waits at most \a timeout for the event of the queued flip.
    /// \return the event. Errors: Timeout (none came), Io or NoDevice (reading the device failed).
    virtual Result<KmsFlipEvent> waitFlip(platform::Duration timeout) = 0;

protected:
    KmsDevice() = default;
    DT_DISABLE_COPY_AND_MOVE(KmsDevice)
};

/// \brief The buffers the renderer draws into (a GBM surface; the seam for tests).
class ScanoutBufferSource {
public:
    virtual ~ScanoutBufferSource() = default;
    /// \brief Locks the buffer rendered last (gbm_surface_lock_front_buffer) so that it is not
    /// rendered into while it is shown. \return it. Errors: OutOfResources (no rendered buffer).
    virtual Result<ScanoutBuffer> lockFront() = 0;
    /// Gives buffer \a id back for rendering (gbm_surface_release_buffer).
    virtual void release(std::uintptr_t id) noexcept = 0;
    /// \brief Keeps \a framebuffer with buffer \a id (ScanoutBuffer::framebuffer from then on);
    /// the source removes the framebuffer when it destroys the buffer.
    virtual void cacheFramebuffer(std::uintptr_t id, std::uint32_t framebuffer) = 0;

protected:
    ScanoutBufferSource() = default;
    DT_DISABLE_COPY_AND_MOVE(ScanoutBufferSource)
};

/// What a scan-out drives.
struct KmsScanoutConfig {
    std::uint32_t crtcId = 0;
    std::uint32_t connectorId = 0;
    DrmModeInfo mode; ///< Set on the CRTC by the first present().
    /// Longest wait for a flip event before the display counts as lost. Several refresh periods
    /// even at 24 Hz.
    platform::Duration flipTimeout = std::chrono::milliseconds(500);
};

/// \brief Mode set, page flips and restore of one CRTC (see the file comment).
class KmsScanout {
public:
    enum class State : std::uint8_t { Idle, Running, Lost };

    /// \param[in] device, source Used from begin() to end(); must outlive the scan-out.
    /// \param[in] clock The backend clock (PresentInfo::vsyncTime).
    /// \param[in] eventClock The clock of the flip events' timestamps.
    KmsScanout(KmsDevice &device, ScanoutBufferSource &source, platform::Clock &clock,
               platform::Clock &eventClock) noexcept;
    ~KmsScanout();

    /// \brief Saves the state of cfg.crtcId for end(). \pre Idle.
    /// \return nothing (state Running). Errors: InvalidState (not Idle), InvalidArgument (no CRTC,
    /// connector or mode size), NoDevice (the CRTC cannot be read: card gone or no access).
    [[nodiscard]] Result<void> begin(const KmsScanoutConfig &cfg);

    /// \brief Shows the buffer rendered last; returns when it is on screen.
    /// \return its vertical blank (backend clock), frames shown since begin() (1, 2, ...) and
    /// the blanks skipped since the previous one. Errors: InvalidState (Idle), NoDevice (Lost,
    /// now or before; Error::sysErrno holds the errno, 0 for a flip timeout), Io (this frame was
    /// not shown; the previous one stays).
    [[nodiscard]] Result<hal::PresentInfo> present();

    /// \brief Restores the CRTC state saved by begin() (once), then releases every locked
    /// buffer; state Idle. Idempotent; no-op when Idle.
    void end() noexcept;

    [[nodiscard]] State state() const noexcept { return state_; }

private:
    /// Logs \a e; makes the scan-out Lost when \a lost or \a e is a loss of the device.
    /// \return the error for present().
    Error fail(const Error &e, const char *what, bool lost = false) noexcept;
    [[nodiscard]] Result<std::uint32_t> framebufferOf(ScanoutBuffer &buffer);
    [[nodiscard]] platform::TimePoint toBackendClock(platform::TimePoint eventTime) const noexcept;

    KmsDevice &device_;
    ScanoutBufferSource &source_;
    platform::Clock &clock_;
    platform::Clock &eventClock_;
    KmsScanoutConfig cfg_;
    State state_ = State::Idle;
    std::optional<KmsCrtcState> saved_;         ///< From begin(), until restored.
    std::uintptr_t shown_ = 0;                  ///< Buffer on screen; 0 before the first frame.
    std::uintptr_t pending_ = 0;                ///< Buffer of a flip that never completed.
    std::optional<std::uint32_t> lastSequence_; ///< Of the last flip event.
    platform::TimePoint lastVsync_{};           ///< Backend clock.
    std::uint64_t frames_ = 0;
};

/// \return true when \a err (an errno) from a DRM call means the display is gone or taken.
bool isKmsLossErrno(int err) noexcept;

} // namespace depthtouch::drivers
