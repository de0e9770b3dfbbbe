#pragma once
/// \file
/// \brief `depthtouch bench stability`: closed-loop stability of the haptic renderers against the
/// stiffness k, coupled to a simulated hand at the servo rate (docs/benchmarks.md).
///
/// The loop, on a simulated clock only (no wall-clock time anywhere): at every servo tick n
/// (t = n·T, T = 1/servo rate) the renderer reads the HIP x(n) and commands F(n), which is held
/// (zero-order hold, as a device outputs it) while the hand moves on until the next tick.
///
/// The hand (HandModel): one point mass on the HIP, pulled by the hand's own spring toward the
/// intended position and damped,
///
///     m·ẍ = F − b·ẋ − k_h·(x − x_intent)          (N; x in m, scene-box frame)
///
/// m = 0.1 kg (fingertip and end effector, as the `sim` haptic device, docs/devices.md),
/// k_h = 300 N/m and b = 1 or 3 N·s/m: a fingertip's impedance is of the order of a hundred N/m
/// and a few N·s/m, both rising with the grip force (Hajian & Howe 1997, "Identification of the
/// mechanical impedance at the human finger tip", J. Biomech. Eng. 119(1); Hasser & Cutkosky 2002
/// for a pinch grasp). The intent lies straight down from the start, 1 N / k_h (3.3 mm) under the
/// surface along its normal, so the hand presses with about 1 N; it starts at rest 1 mm above it.
/// The mass is integrated exactly enough (RK4, 16 steps per servo period) that the sampling is the
/// only energy source.
///
/// The bound drawn on the chart is Colgate & Schenkel's (1997; Colgate & Brown 1994): a sampled
/// spring k with virtual damping B on a device with physical damping b is passive when
/// b > k·T/2 + |B|, so with B = 0 k_max = 2·b/T (at 1 kHz and b = 1 N·s/m, 2000 N/m). With the
/// hand's mass the exact bound of a mass-damper with a sampled spring (Gillespie & Cutkosky 1996)
/// is sampledSpringLimit(), 0.2 to 1 % above 2·b/T for these figures.
///
/// The renderers' stiffness is capped at scene::kMaxStiffness (3000 N/m). Above it the bench
/// reaches k through a workspace scale s = k / 3000, the device-to-scene scale an application
/// sets: the renderer sees the HIP at o + s·(x − o) (o the surface point under the start) with its
/// own stiffness 3000 N/m, so the hand feels k = s·3000 N/m; on a plane (the surfaces here) this is
/// the renderer at stiffness k exactly, the force limits (N) included.
///
/// Units: m, s, N, N/m, N·s/m, J. Thread-safety: reentrant (no shared state); allocates.

#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace depthtouch::haptics::bench {

/// \brief The simulated hand's parameters (see the file comment for the model and its source).
struct HandModel {
    double mass = 0.1;          ///< m, kg.
    double damping = 1.0;       ///< b, N·s/m (viscous loss to the ground).
    double stiffness = 300.0;   ///< k_h, N/m (the hand's own spring toward its intent).
    double pressForce = 1.0;    ///< k_h × the intent's depth under the surface, N.
    double startHeight = 0.001; ///< Start height above the surface, m (at rest).
};

/// \brief One state of the hand: the HIP's position and velocity, m and m/s, scene-box frame.
struct HandState {
    glm::dvec3 x{};
    glm::dvec3 v{};
};

/// \brief Moves the hand \a s over \a period seconds (s) under the held force \a force (N), its
/// spring pulling toward \a intent (m; \a hand.stiffness 0: none): RK4 in \a steps equal steps.
void stepHand(const HandModel &hand, const glm::dvec3 &intent, const glm::dvec3 &force,
              double period, int steps, HandState &s) noexcept;

/// \return Colgate & Schenkel's passivity bound 2·b/T, N/m, for hand damping \a damping (N·s/m)
/// at \a servoRate (Hz).
double colgateBound(double damping, double servoRate) noexcept;

/// \return the exact stability bound, N/m, of a mass \a mass (kg) with damping \a damping
/// (N·s/m) pushed by a spring sampled at \a servoRate (Hz) through a zero-order hold: the k at
/// which the pole pair of the sampled loop reaches the unit circle (Gillespie & Cutkosky 1996),
/// k* = b·(1 − e)/((1 − e)/a − T·e) with a = b/m, e = exp(−a·T).
double sampledSpringLimit(double mass, double damping, double servoRate) noexcept;

/// \brief The surface pressed on: a plane z = tan(slope)·x through the box's centre, m.
struct StabilitySurface {
    std::string name;    ///< "flat" | "sloped"
    double slopeDeg = 0; ///< Slope about the y axis, degrees.
};

/// \brief Options of the sweep.
struct StabilityOptions {
    std::vector<double> servoRates{1000, 500}; ///< Hz.
    std::vector<double> dampings{1.0, 3.0};    ///< Hand damping b, N·s/m.
    double kMin = 200.0;                       ///< N/m.
    double kMax = 20000.0;                     ///< N/m.
    int kSteps = 21;                           ///< Log-spaced stiffnesses kMin..kMax.
    double duration = 4.0;                     ///< Simulated seconds per run.
    /// The last seconds judged, s; the window as long that ends 1.5 s before the end (2.0..2.5 s
    /// at the defaults) tells a slow decay from a sustained oscillation.
    double lateWindow = 0.5;
    double tolerance = 10e-6; ///< Settled: penetration peak-to-peak below, m.
    /// Methods swept: "wall", renderer-table names and "finger-unfiltered" (`finger` without its
    /// offset filter, RendererConfig::smoothOffset off: what the filter's lag costs); empty: all
    /// of them, in the table's order.
    std::vector<std::string> methods;
};

/// \brief The outcome of one run.
struct StabilityRow {
    /// A renderer-table name, "finger-unfiltered", or "wall" (the ideal sampled spring).
    std::string method;
    std::string surface;       ///< StabilitySurface::name
    double servoRate = 0;      ///< Hz.
    double handDamping = 0;    ///< b, N·s/m.
    double stiffness = 0;      ///< k felt by the hand, N/m.
    double workspaceScale = 1; ///< s (1 up to 3000 N/m).
    double colgateBound = 0;   ///< 2·b/T, N/m.
    /// Penetration along the surface normal (positive inside), m: its peak-to-peak over the late
    /// window, and its mean there.
    double oscillation = 0;
    double oscillationEarly = 0; ///< The same over the earlier window, m.
    double penetrationMean = 0;
    double forceMean = 0;     ///< Normal force over the late window, mean, N.
    double forceExpected = 0; ///< The static equilibrium's normal force, N.
    double energyEnd = 0;     ///< Passivity observer E at the end, J (> 0: generated).
    double energyPeak = 0;    ///< Its largest value, J (≥ 0).
    double lateEnergy = 0;    ///< E(end) − E(start of the late window), J.
    double settleTime = -1;   ///< From first contact to the last sample off the band, s; −1 not.
    int releases = 0;         ///< Safety trips.
    /// "settled" (late peak-to-peak under the tolerance), "decaying" (above it but under half the
    /// earlier window's: stable, slowly damped), "oscillates" (sustained or growing: unstable) or
    /// "let-through" (still, but holding under half the expected force: a limiter let the hand
    /// in).
    std::string outcome;
    /// \return the loop is stable: settled or decaying (no sustained oscillation, the hand held).
    [[nodiscard]] bool stable() const { return outcome == "settled" || outcome == "decaying"; }
};

/// \brief The stability limit of one (method, surface, servo rate, hand damping) series.
struct StabilityLimit {
    std::string method;
    std::string surface;
    double servoRate = 0;
    double handDamping = 0;
    double colgateBound = 0; ///< N/m.
    /// Largest k below the first unstable one, N/m (0: none): the Z-width's stiffness end.
    double lastStable = 0;
    double firstUnstable = 0; ///< Smallest k that is not stable(), N/m (0: all are).
};

/// \brief One closed-loop run (see the file comment). \a method: StabilityOptions::methods.
/// The renderers run as `play` does (RendererConfig::forMethod(), Reengage::Ramp) on a 160×120
/// 16-bit frame of the plane in the default scene box. Allocates (the depth frame).
StabilityRow runStabilityCase(const std::string &method, const StabilitySurface &surface,
                              double servoRate, double stiffness, const HandModel &hand,
                              const StabilityOptions &options);

/// \brief Every method × surface × servo rate × hand damping × stiffness. \return the rows in
/// that order.
std::vector<StabilityRow> runStabilitySweep(const StabilityOptions &options);

/// \return the limits of the series in \a rows (in their order).
std::vector<StabilityLimit> stabilityLimits(const std::vector<StabilityRow> &rows);

/// \return the CSV header line of writeStabilityOutputs()'s stability.csv (no newline).
const char *stabilityCsvHeader() noexcept;

/// \brief Prints the limits table to stdout.
void printStabilityLimits(const std::vector<StabilityLimit> &limits);

/// \brief Writes \a dir/stability.csv, stability_limits.csv, charts.gp and, with gnuplot,
/// stability.png and stability_energy.png. \param[out] error what failed. \param[out] note a
/// remark (no gnuplot). \return false when a file could not be written.
bool writeStabilityOutputs(const std::vector<StabilityRow> &rows,
                           const std::vector<StabilityLimit> &limits, const std::string &dir,
                           std::string &error, std::string &note);

} // namespace depthtouch::haptics::bench
