#pragma once
/// \file
/// \brief percentile(): the nearest-rank percentile the benchmarks and the player's stats quote
/// (offline figures, not for a real-time thread: it copies its input).
/// Thread-safety: reentrant.

#include <vector>

namespace depthtouch::platform {

/// \brief Nearest-rank percentile: the smallest sample with at least a fraction \a p of the
/// samples at or below it (p = 0.5: the median, p = 0.99: p99). Units are those of \a samples.
/// \param[in] samples taken by value (reordered in the copy).
/// \param p fraction in [0, 1]; clamped.
/// \return the percentile, or 0 for no samples.
double percentile(std::vector<double> samples, double p);

} // namespace depthtouch::platform
