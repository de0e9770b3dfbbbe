#pragma once
/// \file
/// \brief SimHapticDevice: a simulated viewer's hand on a 3-DOF haptic device (backend `sim`), for
/// hosts without a device and for deterministic closed-loop tests of the haptic task.
///
/// Model (device frame, metres, newtons, seconds): a finger with impedance. The fingertip and the
/// device's end effector are a mass m, tied by a spring-damper (the hand: stiffness k_h, damping
/// c_h, near-critical by default) to the *intended* position p* that the intent script prescribes:
/// `m·a = k·(p* − p) + c·(v* − v) − b·v + F_device`, where F_device is the last commanded force
/// (zero-order hold, clamped to maxForce), b an optional viscous loss to the ground, and k, c are
/// k_h, c_h along z and `grip` (default k_h) with the same damping ratio along x and y.
/// The intended height is `z* = s − depth`: `depth` below the hand's estimate s of where the
/// surface is. The hand learns s by feel, as a real hand does. While it feels the device push
/// (|F_device| > 0.05 N) it regulates its press and lifts over what stands in its way:
/// `ds/dt = (|F_device| − k_h·depth)/(k_h·follow) + climb·max(0, −F_device·u)` (at most 0.2 m/s;
/// u: the unit direction of the stroke). On a still surface s follows the fingertip with time
/// constant `follow` and the press settles at k_h·depth; pushed harder (the surface rises) the
/// hand rises; pushed back against the stroke (the side of an object) it climbs. When it has felt
/// nothing for `reaction` seconds it lowers s at `approach` m/s to look for the surface; `reach`
/// below the last touch without finding one (it went through), it goes back up to the start
/// height `z` at 2·approach and looks again (s starts at `z`; before the first touch it searches
/// down to the workspace floor; at the floor, touched or not, it goes back up as from `reach`).
/// When the support goes (a hole, a pop-through, a released proxy) the fingertip therefore sinks
/// only toward s − depth, at most `depth` below where it was, until the search resumes.
/// Intents (the lateral intended point and the depth):
/// - `press`: hold the point (x, y), after `delay` seconds hovering at (x, y, z) (s frozen): the
///   paper's Fig. 12 experiment (hold a fixed point with a steady press while the scene moves).
/// - `stroke`: press as above while the point moves along the polyline `path` at `speed` m/s,
///   back and forth.
/// - `explore`: press with a depth drawn in [0.2·depth, depth] while the point moves between
///   random points of the workspace, a new one every `period` seconds (xorshift, `seed`).
/// - `idle`: no hand: the fingertip only moves when the force pushes it (and b damps it).
/// The position is clamped to the workspace (a hard stop: the velocity component into the wall is
/// dropped).
///
/// Time: the state is integrated with semi-implicit Euler in fixed 100 µs steps up to the clock's
/// now() on every read() and commandForce() (at most 1000 steps, 0.1 s, per call; a longer gap is
/// skipped, and an explore hand that fell behind draws at most 4 new points), so one call is
/// bounded in time whatever the options, and it is deterministic under platform::ManualClock and
/// runs in real time under SteadyClock. The intent time starts at open().
///
/// Options (BackendConfig::options, "key=value" separated by ','): intent=press|stroke|explore|idle
/// (press), depth (m, default force / hand_stiffness), force (N, 2: the steady press, used only for
/// the default depth), hand_stiffness (N/m, 300), hand_damping (N·s/m, default critical
/// 2·√(hand_stiffness·mass)), follow (s, 0.05), reaction (s, 0.15), approach (m/s, 0.1; 0: a fixed
/// hand that neither feels nor searches: s stays at z, the intended height z − depth), climb
/// (m/s per N, 0.1), reach (m, 0.03), x, y (intended point, m, 0), z (start height and first
/// surface estimate, m, 0.03), delay (s, 0), path (stroke polyline "x:y/x:y/...", m; default
/// "-0.03:0/0.03:0"), speed (m/s, 0.05), period (s, 1, at least 0.01), seed (1), mass (kg, 0.1),
/// damping (viscous loss to the ground, N·s/m, 0), grip (lateral hand stiffness, N/m, default
/// hand_stiffness), max_force (N, 8.5), workspace (half edge, m, 0.06), servo_rate (Hz, 1000),
/// buttons (0..32, 2). Errors: SimHandSettings::parse() and create() give InvalidArgument for an
/// unknown key, a malformed value or one out of range.
///
/// The state, the clamp and non-finite handling are hal::HapticDeviceBase's, the fault injection
/// and the output force SimulatedHapticDeviceBase's; this class is the hand. Real-time: read(),
/// commandForce(), state() and isConnected() do not allocate, lock or log (they read the injected
/// clock; a ManualClock takes a mutex: simulation only). Thread-safety: as hal::HapticDevice; the
/// fault injection and observers are thread-safe.

#include <atomic>
#include <cstdint>
#include <memory>

#include "depthtouch/hal/backends.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/drivers/mock/simulated_haptic_device.h"
#include "depthtouch/drivers/mock/vec3_cell.h"

namespace depthtouch::drivers {

/// \brief The simulated hand's parameters (see the file comment for the options). Units: m, s, kg,
/// N, N/m, N·s/m; device frame.
struct SimHandSettings {
    enum class Intent : std::uint8_t { Press, Stroke, Explore, Idle };
    static constexpr int kMaxPathPoints = 16;

    Intent intent = Intent::Press;
    double force = 2.0; ///< Steady press, N (≥ 0): sets the default depth (force / handStiffness).
    double depth = 0.0; ///< Intended depth below the felt surface, m (≥ 0); set by parse().
    double handStiffness = 300.0; ///< Hand spring along z, N/m (> 0).
    double handDamping = -1.0; ///< Hand damper, N·s/m; < 0: critical, 2·√(handStiffness·mass).
    double follow = 0.05;      ///< Surface estimate's time constant while touching, s (> 0).
    double reaction = 0.15;    ///< Time without feel before searching, s (≥ 0).
    double approach = 0.1; ///< Search speed of the surface estimate, m/s (≥ 0; 0: fixed hand).
    double climb = 0.1;    ///< Lift per newton against the stroke, m/s/N (≥ 0).
    double reach = 0.03;   ///< Search depth below the last touch before retreating, m (> 0).
    double x = 0.0;        ///< Intended point, m.
    double y = 0.0;
    double z = 0.03;    ///< Start height and first surface estimate, m.
    double delay = 0.0; ///< Hover time before pressing, s (≥ 0).
    double path[kMaxPathPoints][2] = {{-0.03, 0.0}, {0.03, 0.0}}; ///< Stroke polyline, m.
    int pathPoints = 2;                                           ///< 2 .. kMaxPathPoints.
    double speed = 0.05;                                          ///< Stroke speed, m/s (> 0).
    double period = 1.0;               ///< Explore: time per random target, s (≥ 0.01).
    std::uint64_t seed = 1;            ///< Explore: random seed.
    double mass = 0.1;                 ///< Fingertip + end effector mass, kg (> 0).
    double damping = 0.0;              ///< Viscous loss to the ground, N·s/m (≥ 0).
    double grip = -1.0;                ///< Lateral hand stiffness, N/m; < 0: handStiffness.
    double maxForce = 8.5;             ///< Device maximum, N (> 0).
    double workspaceHalfExtent = 0.06; ///< m (> 0).
    double servoRateHz = 1000.0;       ///< Hz (> 0).
    int buttonCount = 2;               ///< 0..32.

    /// \return the settings from \a options over the defaults, with depth resolved (force /
    /// handStiffness when not given); InvalidArgument for an unknown key, a malformed value or one
    /// out of range (logged with the key).
    static Result<SimHandSettings> parse(hal::OptionList options);
};

class SimHapticDevice final : public SimulatedHapticDeviceBase {
public:
    /// Backend factory: settings from cfg.options, time from cfg.clock.
    static Result<std::unique_ptr<hal::HapticDevice>> create(const hal::BackendConfig &cfg);

    SimHapticDevice(platform::Clock &clock, const SimHandSettings &settings);
    ~SimHapticDevice() override = default;

    /// \name Observers (thread-safe; lastForce() and the fault injection:
    /// SimulatedHapticDeviceBase)
    ///@{
    /// \return the fingertip position as of the last read() or commandForce(), m.
    [[nodiscard]] hal::Vec3 position() const noexcept;
    ///@}

    [[nodiscard]] const SimHandSettings &settings() const noexcept { return settings_; }

protected:
    [[nodiscard]] Result<State> openDevice() override;
    [[nodiscard]] Result<void> readDevice(hal::HapticState &out) noexcept override;
    [[nodiscard]] Result<void>
    commandForceDevice(const hal::ForceCommand &command) noexcept override;
    /// Zeroes the output force and the force acting on the fingertip.
    void zeroForceDevice() noexcept override;

private:
    /// Integrates the hand up to the clock's now.
    void integrateToNow() noexcept;
    void step(double h) noexcept;
    /// Intended point (x, y) and depth at intent time \a t (s since open()).
    void intentAt(double t, double &gx, double &gy, double &depth) noexcept;
    /// Moves the surface estimate by one step of \a h seconds (press regulation, search or
    /// retreat) for an intended \a depth (m) and stroke direction (\a ux, \a uy) (unit, or 0).
    void updateSurfaceEstimate(double t, double h, double depth, double ux, double uy) noexcept;
    void publishPosition() noexcept;
    void resetHand() noexcept;

    platform::Clock &clock_;
    const SimHandSettings settings_;

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
    double exploreDepth_ = 0.0;
    double pathLength_ = 0.0;
    // The hand: surface estimate, time since it last felt the device push, last intended position.
    double surfaceEstimate_ = 0.0;
    double lastFeltZ_ = 0.0; ///< Fingertip height at the last touch, m (−∞ before the first).
    bool retreating_ = false;
    double unfeltSeconds_ = 0.0;
    hal::Vec3 lastTarget_;
    bool haveTarget_ = false;
    // Resolved gains: hand spring and damper along z, grip and its damper along x and y.
    double kz_ = 0.0;
    double cz_ = 0.0;
    double kxy_ = 0.0;
    double cxy_ = 0.0;

    // Observer: a sequence lock over atomics.
    Vec3Cell position_; ///< Fingertip position, m (read by position()).
};

} // namespace depthtouch::drivers
