// HapticTask's telemetry thread (normal priority, kTelemetryThread): drains the telemetry ring into
// the histograms and the force log, reopens a lost device, and builds the stats.
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "depthtouch/haptic_task/haptic_task.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Haptic)

namespace depthtouch::haptic_task {

using platform::TimePoint;

void HapticTask::serviceLoop()
{
    std::unique_lock<std::mutex> lock(mutex_);
    while (!serviceStop_) {
        drainLocked();
        lock.unlock();
        superviseDevice();
        lock.lock();
        wake_.wait_for(lock, std::chrono::milliseconds(config_.telemetryIntervalMs),
                       [this] { return serviceStop_; });
    }
}

void HapticTask::superviseDevice()
{
    if (owner_.load(std::memory_order_acquire) != kLost) {
        lostLogged_ = false;
        return;
    }
    if (!lostLogged_) {
        DT_LOG(Haptic, Warning, "Haptic device lost: zero force; trying to reopen it every %d ms",
               config_.reconnectIntervalMs);
        lostLogged_ = true;
    }
    const TimePoint now = platform::SteadyClock::instance().now();
    if (now - lastReconnectTry_ < std::chrono::milliseconds(config_.reconnectIntervalMs))
        return;
    lastReconnectTry_ = now;
    device_.close();
    if (auto r = device_.open(); r && device_.isConnected()) {
        DT_LOG(Haptic, Info, "Haptic device back: haptics resume with a %.0f ms ramp",
               config_.rampTime * 1e3);
        reconnects_.store(reconnects_.load(std::memory_order_relaxed) + 1,
                          std::memory_order_relaxed);
        // This loss is over: the next one is said again, even when it comes before this thread
        // next finds the device in use (a loaded machine, or an unplug within one interval).
        lostLogged_ = false;
        owner_.store(kRestored, std::memory_order_release);
    }
}

void HapticTask::drainTelemetry()
{
    std::lock_guard<std::mutex> lock(mutex_);
    drainLocked();
}

void HapticTask::drainLocked()
{
    const auto periodNs = static_cast<std::int64_t>(std::llround(period_ * 1e9));
    TelemetrySample s;
    while (ring_->tryPop(s)) {
        wakeHist_->add(s.wakeLatencyNs);
        updateHist_->add(s.updateNs);
        const bool onTime = (s.flags & TelemetrySample::Overrun) == 0;
        if (prevWakeNs_ >= 0 && onTime && s.cycle == prevCycle_ + 1)
            periodHist_->add(std::llabs(s.wakeNs - prevWakeNs_ - periodNs));
        prevWakeNs_ = s.wakeNs;
        prevCycle_ = s.cycle;
        if (firstWakeNs_ < 0)
            firstWakeNs_ = s.wakeNs;
        if (forceLog_.isOpen() && (s.flags & TelemetrySample::Rendered) != 0) {
            // play_t: seconds since the first update, monotonic through loops and seeks (t is
            // the media time, which restarts); gain: the output ramp's factor on the force.
            std::fprintf(forceLog_.stream(),
                         "%.6f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.6f,%.6f,%.6f,%d,%d,%.6f,%.4f\n", s.t,
                         s.hip.x, s.hip.y, s.hip.z, s.proxy.x, s.proxy.y, s.proxy.z, s.force.x,
                         s.force.y, s.force.z, (s.flags & TelemetrySample::Contact) != 0 ? 1 : 0,
                         (s.flags & TelemetrySample::Released) != 0 ? 1 : 0,
                         static_cast<double>(s.wakeNs - firstWakeNs_) * 1e-9,
                         static_cast<double>(s.gain));
        }
    }
}

HapticStats HapticTask::stats()
{
    std::lock_guard<std::mutex> lock(mutex_);
    drainLocked();
    HapticStats s;
    s.servoRateHz = config_.servoRateHz;
    s.forceLogLost = forceLogLost_ || (forceLog_.isOpen() && std::ferror(forceLog_.stream()) != 0);
    s.updates = updates_.load(std::memory_order_acquire);
    s.renderedUpdates = rendered_.load(std::memory_order_relaxed);
    s.contactUpdates = contacts_.load(std::memory_order_relaxed);
    s.overruns = timer_.overruns();
    s.missedPeriods = timer_.missedPeriods();
    s.watchdogTrips = watchdogTrips_.load(std::memory_order_relaxed);
    s.safetyReleases = releases_.load(std::memory_order_relaxed) + s.watchdogTrips;
    s.deviceLosses = deviceLosses_.load(std::memory_order_relaxed);
    s.reconnects = reconnects_.load(std::memory_order_relaxed);
    s.telemetryDropped = ring_->dropped();
    s.maxForce = maxForceSeen_.load(std::memory_order_relaxed);
    s.deviceMaxForce = device_.capabilities().maxForce;
    s.deviceCallMaxUs =
        static_cast<double>(deviceCallMaxNs_.load(std::memory_order_relaxed)) * 1e-3;
    s.wakeLatency = wakeHist_->summary();
    s.updateTime = updateHist_->summary();
    s.periodError = periodHist_->summary();
    if (firstWakeNs_ >= 0 && prevWakeNs_ > firstWakeNs_)
        s.runSeconds = static_cast<double>(prevWakeNs_ - firstWakeNs_) * 1e-9;
    if (thread_->joinable() || thread_->finished()) {
        char line[256];
        s.thread = thread_->report().format(line, sizeof line);
        s.lockedMiB = static_cast<double>(thread_->report().lockedBytes) / (1024.0 * 1024.0);
    }
    s.pageFaultsMinor = faultsMinor_.load(std::memory_order_relaxed);
    s.pageFaultsMajor = faultsMajor_.load(std::memory_order_relaxed);
    s.pageFaultsWarmup = faultsWarmup_.load(std::memory_order_relaxed);
    return s;
}

} // namespace depthtouch::haptic_task
