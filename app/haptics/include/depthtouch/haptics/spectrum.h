#pragma once
/// \file
/// \brief Power spectral density of a force log, as in the paper's Fig. 12 (section VI): the record
/// is cut into equal segments, each is windowed (Hann), its periodogram is computed, and the
/// periodograms are averaged. Offline analysis for tests and the benchmark: allocates; not for the
/// haptic thread. Thread-safety: reentrant.

#include <cstddef>
#include <vector>

namespace depthtouch::haptics {

/// \brief Averaged one-sided PSD.
struct Psd {
    double binHz = 0.0;          ///< Frequency step, Hz (= fs / segment length).
    std::vector<double> density; ///< PSD at k·binHz, k = 0..; units²/Hz (N²/Hz for forces).
};

/// \brief PSD of \a n samples \a x at rate \a fs (Hz), averaged over \a segments equal segments, up
/// to \a maxHz. The mean of each segment is removed. Direct DFT per bin: O(n·maxHz/binHz). \return
/// an empty density when n < 2·segments or the inputs are not positive.
Psd averagedPsd(const double *x, std::size_t n, int segments, double fs, double maxHz);

/// \return 10·log10 of the largest PSD value within ±\a halfWidthHz of \a hz (dB re 1 unit²/Hz);
/// −infinity when that power is exactly zero (a constant signal); NaN when the range holds no bin.
double psdPeakDb(const Psd &psd, double hz, double halfWidthHz) noexcept;

} // namespace depthtouch::haptics
