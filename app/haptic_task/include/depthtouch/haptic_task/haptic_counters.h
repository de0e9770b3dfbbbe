#pragma once
/// \file
/// \brief HapticCounters: what the haptic thread publishes to the other threads while it runs (the
/// update counters, the ramp gain, the last force and pose, the longest device call, the page
/// faults), lock-free (docs/architecture.md §5). HapticTask's observers (updates(), gain(),
/// lastForce(), lastPose()) and stats() read them.

#include <atomic>
#include <cstdint>

#include <glm/vec3.hpp>

#include "depthtouch/haptic_task/haptic_stats.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/seqlock.h"

namespace depthtouch::haptic_task {

/// \brief Adds \a delta to a counter only the calling thread writes (a relaxed load and store: no
/// read-modify-write, which a single writer does not need).
inline void bump(std::atomic<std::uint64_t> &counter, std::uint64_t delta = 1) noexcept
{
    counter.store(counter.load(std::memory_order_relaxed) + delta, std::memory_order_relaxed);
}

/// \brief Raises \a most to \a value where that is larger, for a value only the calling thread
/// writes (a relaxed load and store, as bump()).
template <typename T> inline void keepMax(std::atomic<T> &most, T value) noexcept
{
    if (value > most.load(std::memory_order_relaxed))
        most.store(value, std::memory_order_relaxed);
}

/// \brief The counters and values the haptic thread publishes.
///
/// Thread-safety: the writers (count*(), note*(), set*(), publish*()) are for the haptic thread
/// only (ServoLoop; one writer per value) and real-time safe: inline, a few relaxed atomic stores
/// or a seqlock store, no allocation, no lock. The readers are thread-safe: updates() acquires
/// what countUpdate() released, the other counters are relaxed (independent statistics), the force
/// and the pose are read whole through their seqlocks.
class HapticCounters {
public:
    HapticCounters() = default;
    DT_DISABLE_COPY_AND_MOVE(HapticCounters)

    /// \name Haptic thread only (real-time safe)
    ///@{
    /// \return the cycles counted so far, read by their only writer.
    [[nodiscard]] std::uint64_t updatesSoFar() const noexcept
    {
        return updates_.load(std::memory_order_relaxed);
    }
    /// Counts the update numbered \a cycle (1-based) as done.
    void countUpdate(std::uint64_t cycle) noexcept
    {
        updates_.store(cycle, std::memory_order_release);
    }
    void countRendered() noexcept { bump(rendered_); }
    void countContact() noexcept { bump(contacts_); }
    /// Counts a release of the renderer's force-jump safety (paper IV.C).
    void countRelease() noexcept { bump(releases_); }
    /// Keeps the largest commanded force magnitude, N.
    void noteForce(double magnitude) noexcept { keepMax(maxForceSeen_, magnitude); }
    /// Keeps the largest change of the commanded force from one command to the next, N
    /// (HapticStats::maxForceStep).
    void noteStep(double magnitude) noexcept { keepMax(maxStepSeen_, magnitude); }
    /// The passivity observer's energy and peak so far, J (HapticStats::energy).
    void setEnergy(double energy, double peak) noexcept
    {
        energy_.store(energy, std::memory_order_relaxed);
        energyPeak_.store(peak, std::memory_order_relaxed);
    }
    /// Keeps the longest device call (HapticStats::deviceCallMaxUs).
    void noteDeviceCall(platform::Duration took) noexcept
    {
        keepMax(deviceCallMaxNs_, static_cast<std::int64_t>(took.count()));
    }
    /// The ramp gain in [0, 1].
    void setGain(double gain) noexcept { gain_.store(gain, std::memory_order_relaxed); }
    /// The last commanded force, N.
    void publishForce(const glm::dvec3 &f) noexcept { force_.store({f.x, f.y, f.z}); }
    /// The HIP and the proxy of a rendered update, m, scene box.
    void publishPose(const glm::dvec3 &hip, const glm::dvec3 &proxy) noexcept
    {
        pose_.store({hip.x, hip.y, hip.z, proxy.x, proxy.y, proxy.z, 1.0});
    }
    /// The page faults (minor + major) of the warm-up.
    void setWarmupFaults(std::uint64_t faults) noexcept
    {
        faultsWarmup_.store(faults, std::memory_order_relaxed);
    }
    /// The page faults since the warm-up.
    void setFaults(std::uint64_t minor, std::uint64_t major) noexcept
    {
        faultsMinor_.store(minor, std::memory_order_relaxed);
        faultsMajor_.store(major, std::memory_order_relaxed);
    }
    ///@}

    /// \name Readers (thread-safe)
    ///@{
    /// \return cycles of the haptic loop so far.
    [[nodiscard]] std::uint64_t updates() const noexcept
    {
        return updates_.load(std::memory_order_acquire);
    }
    /// \return the current ramp gain in [0, 1].
    [[nodiscard]] double gain() const noexcept { return gain_.load(std::memory_order_relaxed); }
    /// \return the last force commanded, N.
    [[nodiscard]] glm::dvec3 lastForce() const noexcept;
    /// \brief The HIP and the proxy of the last rendered update, m. \return false before one.
    bool lastPose(glm::dvec3 &hip, glm::dvec3 &proxy) const noexcept;
    /// \brief Fills updates, renderedUpdates, contactUpdates, safetyReleases (the renderer's
    /// releases only: the caller adds the watchdog trips), maxForce, maxForceStep, energy,
    /// deviceCallMaxUs and
    /// the page faults of \a s.
    void fill(HapticStats &s) const noexcept;
    ///@}

private:
    std::atomic<std::uint64_t> updates_{0};
    std::atomic<std::uint64_t> rendered_{0};
    std::atomic<std::uint64_t> contacts_{0};
    std::atomic<std::uint64_t> releases_{0};
    std::atomic<double> maxForceSeen_{0.0};        ///< N.
    std::atomic<double> maxStepSeen_{0.0};         ///< N (noteStep()).
    std::atomic<double> energy_{0.0};              ///< J (setEnergy()).
    std::atomic<double> energyPeak_{0.0};          ///< J.
    std::atomic<std::int64_t> deviceCallMaxNs_{0}; ///< Longest device call, ns.
    std::atomic<double> gain_{0.0};
    platform::SeqLockArray<3> force_; ///< Last commanded force, N (lastForce()).
    platform::SeqLockArray<7> pose_;  ///< HIP, proxy (m) and a valid flag (lastPose()).
    // Page faults of the haptic thread (HapticStats::pageFaults*).
    std::atomic<std::uint64_t> faultsMinor_{0};
    std::atomic<std::uint64_t> faultsMajor_{0};
    std::atomic<std::uint64_t> faultsWarmup_{0};
};

} // namespace depthtouch::haptic_task
