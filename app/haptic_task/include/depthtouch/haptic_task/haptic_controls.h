#pragma once
/// \file
/// \brief HapticControls: the run-time controls of the haptic task (stop, enable, stiffness,
/// re-seat, clock restart), set from any thread and read by the haptic thread at its next update
/// (docs/architecture.md §5). HapticTask's requestStop(), setEnabled(), setStiffness(),
/// requestReseat() and requestClockRestart() are these.

#include <atomic>
#include <cstdint>

#include "depthtouch/platform/macros.h"
#include "depthtouch/scene/stiffness.h"

namespace depthtouch::haptic_task {

/// \brief The controls: lock-free atomics written by the owner, the control thread or a signal
/// handler, read by the haptic thread (ServoLoop).
///
/// Thread-safety: every member function is thread-safe and async-signal-safe (one lock-free atomic
/// operation, no lock, no allocation). The setters publish with release, the observers read with
/// acquire; the haptic thread's per-update reads of the stiffness are relaxed (it only needs a
/// recent value, never anything published with it).
class HapticControls {
public:
    /// \param enabled haptics on at start (HapticTaskConfig::startEnabled).
    /// \param stiffness the configured surface stiffness, N/m.
    HapticControls(bool enabled, double stiffness) noexcept
        : enabled_(enabled), stiffness_(stiffness)
    {
    }
    DT_DISABLE_COPY_AND_MOVE(HapticControls)

    /// Asks the haptic loop to command zero force and return. Never undone.
    void requestStop() noexcept { stopRequested_.store(true, std::memory_order_release); }
    /// \return true once requestStop() was called.
    [[nodiscard]] bool stopRequested() const noexcept
    {
        return stopRequested_.load(std::memory_order_acquire);
    }

    /// Haptics on or off; the haptic thread ramps the force over HapticTaskConfig::rampTime.
    void setEnabled(bool enabled) noexcept { enabled_.store(enabled, std::memory_order_release); }
    [[nodiscard]] bool enabled() const noexcept { return enabled_.load(std::memory_order_acquire); }

    /// The surface stiffness, N/m: values outside the one range scene::kMinStiffness..
    /// kMaxStiffness (stiffness.h) are ignored, as the renderer ignores them.
    void setStiffness(double newtonsPerMetre) noexcept
    {
        if (scene::stiffnessInRange(newtonsPerMetre))
            stiffness_.store(newtonsPerMetre, std::memory_order_release);
    }
    /// \return the stiffness set, N/m.
    [[nodiscard]] double stiffness() const noexcept
    {
        return stiffness_.load(std::memory_order_acquire);
    }
    /// \return the stiffness set, N/m, read relaxed: for the haptic thread's update.
    [[nodiscard]] double stiffnessForUpdate() const noexcept
    {
        return stiffness_.load(std::memory_order_relaxed);
    }

    /// Asks for a re-seat of the proxy (HapticTask::requestReseat()).
    void requestReseat() noexcept { reseatRequests_.fetch_add(1, std::memory_order_acq_rel); }
    /// \return the re-seats asked for so far (the haptic thread compares with those it did).
    [[nodiscard]] std::uint32_t reseatRequests() const noexcept
    {
        return reseatRequests_.load(std::memory_order_acquire);
    }
    /// Asks for a restart of the haptic time (HapticTask::requestClockRestart()).
    void requestClockRestart() noexcept { clockRestarts_.fetch_add(1, std::memory_order_acq_rel); }
    /// \return the clock restarts asked for so far.
    [[nodiscard]] std::uint32_t clockRestarts() const noexcept
    {
        return clockRestarts_.load(std::memory_order_acquire);
    }

private:
    std::atomic<bool> stopRequested_{false};
    std::atomic<bool> enabled_;
    std::atomic<double> stiffness_; ///< N/m.
    std::atomic<std::uint32_t> reseatRequests_{0};
    std::atomic<std::uint32_t> clockRestarts_{0};
};

} // namespace depthtouch::haptic_task
