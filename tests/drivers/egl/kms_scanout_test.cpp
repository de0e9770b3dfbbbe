// The kms display's scan-out logic (KmsScanout) against a fake DRM device and a fake GBM surface:
// mode set then page flips, one flip at a time, buffer release order, framebuffer cache, loss
// (flip timeout, ioctl errors), restore of the saved CRTC state, vertical blank accounting.
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/drivers/egl/kms_scanout.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {
namespace {

using namespace std::chrono_literals;
using platform::Duration;
using platform::ManualClock;
using platform::TimePoint;

constexpr std::uint32_t kCrtc = 41;
constexpr std::uint32_t kConnector = 31;
constexpr Duration kPeriod = 16'666'667ns; // 60 Hz

/// Calls in the order they happened, from both fakes ("setCrtc 101", "flip 102", "wait",
/// "release 1", ...).
using CallLog = std::vector<std::string>;

/// A CRTC and its page flips as the kernel runs them: one flip pending at most (EBUSY otherwise,
/// as DRM), the event after \a steps vertical blanks on the event clock.
class FakeDevice final : public KmsDevice {
public:
    FakeDevice(CallLog &log, ManualClock &eventClock) : log_(log), eventClock_(eventClock)
    {
        crtc.crtcId = kCrtc;
        crtc.framebuffer = 7; // the console's picture
        crtc.x = 0;
        crtc.y = 0;
        crtc.modeValid = true;
        crtc.mode = {"1280x720", 1280, 720, 60.0, false, {}};
        crtc.mode.timings.clock = 74250;
        crtc.mode.timings.htotal = 1650;
        crtc.mode.timings.vtotal = 750;
    }

    Result<KmsCrtcState> getCrtc(std::uint32_t id) override
    {
        log_.push_back("getCrtc");
        if (getCrtcErrno != 0)
            return unexpected(Errc::Io, "fake getCrtc failure", getCrtcErrno);
        EXPECT_EQ(id, crtc.crtcId);
        return crtc;
    }

    Result<void> setCrtc(const KmsCrtcState &state, std::uint32_t connectorId) override
    {
        log_.push_back("setCrtc " + std::to_string(state.framebuffer));
        setCrtcCalls.push_back(state);
        setCrtcConnectors.push_back(connectorId);
        if (setCrtcErrno != 0)
            return unexpected(Errc::Io, "fake setCrtc failure", setCrtcErrno);
        crtc = state;
        pending.reset(); // a mode set replaces a pending flip
        return ok();
    }

    Result<std::uint32_t> addFramebuffer(const ScanoutBuffer &b) override
    {
        log_.push_back("addFb " + std::to_string(b.id));
        if (addFbErrno != 0)
            return unexpected(Errc::Io, "fake AddFB2 failure", addFbErrno);
        const std::uint32_t fb = 100 + static_cast<std::uint32_t>(b.id);
        ++addedPerBuffer[b.id];
        return fb;
    }

    Result<void> pageFlip(std::uint32_t id, std::uint32_t fb) override
    {
        log_.push_back("flip " + std::to_string(fb));
        EXPECT_EQ(id, kCrtc);
        if (pending) {
            ++flipsWhilePending;
            return unexpected(Errc::Io, "flip already pending", EBUSY);
        }
        if (flipErrno != 0)
            return unexpected(Errc::Io, "fake page flip failure", flipErrno);
        pending = fb;
        return ok();
    }

    Result<KmsFlipEvent> waitFlip(Duration timeout) override
    {
        log_.push_back("wait");
        timeouts.push_back(timeout);
        if (!pending)
            return unexpected(Errc::Timeout, "no flip queued");
        if (neverComplete) {
            eventClock_.advance(timeout); // the wait is bounded by the timeout it was given
            return unexpected(Errc::Timeout, "No page flip event in time");
        }
        std::uint32_t steps = 1;
        if (!blanksPerFlip.empty()) {
            steps = blanksPerFlip.front();
            blanksPerFlip.erase(blanksPerFlip.begin());
        }
        sequence += steps;
        eventClock_.advance(kPeriod * steps);
        crtc.framebuffer = *pending;
        pending.reset();
        KmsFlipEvent e;
        e.sequence = sequence;
        e.time = eventClock_.now() - eventAge;
        return e;
    }

    KmsCrtcState crtc;                    ///< What the CRTC shows now.
    std::optional<std::uint32_t> pending; ///< Framebuffer of the queued flip.
    std::vector<KmsCrtcState> setCrtcCalls;
    std::vector<std::uint32_t> setCrtcConnectors;
    std::map<std::uintptr_t, int> addedPerBuffer;
    std::vector<Duration> timeouts;
    std::vector<std::uint32_t> blanksPerFlip; ///< Blanks each flip takes (default 1).
    std::uint32_t sequence = 5000;
    Duration eventAge{}; ///< How long before its handling each event's blank was.
    int flipsWhilePending = 0;
    int getCrtcErrno = 0;
    int setCrtcErrno = 0;
    int addFbErrno = 0;
    int flipErrno = 0;
    bool neverComplete = false;

private:
    CallLog &log_;
    ManualClock &eventClock_;
};

/// A GBM surface of \a count buffers (ids 1..count) rendered round-robin; checks that no buffer is
/// released twice or while the CRTC shows it (or a flip to it is pending).
class FakeSource final : public ScanoutBufferSource {
public:
    FakeSource(CallLog &log, const FakeDevice &device, int count = 3)
        : log_(log), device_(device), count_(count)
    {
    }

    Result<ScanoutBuffer> lockFront() override
    {
        ++lockCalls;
        // The next buffer in rendering order that is not locked.
        for (int tries = 0; tries < count_; ++tries) {
            const std::uintptr_t id = next_;
            next_ = next_ % static_cast<std::uintptr_t>(count_) + 1;
            if (locked.count(id) == 0) {
                locked.insert(id);
                lockOrder.push_back(id);
                ScanoutBuffer b;
                b.id = id;
                b.width = 1280;
                b.height = 720;
                b.format = 0x34325258; // XR24
                b.handles[0] = static_cast<std::uint32_t>(id);
                b.strides[0] = 1280 * 4;
                auto fb = framebuffers.find(id);
                b.framebuffer = fb != framebuffers.end() ? fb->second : 0;
                return b;
            }
        }
        return unexpected(Errc::OutOfResources, "no free buffer");
    }

    void release(std::uintptr_t id) noexcept override
    {
        log_.push_back("release " + std::to_string(id));
        releaseOrder.push_back(id);
        if (locked.erase(id) == 0)
            ++badReleases;
        auto fb = framebuffers.find(id);
        if (fb != framebuffers.end() &&
            (fb->second == device_.crtc.framebuffer || fb->second == device_.pending))
            ++releasesOnScreen;
    }

    void cacheFramebuffer(std::uintptr_t id, std::uint32_t fb) override { framebuffers[id] = fb; }

    std::set<std::uintptr_t> locked;
    std::vector<std::uintptr_t> lockOrder;
    std::vector<std::uintptr_t> releaseOrder;
    std::map<std::uintptr_t, std::uint32_t> framebuffers;
    int lockCalls = 0;
    int badReleases = 0;
    int releasesOnScreen = 0;

private:
    CallLog &log_;
    const FakeDevice &device_;
    int count_;
    std::uintptr_t next_ = 1;
};

DrmModeInfo mode1080()
{
    DrmModeInfo m{"1920x1080", 1920, 1080, 60.0, true, {}};
    m.timings.clock = 148500;
    m.timings.hdisplay = 1920;
    m.timings.vdisplay = 1080;
    m.timings.htotal = 2200;
    m.timings.vtotal = 1125;
    m.timings.vrefresh = 60;
    return m;
}

KmsScanoutConfig config()
{
    KmsScanoutConfig c;
    c.crtcId = kCrtc;
    c.connectorId = kConnector;
    c.mode = mode1080();
    c.flipTimeout = 200ms;
    return c;
}

/// A scan-out on the fakes, one ManualClock for both the backend and the events.
struct Rig {
    CallLog log;
    ManualClock clock{ManualClock::Mode::AutoAdvance, TimePoint(10s)};
    FakeDevice device{log, clock};
    FakeSource source{log, device};
    KmsScanout scanout{device, source, clock, clock};

    /// \return the number of setCrtc calls that put the saved (console) state back.
    [[nodiscard]] int restores(const KmsCrtcState &saved) const
    {
        int n = 0;
        for (const KmsCrtcState &s : device.setCrtcCalls)
            n += s == saved ? 1 : 0;
        return n;
    }
};

TEST(KmsScanoutTest, firstPresentSetsTheModeAndLaterOnesFlip)
{
    // GIVEN a scan-out begun on the console's CRTC
    Rig r;
    const KmsCrtcState console = r.device.crtc;
    ASSERT_TRUE(r.scanout.begin(config()));
    // WHEN three frames are presented
    for (std::uint64_t i = 1; i <= 3; ++i) {
        auto info = r.scanout.present();
        ASSERT_TRUE(info) << info.error().what;
        EXPECT_EQ(info->frameCounter, i);
    }
    // THEN the first one set the mode on the connector, the others were page flips each
    // followed by their wait, and the buffer shown before went back after the flip
    ASSERT_EQ(r.device.setCrtcCalls.size(), 1u);
    const KmsCrtcState &set = r.device.setCrtcCalls[0];
    EXPECT_EQ(set.crtcId, kCrtc);
    EXPECT_TRUE(set.modeValid);
    EXPECT_EQ(set.mode, mode1080());
    EXPECT_EQ(set.framebuffer, 101u);
    EXPECT_EQ(r.device.setCrtcConnectors[0], kConnector);
    const CallLog expected = {"getCrtc",   "addFb 1", "setCrtc 101", "addFb 2", "flip 102", "wait",
                              "release 1", "addFb 3", "flip 103",    "wait",    "release 2"};
    EXPECT_EQ(r.log, expected);
    EXPECT_EQ(r.device.crtc.framebuffer, 103u);
    EXPECT_NE(r.device.crtc, console);
}

TEST(KmsScanoutTest, eachFlipWaitsForItsEventAndBuffersGoBackInOrder)
{
    Rig r;
    ASSERT_TRUE(r.scanout.begin(config()));
    for (int i = 0; i < 10; ++i) {
        ASSERT_TRUE(r.scanout.present());
        // Between frames only the buffer on screen is held.
        ASSERT_EQ(r.source.locked.size(), 1u);
        EXPECT_EQ(r.source.framebuffers[*r.source.locked.begin()], r.device.crtc.framebuffer);
    }
    EXPECT_EQ(r.device.flipsWhilePending, 0);
    EXPECT_EQ(r.source.releasesOnScreen, 0);
    EXPECT_EQ(r.source.badReleases, 0);
    // Released in the order they were locked, all but the last.
    const std::vector<std::uintptr_t> released(r.source.lockOrder.begin(),
                                               r.source.lockOrder.end() - 1);
    EXPECT_EQ(r.source.releaseOrder, released);
    // Every flip waited with the configured bound.
    EXPECT_EQ(r.device.timeouts, std::vector<Duration>(9, Duration(200ms)));
}

TEST(KmsScanoutTest, framebufferIsCreatedOncePerBufferAndReused)
{
    Rig r;
    ASSERT_TRUE(r.scanout.begin(config()));
    for (int i = 0; i < 9; ++i)
        ASSERT_TRUE(r.scanout.present());
    // Three buffers in rotation: three framebuffers, each made once and cached on its buffer.
    ASSERT_EQ(r.device.addedPerBuffer.size(), 3u);
    for (const auto &[id, count] : r.device.addedPerBuffer)
        EXPECT_EQ(count, 1) << "buffer " << id;
    EXPECT_EQ(r.source.framebuffers.size(), 3u);
    // The frame on screen is the last buffer's cached framebuffer.
    EXPECT_EQ(r.device.crtc.framebuffer, r.source.framebuffers[r.source.lockOrder.back()]);
}

TEST(KmsScanoutTest, flipThatNeverCompletesIsLostWithoutHanging)
{
    Rig r;
    const KmsCrtcState console = r.device.crtc;
    ASSERT_TRUE(r.scanout.begin(config()));
    ASSERT_TRUE(r.scanout.present());
    r.device.neverComplete = true;
    const TimePoint before = r.clock.now();
    auto lost = r.scanout.present();
    ASSERT_FALSE(lost);
    EXPECT_EQ(lost.error().code, Errc::NoDevice);
    EXPECT_EQ(r.scanout.state(), KmsScanout::State::Lost);
    // The wait was bounded by the configured timeout.
    EXPECT_EQ(r.clock.now() - before, Duration(200ms));
    // Further presents fail at once without touching the device or the surface.
    const std::size_t calls = r.log.size();
    const int locks = r.source.lockCalls;
    EXPECT_EQ(r.scanout.present().error().code, Errc::NoDevice);
    EXPECT_EQ(r.log.size(), calls);
    EXPECT_EQ(r.source.lockCalls, locks);
    // end() restores the console once, then lets go of both buffers (shown and pending).
    r.scanout.end();
    EXPECT_EQ(r.restores(console), 1);
    EXPECT_EQ(r.device.crtc, console);
    EXPECT_TRUE(r.source.locked.empty());
    EXPECT_EQ(r.source.badReleases, 0);
    EXPECT_EQ(r.scanout.state(), KmsScanout::State::Idle);
}

TEST(KmsScanoutTest, deviceErrorsOfAnUnpluggedDisplayAreLost)
{
    for (const int err : {EACCES, ENODEV, EINVAL}) {
        SCOPED_TRACE(err);
        Rig r;
        ASSERT_TRUE(r.scanout.begin(config()));
        ASSERT_TRUE(r.scanout.present());
        r.device.flipErrno = err;
        auto p = r.scanout.present();
        ASSERT_FALSE(p);
        EXPECT_EQ(p.error().code, Errc::NoDevice);
        EXPECT_EQ(p.error().sysErrno, err);
        EXPECT_EQ(r.scanout.state(), KmsScanout::State::Lost);
        // The frame that was not flipped went back; the one on screen stays until end().
        EXPECT_EQ(r.source.locked.size(), 1u);
        EXPECT_EQ(r.source.releasesOnScreen, 0);
    }
    // An error of the framebuffer creation counts the same.
    Rig r;
    ASSERT_TRUE(r.scanout.begin(config()));
    r.device.addFbErrno = ENODEV;
    EXPECT_EQ(r.scanout.present().error().code, Errc::NoDevice);
    EXPECT_EQ(r.scanout.state(), KmsScanout::State::Lost);
    EXPECT_TRUE(r.source.locked.empty());
}

TEST(KmsScanoutTest, transientErrorsKeepThePreviousFrame)
{
    Rig r;
    ASSERT_TRUE(r.scanout.begin(config()));
    ASSERT_TRUE(r.scanout.present());
    const std::uint32_t shown = r.device.crtc.framebuffer;
    r.device.flipErrno = ENOMEM;
    auto p = r.scanout.present();
    ASSERT_FALSE(p);
    EXPECT_EQ(p.error().code, Errc::Io);
    EXPECT_EQ(r.scanout.state(), KmsScanout::State::Running);
    EXPECT_EQ(r.device.crtc.framebuffer, shown);
    EXPECT_EQ(r.source.locked.size(), 1u);
    // The next frame goes on.
    r.device.flipErrno = 0;
    auto next = r.scanout.present();
    ASSERT_TRUE(next) << next.error().what;
    EXPECT_EQ(next->frameCounter, 2u);
    EXPECT_EQ(r.source.releasesOnScreen, 0);
}

TEST(KmsScanoutTest, endRestoresTheSavedCrtcExactlyOnce)
{
    // GIVEN frames shown
    Rig r;
    const KmsCrtcState console = r.device.crtc;
    ASSERT_TRUE(r.scanout.begin(config()));
    for (int i = 0; i < 4; ++i)
        ASSERT_TRUE(r.scanout.present());
    // WHEN the scan-out ends twice
    r.scanout.end();
    r.scanout.end();
    // THEN the console's mode, framebuffer and position are back, set once on our connector,
    // before any of our buffers was let go
    EXPECT_EQ(r.restores(console), 1);
    EXPECT_EQ(r.device.crtc, console);
    EXPECT_EQ(r.device.setCrtcConnectors.back(), kConnector);
    const auto restore = std::find(r.log.begin(), r.log.end(), "setCrtc 7");
    ASSERT_NE(restore, r.log.end());
    EXPECT_EQ(std::next(restore), r.log.end() - 1);
    EXPECT_EQ(r.log.back().rfind("release ", 0), 0u);
    EXPECT_TRUE(r.source.locked.empty());
    EXPECT_EQ(r.source.releasesOnScreen, 0);
}

TEST(KmsScanoutTest, endRestoresAfterAFailedFirstFrameAndAfterNoFrame)
{
    // A mode the sink refuses: the first present fails, end() still restores once.
    {
        Rig r;
        const KmsCrtcState console = r.device.crtc;
        ASSERT_TRUE(r.scanout.begin(config()));
        r.device.setCrtcErrno = EINVAL;
        EXPECT_EQ(r.scanout.present().error().code, Errc::NoDevice);
        r.device.setCrtcErrno = 0;
        r.scanout.end();
        EXPECT_EQ(r.restores(console), 1);
        EXPECT_EQ(r.device.crtc, console);
        EXPECT_TRUE(r.source.locked.empty());
    }
    // Begun, then the rest of the opening failed before any frame.
    {
        Rig r;
        const KmsCrtcState console = r.device.crtc;
        ASSERT_TRUE(r.scanout.begin(config()));
        r.scanout.end();
        EXPECT_EQ(r.restores(console), 1);
    }
    // The destructor ends a running scan-out.
    {
        CallLog log;
        ManualClock clock;
        FakeDevice device(log, clock);
        FakeSource source(log, device);
        const KmsCrtcState console = device.crtc;
        {
            KmsScanout scanout(device, source, clock, clock);
            ASSERT_TRUE(scanout.begin(config()));
            ASSERT_TRUE(scanout.present());
        }
        EXPECT_EQ(device.crtc, console);
        EXPECT_TRUE(source.locked.empty());
    }
}

TEST(KmsScanoutTest, beginChecksStateArgumentsAndTheCrtc)
{
    Rig r;
    EXPECT_EQ(r.scanout.present().error().code, Errc::InvalidState);
    KmsScanoutConfig bad = config();
    bad.crtcId = 0;
    EXPECT_EQ(r.scanout.begin(bad).error().code, Errc::InvalidArgument);
    r.device.getCrtcErrno = EACCES;
    EXPECT_EQ(r.scanout.begin(config()).error().code, Errc::NoDevice);
    EXPECT_EQ(r.scanout.state(), KmsScanout::State::Idle);
    r.scanout.end(); // nothing saved: nothing restored
    EXPECT_TRUE(r.device.setCrtcCalls.empty());
    r.device.getCrtcErrno = 0;
    ASSERT_TRUE(r.scanout.begin(config()));
    EXPECT_EQ(r.scanout.begin(config()).error().code, Errc::InvalidState);
}

TEST(KmsScanoutTest, skippedVsyncsComeFromTheEventSequenceNumbers)
{
    Rig r;
    ASSERT_TRUE(r.scanout.begin(config()));
    ASSERT_TRUE(r.scanout.present()); // mode set
    // Flips that took 1, 1, 3, 1 and 2 blanks; the sequence counter wraps on the way.
    r.device.sequence = 0xFFFFFFFEu;
    r.device.blanksPerFlip = {1, 1, 3, 1, 2};
    std::vector<std::uint32_t> skipped;
    std::vector<TimePoint> times;
    for (int i = 0; i < 5; ++i) {
        auto info = r.scanout.present();
        ASSERT_TRUE(info) << info.error().what;
        skipped.push_back(info->skippedVsyncs);
        times.push_back(info->vsyncTime);
    }
    // The first flip after the mode set has no sequence before it: estimated from the time (one
    // period after the mode set: none skipped).
    EXPECT_EQ(skipped, (std::vector<std::uint32_t>{0, 0, 2, 0, 1}));
    // Each frame's time is its flip event's blank.
    EXPECT_EQ(times[2] - times[1], kPeriod * 3);
    EXPECT_EQ(times[4] - times[3], kPeriod * 2);
}

TEST(KmsScanoutTest, firstFlipAfterTheModeSetEstimatesSkippedBlanksFromTime)
{
    Rig r;
    ASSERT_TRUE(r.scanout.begin(config()));
    ASSERT_TRUE(r.scanout.present());
    r.device.blanksPerFlip = {4};
    auto info = r.scanout.present();
    ASSERT_TRUE(info);
    EXPECT_EQ(info->skippedVsyncs, 3u);
}

TEST(KmsScanoutTest, flipTimestampsMoveToTheBackendClock)
{
    // GIVEN a backend clock 1000 s ahead of the event clock, events handled 2 ms after their blank
    CallLog log;
    ManualClock backend(ManualClock::Mode::AutoAdvance, TimePoint(1005s));
    ManualClock events(ManualClock::Mode::AutoAdvance, TimePoint(5s));
    FakeDevice device(log, events);
    FakeSource source(log, device);
    device.eventAge = 2ms;
    KmsScanout scanout(device, source, backend, events);
    ASSERT_TRUE(scanout.begin(config()));
    auto first = scanout.present();
    ASSERT_TRUE(first);
    EXPECT_EQ(first->vsyncTime, TimePoint(1005s)); // the mode set: when it returned
    // WHEN a flip completes (the event clock moves one period)
    auto second = scanout.present();
    ASSERT_TRUE(second);
    // THEN its time is the blank, on the backend clock: now minus the event's age
    EXPECT_EQ(second->vsyncTime, backend.now() - Duration(2ms));
    EXPECT_EQ(backend.now(), TimePoint(1005s)); // the backend clock itself did not move
}

TEST(KmsScanoutTest, noFreeBufferIsAnErrorNotALoss)
{
    CallLog log;
    ManualClock clock;
    FakeDevice device(log, clock);
    FakeSource source(log, device, /*count=*/1);
    KmsScanout scanout(device, source, clock, clock);
    ASSERT_TRUE(scanout.begin(config()));
    ASSERT_TRUE(scanout.present());
    // The only buffer is on screen: nothing rendered to show.
    auto p = scanout.present();
    ASSERT_FALSE(p);
    EXPECT_EQ(p.error().code, Errc::Io);
    EXPECT_EQ(scanout.state(), KmsScanout::State::Running);
    EXPECT_EQ(source.releasesOnScreen, 0);
}

TEST(KmsScanoutTest, lossErrnosAreTheDeviceOnes)
{
    for (const int err : {EACCES, EPERM, ENODEV, ENXIO, ENOENT, EINVAL})
        EXPECT_TRUE(isKmsLossErrno(err)) << err;
    for (const int err : {0, EBUSY, ENOMEM, EINTR, EAGAIN})
        EXPECT_FALSE(isKmsLossErrno(err)) << err;
}

} // namespace
} // namespace depthtouch::drivers
