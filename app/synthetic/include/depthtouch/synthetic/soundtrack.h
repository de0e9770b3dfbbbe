#pragma once
/// \file
/// \brief The soundtrack of a built-in scene: sound whose events are the picture's, so that sync
/// can be heard and measured (docs/making-content.md, "Synthetic scenes").
///
/// Every scene: a click (5 ms of 1 kHz at 0.5 of full scale, raised-cosine edges) at 0 s, the
/// clip's first frame, so every start of a loop clicks. `head`: a 220 Hz tone whose loudness
/// follows the speed at which the head turns (|d yaw / dt| of its yaw 35°·sin(2πt / 4 s)), loudest
/// as it passes the camera (t = 0, 2, 4 s...) and silent where it turns back (t = 1, 3 s...), and a
/// tick (2 ms of 2 kHz) at each turn-around. Pure: no rendering, no I/O.
///
/// Thread-safety: reentrant.

#include <cstdint>
#include <string_view>
#include <vector>

namespace depthtouch::synthetic {

/// \brief Times of the scene's sound events, s: the click at 0, and for `head` the turn-arounds.
/// \param scene "head", "spheres" or "cut" (another name: the click only).
/// \param seconds The clip's length, s.
std::vector<double> soundtrackEvents(std::string_view scene, double seconds);

/// \brief The soundtrack: mono signed 16-bit samples at \a rate Hz, \a seconds long.
/// \return round(seconds · rate) samples; empty for a length or rate that is not positive.
std::vector<std::int16_t> sceneSoundtrack(std::string_view scene, double seconds, int rate);

} // namespace depthtouch::synthetic
