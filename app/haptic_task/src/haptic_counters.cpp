// HapticCounters' readers: the last force and pose through their seqlocks, and the stats.
#include "depthtouch/haptic_task/haptic_counters.h"

namespace depthtouch::haptic_task {

glm::dvec3 HapticCounters::lastForce() const noexcept
{
    const auto f = force_.load();
    return {f[0], f[1], f[2]};
}

bool HapticCounters::lastPose(glm::dvec3 &hip, glm::dvec3 &proxy) const noexcept
{
    const auto p = pose_.load();
    if (p[6] == 0.0)
        return false;
    hip = {p[0], p[1], p[2]};
    proxy = {p[3], p[4], p[5]};
    return true;
}

void HapticCounters::fill(HapticStats &s) const noexcept
{
    s.updates = updates_.load(std::memory_order_acquire);
    s.renderedUpdates = rendered_.load(std::memory_order_relaxed);
    s.contactUpdates = contacts_.load(std::memory_order_relaxed);
    s.safetyReleases = releases_.load(std::memory_order_relaxed);
    s.maxForce = maxForceSeen_.load(std::memory_order_relaxed);
    s.maxForceStep = maxStepSeen_.load(std::memory_order_relaxed);
    s.energy = energy_.load(std::memory_order_relaxed);
    s.energyPeak = energyPeak_.load(std::memory_order_relaxed);
    s.deviceCallMaxUs =
        static_cast<double>(deviceCallMaxNs_.load(std::memory_order_relaxed)) * 1e-3;
    s.pageFaultsMinor = faultsMinor_.load(std::memory_order_relaxed);
    s.pageFaultsMajor = faultsMajor_.load(std::memory_order_relaxed);
    s.pageFaultsWarmup = faultsWarmup_.load(std::memory_order_relaxed);
}

} // namespace depthtouch::haptic_task
