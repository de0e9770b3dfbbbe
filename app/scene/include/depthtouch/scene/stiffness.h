#pragma once
/// \file
/// \brief The one range of the surface stiffness k (N/m), wherever it is set: `play --stiffness`
/// and play.toml, `demo --stiffness`, `touch --stiffness` (haptics::ReplayLimits), the control
/// socket's `stiffness N` and mpv's `set_property stiffness`, the remote's CH+/CH− steps
/// (player::StateMachine), the renderer's configuration and its run-time
/// HapticRenderer::setStiffness(). A material track scales k per pixel on top of it
/// (docs/materials.md).
///
/// 100..3000 N/m: softer than 100 N/m a 1 mm press gives under 0.1 N, below what a fingertip
/// tells from nothing; desktop 3-DOF devices quote their largest stable stiffness at a few N/mm
/// at the 1 kHz servo rate, and 3000 N/m stays below them (docs/devices.md).
///
/// Thread-safety: constants and a pure function.

namespace depthtouch::scene {

inline constexpr double kMinStiffness = 100.0;  ///< N/m.
inline constexpr double kMaxStiffness = 3000.0; ///< N/m.
inline constexpr double kStiffnessStep = 100.0; ///< N/m, one remote step (`stiffness +`).

/// \return whether \a newtonsPerMetre lies in kMinStiffness..kMaxStiffness (false for NaN).
[[nodiscard]] inline bool stiffnessInRange(double newtonsPerMetre) noexcept
{
    return newtonsPerMetre >= kMinStiffness && newtonsPerMetre <= kMaxStiffness;
}

} // namespace depthtouch::scene
