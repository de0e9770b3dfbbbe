// TelemetryService: HapticTask's telemetry thread (normal priority, kTelemetryThread): drains the
// telemetry ring into the histograms and the force log, and has a lost device reopened.
#include "depthtouch/haptic_task/telemetry_service.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>

#include "depthtouch/platform/thread_config.h"
#include "depthtouch/platform/work_queue.h"

namespace depthtouch::haptic_task {

TelemetryService::TelemetryService(const HapticTaskConfig &config, TelemetryRing &ring,
                                   DeviceSupervisor &supervisor)
    : config_(config), ring_(ring), supervisor_(supervisor),
      wakeHist_(std::make_unique<LatencyHistogram>()),
      updateHist_(std::make_unique<LatencyHistogram>()),
      periodHist_(std::make_unique<LatencyHistogram>())
{
}

Result<void> TelemetryService::openLog()
{
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
    return ok();
}

Result<void> TelemetryService::start()
{
    serviceStop_ = false;
    service_ = std::make_unique<platform::RealtimeThread>(
        platform::kTelemetryThread, platform::kPlainThreadOptions,
        [this](platform::StopToken) { serviceLoop(); });
    return service_->start();
}

void TelemetryService::halt() noexcept
{
    platform::raiseAndNotifyAll(mutex_, serviceStop_, wake_);
    if (service_)
        service_->join();
}

void TelemetryService::abortLog() noexcept
{
    forceLog_.abort();
}

void TelemetryService::finish() noexcept
{
    std::lock_guard<std::mutex> lock(mutex_);
    drainLocked();
    if (forceLog_.isOpen()) {
        // A write that failed (a full disk) shows in the stream's error flag, at the close or at
        // the rename; then nothing is left under the log's name.
        if (!forceLog_.commit())
            forceLogLost_ = true;
    }
}

void TelemetryService::serviceLoop()
{
    std::unique_lock<std::mutex> lock(mutex_);
    while (!serviceStop_) {
        drainLocked();
        lock.unlock();
        supervisor_.supervise();
        lock.lock();
        wake_.wait_for(lock, std::chrono::milliseconds(config_.telemetryIntervalMs),
                       [this] { return serviceStop_; });
    }
}

void TelemetryService::drain()
{
    std::lock_guard<std::mutex> lock(mutex_);
    drainLocked();
}

void TelemetryService::drainLocked()
{
    const auto periodNs =
        static_cast<std::int64_t>(std::llround((1.0 / config_.servoRateHz) * 1e9));
    TelemetrySample s;
    while (ring_.tryPop(s)) {
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

void TelemetryService::collect(HapticStats &s)
{
    std::lock_guard<std::mutex> lock(mutex_);
    drainLocked();
    s.servoRateHz = config_.servoRateHz;
    s.forceLogLost = forceLogLost_ || (forceLog_.isOpen() && std::ferror(forceLog_.stream()) != 0);
    s.wakeLatency = wakeHist_->summary();
    s.updateTime = updateHist_->summary();
    s.periodError = periodHist_->summary();
    if (firstWakeNs_ >= 0 && prevWakeNs_ > firstWakeNs_)
        s.runSeconds = static_cast<double>(prevWakeNs_ - firstWakeNs_) * 1e-9;
}

} // namespace depthtouch::haptic_task
