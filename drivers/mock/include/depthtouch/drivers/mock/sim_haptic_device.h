#pragma once
/// \file
/// \brief SimHapticDevice: a simulated viewer's hand on a 3-DOF haptic device (backend `sim`), for
/// hosts without a device and for deterministic closed-loop tests of the haptic task.
///
/// Model (device frame, metres, newtons, seconds): a fingertip of mass m with viscous damping b,
/// `m·a = F_intent + F_device − b·v`, where F_device is the last commanded force (zero-order hold,
/// clamped to maxForce) and F_intent comes from an intent script:
/// - `press`: hold the point (x, y) with a lateral grip (a critically damped spring of stiffness
///   `grip`) and push toward −z (into the scene) with a constant force `force`, after `delay`
///   seconds hovering at z = `z`: the paper's Fig. 12 experiment (hold a fixed point with a uniform
///   force while the scene moves).
/// - `stroke`: press as above while the grip point moves along the polyline `path` at `speed`
///   m/s, back and forth.
/// - `explore`: press with a force drawn in [0.2·force, force] while the grip point moves between
///   random points of the workspace, a new one every `period` seconds (xorshift, `seed`).
/// - `idle`: no intent: the fingertip only moves when the force pushes it.
/// The force pushes the fingertip back, so the loop through the haptic task is closed: at rest on a
/// surface of stiffness k the penetration is force / k. The position is clamped to the workspace
/// (a hard stop: the velocity component into the wall is dropped).
///
/// Time: the state is integrated with semi-implicit Euler in fixed 100 µs steps up to the clock's
/// now() on every read() and commandForce() (at most 1 s per call; a longer gap is skipped), so it
/// is deterministic under platform::ManualClock and runs in real time under SteadyClock.
/// The intent time starts at open().
///
/// Options (BackendConfig::options, "key=value" separated by ','): intent=press|stroke|explore|idle
/// (press), force (N, 2), x, y (grip point, m, 0), z (start height, m, 0.03), delay (s, 0), path
/// (stroke polyline "x:y/x:y/...", m; default "-0.03:0/0.03:0"), speed (m/s, 0.05), period (s,
/// 1), seed (1), mass (kg, 0.1), damping (N·s/m, 10), grip (N/m, 200), max_force (N, 8.5),
/// workspace (half edge, m, 0.06), servo_rate (Hz, 1000), buttons (0..32, 2).
///
/// Real-time: read(), commandForce(), state() and isConnected() do not allocate, lock or log (they
/// read the injected clock; a ManualClock takes a mutex: simulation only). Thread-safety: as
/// hal::HapticDevice; the fault injection and observers are thread-safe.

#include <atomic>
#include <cstdint>
#include <memory>

#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/haptic_device.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/seqlock.h"

namespace depthtouch::drivers {

/// \brief The simulated hand's parameters (see the file comment for the options).
struct SimHandSettings {
    enum class Intent : std::uint8_t { Press, Stroke, Explore, Idle };
    static constexpr int kMaxPathPoints = 16;

    Intent intent = Intent::Press;
    double force = 2.0; ///< Press force toward −z, N (≥ 0).
    double x = 0.0;     ///< Grip point, m.
    double y = 0.0;
    double z = 0.03;    ///< Start height, m.
    double delay = 0.0; ///< Hover time before pressing, s (≥ 0).
    double path[kMaxPathPoints][2] = {{-0.03, 0.0}, {0.03, 0.0}}; ///< Stroke polyline, m.
    int pathPoints = 2;                                           ///< 2 .. kMaxPathPoints.
    double speed = 0.05;                                          ///< Stroke speed, m/s (> 0).
    double period = 1.0;               ///< Explore: time per random target, s (> 0).
    std::uint64_t seed = 1;            ///< Explore: random seed.
    double mass = 0.1;                 ///< Fingertip mass, kg (> 0).
    double damping = 10.0;             ///< Viscous damping, N·s/m (≥ 0).
    double grip = 200.0;               ///< Lateral grip stiffness, N/m (≥ 0).
    double maxForce = 8.5;             ///< Device maximum, N (> 0).
    double workspaceHalfExtent = 0.06; ///< m (> 0).
    double servoRateHz = 1000.0;       ///< Hz (> 0).
    int buttonCount = 2;               ///< 0..32.

    /// \return the settings from \a options over the defaults; InvalidArgument for an unknown key,
    /// a malformed value or one out of range (logged with the key).
    static Result<SimHandSettings> parse(hal::OptionList options);
};

class SimHapticDevice final : public hal::HapticDevice {
public:
    /// Backend factory: settings from cfg.options, time from cfg.clock.
    static Result<std::unique_ptr<hal::HapticDevice>> create(const hal::BackendConfig &cfg);

    SimHapticDevice(platform::Clock &clock, const SimHandSettings &settings);
    ~SimHapticDevice() override = default;

    [[nodiscard]] const hal::HapticCapabilities &capabilities() const noexcept override
    {
        return caps_;
    }
    [[nodiscard]] State state() const noexcept override
    {
        return state_.load(std::memory_order_acquire);
    }
    [[nodiscard]] Result<void> open() override;
    void close() noexcept override;
    [[nodiscard]] Result<void> read(hal::HapticState &out) noexcept override;
    [[nodiscard]] Result<void> commandForce(const hal::Vec3 &force) noexcept override;
    [[nodiscard]] bool isConnected() const noexcept override;

    /// \name Fault injection (thread-safe), as MockHapticDevice
    ///@{
    void disconnect() noexcept { present_.store(false, std::memory_order_release); }
    void reconnect() noexcept { present_.store(true, std::memory_order_release); }
    void setStalled(bool stalled) noexcept { stalled_.store(stalled, std::memory_order_release); }
    ///@}

    /// \name Observers (thread-safe)
    ///@{
    /// \return the force output now, N (zero when not connected).
    [[nodiscard]] hal::Vec3 lastForce() const noexcept;
    /// \return the fingertip position as of the last read() or commandForce(), m.
    [[nodiscard]] hal::Vec3 position() const noexcept;
    ///@}

    [[nodiscard]] const SimHandSettings &settings() const noexcept { return settings_; }

private:
    Result<void> checkUsable() noexcept;
    /// Integrates the hand up to the clock's now.
    void integrateToNow() noexcept;
    void step(double h) noexcept;
    /// Grip point (x, y) and press force at intent time \a t (s since open()).
    void intentAt(double t, double &gx, double &gy, double &press) noexcept;
    void setOutput(const hal::Vec3 &f) noexcept;
    void publishPosition() noexcept;
    void resetHand() noexcept;

    platform::Clock &clock_;
    const SimHandSettings settings_;
    hal::HapticCapabilities caps_;

    std::atomic<State> state_{State::Closed};
    std::atomic<bool> present_{true};
    std::atomic<bool> stalled_{false};

    // Physics state: touched by the device's user thread (the haptic thread) only.
    platform::TimePoint openedAt_{};
    platform::TimePoint simTime_{};
    hal::Vec3 pos_;
    hal::Vec3 vel_;
    hal::Vec3 force_; ///< Output force (clamped).
    // Explore: current segment of the random walk.
    std::uint64_t rng_ = 1;
    std::int64_t exploreSegment_ = -1;
    double exploreFrom_[2] = {0.0, 0.0};
    double exploreTo_[2] = {0.0, 0.0};
    double exploreForce_ = 0.0;
    double pathLength_ = 0.0;

    // Observers: sequence locks over atomics.
    platform::SeqLockArray<3> output_;   ///< Output force, N (read by lastForce()).
    platform::SeqLockArray<3> position_; ///< Fingertip position, m (read by position()).
};

} // namespace depthtouch::drivers
