#pragma once
/// \file
/// \brief The surface stiffness k (N/m) under the names the haptic code uses: its one range is
/// the row options::kStiffness (depthtouch/options/option_range.h), read by every place k is set:
/// `play --stiffness` and play.toml, dt_set_option_string(), `demo --stiffness`, `touch
/// --stiffness` (haptics::ReplayLimits), the control socket's `stiffness N`, mpv's `set_property
/// stiffness` and `add stiffness`, the remote's CH+/CH− steps (player::StateMachine), the
/// renderer's configuration and its run-time HapticRenderer::setStiffness(). A material track
/// scales k per pixel on top of it (docs/materials.md).
///
/// Thread-safety: constants and a pure function.

#include "depthtouch/options/option_range.h"

namespace depthtouch::scene {

inline constexpr double kMinStiffness = options::kStiffness.min;   ///< N/m.
inline constexpr double kMaxStiffness = options::kStiffness.max;   ///< N/m.
inline constexpr double kStiffnessStep = options::kStiffness.step; ///< N/m, one `stiffness +`.

/// \return whether \a newtonsPerMetre lies in kMinStiffness..kMaxStiffness (false for NaN).
[[nodiscard]] inline bool stiffnessInRange(double newtonsPerMetre) noexcept
{
    return options::kStiffness.contains(newtonsPerMetre);
}

} // namespace depthtouch::scene
