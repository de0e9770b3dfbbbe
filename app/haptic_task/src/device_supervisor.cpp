// DeviceSupervisor's telemetry-thread side: reopening a lost device (hot-plug recovery).
#include "depthtouch/haptic_task/device_supervisor.h"

#include <chrono>

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Haptic)

namespace depthtouch::haptic_task {

using platform::TimePoint;

void DeviceSupervisor::supervise()
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
        bump(reconnects_);
        // This loss is over: the next one is said again, even when it comes before this thread
        // next finds the device in use (a loaded machine, or an unplug within one interval).
        lostLogged_ = false;
        owner_.store(kRestored, std::memory_order_release);
    }
}

} // namespace depthtouch::haptic_task
