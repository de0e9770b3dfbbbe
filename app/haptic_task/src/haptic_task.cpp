#include "depthtouch/haptic_task/haptic_task.h"

#include <algorithm>
#include <cmath>
#include <new>
#include <utility>

#include <glm/geometric.hpp>

#include "depthtouch/platform/memory_lock.h"
#include "depthtouch/platform/thread_config.h"

namespace depthtouch::haptic_task {

namespace {

using platform::Duration;
using platform::TimePoint;

/// Adds \a delta to a counter only the calling thread writes.
void bump(std::atomic<std::uint64_t> &counter, std::uint64_t delta = 1) noexcept
{
    counter.store(counter.load(std::memory_order_relaxed) + delta, std::memory_order_relaxed);
}

/// Smooth ramp 0 → 1 with zero slope at both ends.
double smoothstep(double x) noexcept
{
    const double p = std::clamp(x, 0.0, 1.0);
    return p * p * (3.0 - 2.0 * p);
}

/// Libraries whose code a haptic device's driver runs on the haptic thread (the Falcon's libusb);
/// one that is not loaded locks nothing.
const char *const kDeviceObjects[] = {"libusb-1.0.so", nullptr};

/// Bytes locked from the start of an object of unknown size that may not be a heap block (the
/// device): its page and the next three, as far as they are mapped.
constexpr std::size_t kUnknownObjectBytes = 16 * 1024;

platform::ThreadConfig hapticThreadConfig(platform::SchedPolicy policy) noexcept
{
    platform::ThreadConfig c = platform::kHapticThread;
    if (policy == platform::SchedPolicy::Other) {
        c.policy = platform::SchedPolicy::Other;
        c.relativePriority = 0;
    }
    return c;
}

} // namespace

Result<void> HapticTaskConfig::validate() const noexcept
{
    if (!(servoRateHz >= 100.0 && servoRateHz <= 10000.0))
        return unexpected(Errc::InvalidArgument, "Servo rate must be in [100, 10000] Hz");
    DT_TRY(renderer.validate());
    if (!(maxForceRate > 0.0) || !std::isfinite(maxForceRate))
        return unexpected(Errc::InvalidArgument,
                          "Force rate limit must be a positive number of N/s");
    if (!(mapping.scale > 0.0) || !std::isfinite(mapping.scale) ||
        !std::isfinite(mapping.offset.x) || !std::isfinite(mapping.offset.y) ||
        !std::isfinite(mapping.offset.z))
        return unexpected(Errc::InvalidArgument,
                          "Device mapping needs a positive scale and a finite offset");
    if (mapping.clutchButton < -1 || mapping.clutchButton > 31)
        return unexpected(Errc::InvalidArgument, "Clutch button must be -1 (none) or 0..31");
    if (watchdogMissedDeadlines < 1 || watchdogDeviceTimeouts < 1)
        return unexpected(Errc::InvalidArgument, "Watchdog limits must be at least 1");
    if (!(rampTime > 0.0) || !std::isfinite(rampTime))
        return unexpected(Errc::InvalidArgument, "Force ramp time must be > 0 s");
    if (telemetryIntervalMs < 1 || telemetryIntervalMs > 1000 || reconnectIntervalMs < 1)
        return unexpected(Errc::InvalidArgument,
                          "Telemetry interval must be 1..1000 ms and reconnect interval >= 1 ms");
    return ok();
}

Result<std::unique_ptr<HapticTask>> HapticTask::create(const HapticTaskConfig &config,
                                                       hal::HapticDevice &device,
                                                       DepthHandoff &handoff,
                                                       platform::Clock &clock)
{
    DT_TRY(config.validate());
    haptics::RendererConfig rc = config.renderer;
    const double deviceMax = device.capabilities().maxForce;
    if (deviceMax > 0.0 && deviceMax < rc.maxForce)
        rc.maxForce = deviceMax;
    auto renderer = haptics::makeRenderer(config.method, rc, handoff.width(), handoff.height());
    if (!renderer)
        return unexpected(renderer.error());
    HapticTaskConfig effective = config;
    effective.renderer = rc;
    try {
        return std::unique_ptr<HapticTask>(
            new HapticTask(effective, device, handoff, clock, std::move(*renderer)));
    } catch (const std::bad_alloc &) {
        return unexpected(Errc::OutOfResources, "Not enough memory for the haptic task");
    }
}

HapticTask::HapticTask(const HapticTaskConfig &config, hal::HapticDevice &device,
                       DepthHandoff &handoff, platform::Clock &clock,
                       std::unique_ptr<haptics::HapticRenderer> renderer)
    : config_(config), device_(device), handoff_(handoff), clock_(clock),
      renderer_(std::move(renderer)), ring_(std::make_unique<Ring>()),
      timer_(clock, platform::fromSeconds(1.0 / config.servoRateHz)),
      maxForce_(config.renderer.maxForce), period_(1.0 / config.servoRateHz),
      enabled_(config.startEnabled), stiffness_(config.renderer.stiffness),
      rendererStiffness_(config.renderer.stiffness), offset_(config.mapping.offset),
      wakeHist_(std::make_unique<LatencyHistogram>()),
      updateHist_(std::make_unique<LatencyHistogram>()),
      periodHist_(std::make_unique<LatencyHistogram>())
{
    platform::RealtimeThreadOptions options;
    options.requireRt = config.requireRt;
    options.lockMemory = config.lockMemory;
    options.lockMode = config.memoryLock;
    options.cpuAffinity = config.cpu;
    collectLockRegions();
    options.regions = lockRegions_;
    options.regionCount = lockRegionCount_;
    options.lockObjects = kDeviceObjects;
    thread_ = std::make_unique<platform::RealtimeThread>(
        hapticThreadConfig(config.policy), options,
        [this](platform::StopToken stop) noexcept { run(stop); });
}

void HapticTask::collectLockRegions() noexcept
{
    // What the haptic thread reads and writes besides its stack and static data: this object
    // (counters, timer, state), the telemetry ring, the hand-off and its pixels, the renderer (its
    // height field and force stage are members: no buffer of its own for finger, modified and
    // proxy-graph; makeRenderer() allocates it with new) and the device object.
    const platform::MemoryRegion regions[] = {
        {this, sizeof(*this)},
        {ring_.get(), sizeof(Ring)},
        {&handoff_, sizeof(DepthHandoff)},
        handoff_.pixelRegion(),
        {renderer_.get(), platform::heapBlockBytes(renderer_.get(), kUnknownObjectBytes)},
        {dynamic_cast<const void *>(&device_), kUnknownObjectBytes},
    };
    static_assert(sizeof(regions) <= sizeof(lockRegions_));
    lockRegionCount_ = 0;
    for (const platform::MemoryRegion &r : regions)
        lockRegions_[lockRegionCount_++] = r;
}

HapticTask::~HapticTask()
{
    stop();
}

Result<void> HapticTask::start()
{
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (started_)
            return unexpected(Errc::InvalidState, "Haptic task already started");
        started_ = true;
    }
    if (device_.state() == hal::HapticDevice::State::Closed) {
        if (auto r = device_.open(); !r && r.error().code != Errc::NoDevice)
            return r;
    }
    // The haptic thread starts with the device if it is answering; otherwise the telemetry thread
    // polls for it (hot-plug) and hands it over once open.
    owner_.store(device_.isConnected() ? kRtOwns : kLost, std::memory_order_release);

    if (!config_.forceLogPath.empty()) {
        // Written under a temporary name beside it, renamed into place by stop() when complete.
        auto log = platform::OutputFile::open(config_.forceLogPath);
        if (!log)
            return unexpected(Errc::Io, "Failed to create the force log", log.error().sysErrno);
        forceLog_ = std::move(*log);
        std::fputs(
            "t,hip_x,hip_y,hip_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,contact,released,play_t,gain\n",
            forceLog_.stream());
    }
    serviceStop_ = false;
    service_ = std::make_unique<platform::RealtimeThread>(
        platform::kTelemetryThread, platform::kPlainThreadOptions,
        [this](platform::StopToken) { serviceLoop(); });
    Result<void> started = service_->start();
    if (started)
        started = thread_->start();
    if (!started) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            serviceStop_ = true;
        }
        wake_.notify_all();
        service_->join();
        forceLog_.abort();
        return started;
    }
    return ok();
}

void HapticTask::requestStop() noexcept
{
    stopRequested_.store(true, std::memory_order_release);
}

void HapticTask::stop() noexcept
{
    requestStop();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!started_ || stopped_)
            return;
        stopped_ = true;
    }
    thread_->requestStop();
    thread_->join();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        serviceStop_ = true;
    }
    wake_.notify_all();
    if (service_)
        service_->join();
    std::lock_guard<std::mutex> lock(mutex_);
    drainLocked();
    if (forceLog_.isOpen()) {
        // A write that failed (a full disk) shows in the stream's error flag, at the close or at
        // the rename; then nothing is left under the log's name.
        if (!forceLog_.commit())
            forceLogLost_ = true;
    }
}

const platform::RealtimeThreadReport &HapticTask::threadReport() const noexcept
{
    return thread_->report();
}

// ---------------------------------------------------------------------------------------------
// The haptic thread. Nothing below may allocate, lock, log, write or throw.

void HapticTask::run(platform::StopToken stop) noexcept
{
    if (config_.threadHook != nullptr)
        config_.threadHook(config_.threadHookUser);
    const platform::PageFaults atStart = platform::threadPageFaults();
    platform::PageFaults afterWarmup{};
    std::uint64_t cycles = 0;
    timer_.start();
    while (!stop.stopRequested() && !stopRequested()) {
        const platform::PeriodicWait wait = timer_.wait();
        if (wait.cancelled || stop.stopRequested() || stopRequested())
            continue;
        cycle(wait);
        ++cycles;
        if (cycles == kWarmupUpdates) {
            afterWarmup = platform::threadPageFaults();
            faultsWarmup_.store(afterWarmup.minor + afterWarmup.major - atStart.minor -
                                    atStart.major,
                                std::memory_order_relaxed);
        } else if (cycles > kWarmupUpdates && cycles % 256 == 0) {
            countFaults(afterWarmup);
        }
    }
    if (cycles > kWarmupUpdates)
        countFaults(afterWarmup);
    if (owner_.load(std::memory_order_acquire) == kRtOwns)
        (void)device_.commandForce({});
    publishForce({});
    // A simulated clock must not wait for this thread to sleep again.
    if (auto *manual = dynamic_cast<platform::ManualClock *>(&clock_))
        manual->detachThread();
}

void HapticTask::countFaults(const platform::PageFaults &since) noexcept
{
    const platform::PageFaults now = platform::threadPageFaults();
    faultsMinor_.store(now.minor - since.minor, std::memory_order_relaxed);
    faultsMajor_.store(now.major - since.major, std::memory_order_relaxed);
}

void HapticTask::publishForce(const glm::dvec3 &f) noexcept
{
    force_.store({f.x, f.y, f.z});
}

glm::dvec3 HapticTask::lastForce() const noexcept
{
    const auto f = force_.load();
    return {f[0], f[1], f[2]};
}

bool HapticTask::lastPose(glm::dvec3 &hip, glm::dvec3 &proxy) const noexcept
{
    const auto p = pose_.load();
    if (p[6] == 0.0)
        return false;
    hip = {p[0], p[1], p[2]};
    proxy = {p[3], p[4], p[5]};
    return true;
}

void HapticTask::zeroForce() noexcept
{
    prevForce_ = {};
    phase_ = 0.0;
    gain_.store(0.0, std::memory_order_relaxed);
    publishForce({});
}

void HapticTask::loseDevice(TelemetrySample &sample) noexcept
{
    zeroForce();
    bump(deviceLosses_);
    owner_.store(kLost, std::memory_order_release);
    sample.flags |= TelemetrySample::DeviceLost;
}

// One haptic update, step by step. Each step is real-time safe and always inlined, so cycle() costs
// what one function did; the arithmetic is the same, in the same order, as before the split.

[[gnu::always_inline]] inline TelemetrySample
HapticTask::beginSample(const platform::PeriodicWait &wait) const noexcept
{
    TelemetrySample sample;
    sample.wakeNs = wait.wakeTime.time_since_epoch().count();
    sample.wakeLatencyNs = static_cast<std::int32_t>(
        std::clamp<std::int64_t>(wait.latency.count(), INT32_MIN, INT32_MAX));
    sample.missedPeriods =
        static_cast<std::uint32_t>(std::min<std::uint64_t>(wait.missedPeriods, UINT32_MAX));
    if (wait.overrun)
        sample.flags |= TelemetrySample::Overrun;
    sample.cycle = updates_.load(std::memory_order_relaxed) + 1;
    return sample;
}

[[gnu::always_inline]] inline void HapticTask::finishCycle(CycleContext &c) noexcept
{
    c.sample.gain = static_cast<float>(gain_.load(std::memory_order_relaxed));
    c.sample.updateNs = static_cast<std::int32_t>(
        std::clamp<std::int64_t>((clock_.now() - c.begin).count(), 0, INT32_MAX));
    (void)ring_->tryPush(c.sample);
    updates_.store(c.sample.cycle, std::memory_order_release);
}

[[gnu::always_inline]] inline bool
HapticTask::watchDeadlines(const platform::PeriodicWait &wait) noexcept
{
    // Watchdog 1: the loop itself is late. More than N deadlines missed in a row → zero force now;
    // the ramp brings the force back once the deadlines are kept again.
    if (wait.overrun) {
        missedInARow_ += 1 + static_cast<int>(std::min<std::uint64_t>(wait.missedPeriods, 1000000));
    } else {
        missedInARow_ = 0;
    }
    // A wake-up as late as that many deadlines (the process was stopped, SIGSTOP then SIGCONT,
    // while the thread slept; a suspended machine) missed them as surely as an overrun does, and
    // the device moved meanwhile: this update commands no force either, not only the next one.
    const double lateSeconds = platform::toSeconds(wait.latency);
    const bool wokeLate =
        !wait.overrun && lateSeconds > (config_.watchdogMissedDeadlines + 1) * period_;
    return wokeLate || missedInARow_ > config_.watchdogMissedDeadlines;
}

[[gnu::always_inline]] inline void HapticTask::takeFrames() noexcept
{
    // Newest depth pair, without waiting; the held pair stays if the decoder stalls.
    DepthPair pair;
    if (handoff_.acquire(pair)) {
        if (renderer_->setFrames(pair.current, pair.hasNext ? &pair.next : nullptr))
            haveFrames_ = true;
    }
}

[[gnu::always_inline]] inline bool HapticTask::ownDevice(TelemetrySample &sample) noexcept
{
    // Device ownership: while lost, the telemetry thread closes and opens it; don't touch it.
    std::uint8_t owner = owner_.load(std::memory_order_acquire);
    if (owner == kRestored) {
        owner_.store(kRtOwns, std::memory_order_release);
        owner = kRtOwns;
        needReset_ = true;
        clutched_ = false;
        zeroForce();
    }
    if (owner != kRtOwns) {
        sample.flags |= TelemetrySample::DeviceLost;
        return false;
    }
    return true;
}

[[gnu::always_inline]] inline void HapticTask::noteDeviceCall(platform::Duration took) noexcept
{
    const std::int64_t ns = took.count();
    if (ns > deviceCallMaxNs_.load(std::memory_order_relaxed))
        deviceCallMaxNs_.store(ns, std::memory_order_relaxed);
}

[[gnu::always_inline]] inline bool HapticTask::readDevice(hal::HapticState &state,
                                                          TelemetrySample &sample) noexcept
{
    const platform::TimePoint callBegin = clock_.now();
    auto r = device_.read(state);
    noteDeviceCall(clock_.now() - callBegin);
    if (!r) {
        if (r.error().code == Errc::Timeout) {
            sample.flags |= TelemetrySample::DeviceTimeout;
            if (++timeoutsInARow_ > config_.watchdogDeviceTimeouts && !deviceFailed_.load()) {
                (void)device_.commandForce({});
                zeroForce();
                deviceFailed_.store(true, std::memory_order_release);
                bump(watchdogTrips_);
                sample.flags |= TelemetrySample::WatchdogTrip;
            }
        } else {
            // Unplugged (NoDevice) or closed under us: the device outputs zero force.
            loseDevice(sample);
        }
        return false;
    }
    timeoutsInARow_ = 0;
    deviceFailed_.store(false, std::memory_order_relaxed);
    return true;
}

[[gnu::always_inline]] inline glm::dvec3 HapticTask::mapToScene(const hal::HapticState &state,
                                                                TelemetrySample &sample) noexcept
{
    // Device → scene, with the clutch.
    const glm::dvec3 p(state.position.x, state.position.y, state.position.z);
    const double scale = config_.mapping.scale;
    glm::dvec3 hip = scale * p + offset_;
    const int clutchButton = config_.mapping.clutchButton;
    const bool clutchHeld = clutchButton >= 0 && ((state.buttons >> clutchButton) & 1u) != 0;
    if (clutchHeld && !clutched_) {
        clutched_ = true;
        frozenHip_ = needReset_ ? hip : lastHip_;
    }
    if (clutched_) {
        if (!clutchHeld) {
            clutched_ = false;
            offset_ = frozenHip_ - scale * p; // re-centred: the HIP continues from where it was
        }
        hip = frozenHip_;
        sample.flags |= TelemetrySample::Clutched;
    }
    lastHip_ = hip;
    return hip;
}

[[gnu::always_inline]] inline void HapticTask::applyRestarts() noexcept
{
    // Seek or loop: the haptic time restarts (it may jump backwards); proxy and force are kept.
    const std::uint32_t restarts = clockRestarts_.load(std::memory_order_acquire);
    if (restarts != clockRestartsDone_) {
        clockRestartsDone_ = restarts;
        lastT_ = -1e300;
        renderer_->restartClock();
    }
    // Recenter: re-seat the proxy above the HIP, restart the haptic time and ramp the force in
    // from zero.
    const std::uint32_t reseats = reseatRequests_.load(std::memory_order_acquire);
    if (reseats != reseatsDone_) {
        reseatsDone_ = reseats;
        needReset_ = true;
        lastT_ = -1e300;
        phase_ = 0.0;
    }
}

[[gnu::always_inline]] inline glm::dvec3 HapticTask::render(const glm::dvec3 &hip,
                                                            CycleContext &c) noexcept
{
    TelemetrySample &sample = c.sample;
    if (!haveFrames_) {
        sample.flags |= TelemetrySample::NoFrames;
        sample.hip = hip;
        sample.proxy = hip;
        return {};
    }
    if (needReset_) {
        // Seat the proxy above the top of the scene box: this update then stops it on the surface
        // directly over the HIP (a height field has no overhang), so a finger that is already
        // inside an object at start or after a reconnect feels it, ramped in, instead of being
        // left inside with no force.
        const double top = 0.5 * config_.renderer.box.depth + 1e-3;
        renderer_->reset({hip.x, hip.y, std::max(hip.z, top)});
        needReset_ = false;
    }
    const double t = std::max(platform::toSeconds(c.begin - handoff_.mediaOrigin()), lastT_);
    lastT_ = t;
    // Run-time stiffness (setStiffness()) goes into the renderer, so its safety and slew limit
    // act on the force the device is sent.
    const double k = stiffness_.load(std::memory_order_relaxed);
    if (k != rendererStiffness_) {
        renderer_->setStiffness(k);
        rendererStiffness_ = k;
    }
    const haptics::HapticOutput out = renderer_->update(hip, t);
    sample.t = t;
    sample.hip = out.hip;
    sample.proxy = out.proxy;
    sample.flags |= TelemetrySample::Rendered;
    bump(rendered_);
    if (out.contact) {
        sample.flags |= TelemetrySample::Contact;
        bump(contacts_);
    }
    if (out.released) {
        sample.flags |= TelemetrySample::Released;
        bump(releases_);
    }
    pose_.store({out.hip.x, out.hip.y, out.hip.z, out.proxy.x, out.proxy.y, out.proxy.z, 1.0});
    return out.force;
}

[[gnu::always_inline]] inline double HapticTask::rampGain(CycleContext &c) noexcept
{
    // Enable ramp; a late loop or the clutch forces the gain to zero.
    if (c.late) {
        if (phase_ > 0.0 || glm::length(prevForce_) > 0.0) {
            bump(watchdogTrips_);
            c.sample.flags |= TelemetrySample::WatchdogTrip;
        }
        phase_ = 0.0;
        prevForce_ = {};
    } else {
        const double step = period_ / config_.rampTime;
        phase_ = enabled() ? std::min(1.0, phase_ + step) : std::max(0.0, phase_ - step);
    }
    const double gain = smoothstep(phase_);
    gain_.store(gain, std::memory_order_relaxed);
    return gain;
}

[[gnu::always_inline]] inline glm::dvec3
HapticTask::shapeForce(glm::dvec3 target, double gain, const CycleContext &c) const noexcept
{
    const bool late = c.late;
    if (clutched_ || late)
        target = {};
    target = haptics::limitForce(gain * target, maxForce_);

    // Force-rate limit over the time since the last command (at most a few periods, so a re-sync
    // after an overrun does not allow a jump).
    double dt = period_;
    if (havePrevCommand_)
        dt = std::clamp(platform::toSeconds(c.begin - prevCommandTime_), 0.0, 4.0 * period_);
    return late ? glm::dvec3{}
                : haptics::slewForce(prevForce_, target, config_.maxForceRate * dt, maxForce_);
}

[[gnu::always_inline]] inline bool HapticTask::command(const glm::dvec3 &force,
                                                       CycleContext &c) noexcept
{
    const platform::TimePoint callBegin = clock_.now();
    auto r = device_.commandForce({force.x, force.y, force.z});
    noteDeviceCall(clock_.now() - callBegin);
    if (!r) {
        if (r.error().code == Errc::NoDevice || r.error().code == Errc::InvalidState) {
            loseDevice(c.sample);
            return false;
        }
        // Timeout or a rejected value: the device keeps its previous output; try again next cycle.
    }
    prevForce_ = force;
    prevCommandTime_ = c.begin;
    havePrevCommand_ = true;
    return true;
}

[[gnu::always_inline]] inline void HapticTask::recordForce(const glm::dvec3 &force,
                                                           TelemetrySample &sample) noexcept
{
    publishForce(force);
    sample.force = force;
    const double magnitude = glm::length(force);
    if (magnitude > maxForceSeen_.load(std::memory_order_relaxed))
        maxForceSeen_.store(magnitude, std::memory_order_relaxed);
}

void HapticTask::cycle(const platform::PeriodicWait &wait) noexcept
{
    CycleContext c{wait.wakeTime, beginSample(wait), false};
    c.late = watchDeadlines(wait);
    takeFrames();
    hal::HapticState state;
    if (ownDevice(c.sample) && readDevice(state, c.sample)) {
        const glm::dvec3 hip = mapToScene(state, c.sample);
        applyRestarts();
        const glm::dvec3 target = render(hip, c);
        const double gain = rampGain(c);
        const glm::dvec3 force = shapeForce(target, gain, c);
        if (command(force, c))
            recordForce(force, c.sample);
    }
    finishCycle(c);
}

} // namespace depthtouch::haptic_task
