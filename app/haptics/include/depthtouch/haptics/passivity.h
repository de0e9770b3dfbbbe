#pragma once
/// \file
/// \brief The energy a haptic renderer puts into the hand: the time-domain passivity observer of
/// Hannaford & Ryu (2002) at the device's port, the stability figure of `bench feel`, `touch`'s
/// summary, the demo and `play --stats` (docs/architecture.md §7, "Beyond the paper").
///
/// A passive virtual environment never gives back more energy than it was given. At the port
/// between the device and the hand the energy the device has put into the hand since the start is
///
///     E(n) = Σ_{j=1..n} F(j−1) · (x(j) − x(j−1))        (J = N·m)
///
/// with F the force commanded at update j−1 and held until update j (a zero-order hold, what the
/// device outputs) and x the hand's position (the HIP). This is Hannaford & Ryu's observed energy
/// with the sign turned to the hand's side: their E_obs = −E. A static surface rendered passively
/// keeps E ≤ 0 (energy stored in the spring while pressing comes back at most while leaving); a
/// positive E is energy the renderer generated (a sampled spring's staircase, a force that lags
/// the surface and pushes while the hand leaves, a limit cycle). A moving surface does work of its
/// own on the hand (a turning head pushes the finger away): `bench feel` judges a renderer by its
/// E beyond the ideal penalty's on the same path (FeelFigures::energyExcessMj), which is that
/// work plus the sampling's share.
///
/// Units: m, N, J. Thread-safety: thread-bound; update() is real-time safe (no allocation, no
/// lock, a few flops), so the haptic task runs one on its own thread.

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace depthtouch::haptics {

/// \brief Hannaford & Ryu's passivity observer on one port (see the file comment).
class PassivityObserver {
public:
    /// \brief One update: the hand is at \a position (m) and the force \a force (N) is commanded
    /// from now until the next update. Adds the work the last update's force did over the move
    /// since then. A non-finite position or force is skipped (the history is kept).
    void update(const glm::dvec3 &position, const glm::dvec3 &force) noexcept
    {
        if (!finite(position) || !finite(force))
            return;
        if (started_) {
            energy_ += glm::dot(lastForce_, position - lastPosition_);
            peak_ = std::max(peak_, energy_);
        }
        started_ = true;
        lastPosition_ = position;
        lastForce_ = force;
    }
    /// \brief Forgets the history: energy 0, the next update starts a new path (a reconnect, a
    /// clutch: the hand moved while nothing was commanded).
    void reset() noexcept { *this = PassivityObserver{}; }
    /// \brief The next update starts a new path but the energy so far is kept (the hand moved
    /// with no force on it: the clutch held, the device was lost).
    void breakPath() noexcept { started_ = false; }
    /// \return E(n), J: the net energy the device put into the hand since reset(); > 0 is
    /// generated energy.
    [[nodiscard]] double energy() const noexcept { return energy_; }
    /// \return the largest E(n) so far, J (≥ 0): the most the hand was given back at any time.
    [[nodiscard]] double peak() const noexcept { return peak_; }

private:
    static bool finite(const glm::dvec3 &v) noexcept
    {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    }
    glm::dvec3 lastPosition_{};
    glm::dvec3 lastForce_{};
    double energy_ = 0.0;
    double peak_ = 0.0;
    bool started_ = false;
};

} // namespace depthtouch::haptics
