#include "depthtouch/haptic_task/haptic_task.h"

#include <cmath>
#include <new>
#include <utility>

#include "depthtouch/options/option_range.h"
#include "depthtouch/platform/memory_lock.h"
#include "depthtouch/platform/thread_config.h"

namespace depthtouch::haptic_task {

namespace {

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
    static_assert(options::kServoRate.min == 100.0 && options::kServoRate.max == 10000.0,
                  "the message below says the range");
    if (!options::kServoRate.contains(servoRateHz))
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
    : config_(config), device_(device), handoff_(handoff), ring_(std::make_unique<TelemetryRing>()),
      controls_(config_.startEnabled, config_.renderer.stiffness), supervisor_(config_, device),
      loop_(config_, device, handoff, clock, std::move(renderer), *ring_, controls_, counters_,
            supervisor_),
      service_(config_, *ring_, supervisor_)
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
        [this](platform::StopToken stop) noexcept { loop_.run(stop); });
}

void HapticTask::collectLockRegions() noexcept
{
    // What the haptic thread reads and writes besides its stack and static data: this object
    // (counters, timer, state), the telemetry ring, the hand-off and its pixels, the renderer (its
    // height field and force stage are members: no buffer of its own for finger, modified and
    // proxy-graph; makeRenderer() allocates it with new) and the device object.
    const platform::MemoryRegion regions[] = {
        {this, sizeof(*this)},
        {ring_.get(), sizeof(TelemetryRing)},
        {&handoff_, sizeof(DepthHandoff)},
        handoff_.pixelRegion(),
        {loop_.renderer(), platform::heapBlockBytes(loop_.renderer(), kUnknownObjectBytes)},
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
    supervisor_.begin();
    DT_TRY(service_.openLog());
    Result<void> started = service_.start();
    if (started)
        started = thread_->start();
    if (!started) {
        service_.halt();
        service_.abortLog();
        return started;
    }
    return ok();
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
    service_.halt();
    service_.finish();
}

const platform::RealtimeThreadReport &HapticTask::threadReport() const noexcept
{
    return thread_->report();
}

HapticStats HapticTask::stats()
{
    HapticStats s;
    service_.collect(s); // drains first
    counters_.fill(s);
    supervisor_.fill(s);
    s.safetyReleases += s.watchdogTrips; // renderer releases + watchdog trips
    s.overruns = loop_.timer().overruns();
    s.missedPeriods = loop_.timer().missedPeriods();
    s.telemetryDropped = ring_->dropped();
    s.deviceMaxForce = device_.capabilities().maxForce;
    if (thread_->joinable() || thread_->finished()) {
        char line[256];
        s.thread = thread_->report().format(line, sizeof line);
        s.lockedMiB = static_cast<double>(thread_->report().lockedBytes) / (1024.0 * 1024.0);
    }
    return s;
}

} // namespace depthtouch::haptic_task
