#include "depthtouch/haptics/spectrum.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace depthtouch::haptics {

Psd averagedPsd(const double *x, std::size_t n, int segments, double fs, double maxHz)
{
    Psd out;
    if (segments < 1 || fs <= 0.0 || maxHz <= 0.0 || n < 2 * static_cast<std::size_t>(segments))
        return out;
    const std::size_t len = n / static_cast<std::size_t>(segments);
    const double lenD = static_cast<double>(len);
    out.binHz = fs / lenD;
    const auto bins = std::min(len / 2 + 1, static_cast<std::size_t>(maxHz / out.binHz) + 1);
    out.density.assign(bins, 0.0);
    std::vector<double> window(len);
    double windowPower = 0.0;
    for (std::size_t i = 0; i < len; ++i) {
        window[i] = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * static_cast<double>(i) / lenD);
        windowPower += window[i] * window[i];
    }
    std::vector<double> seg(len);
    for (int s = 0; s < segments; ++s) {
        const double *p = x + static_cast<std::size_t>(s) * len;
        double mean = 0.0;
        for (std::size_t i = 0; i < len; ++i)
            mean += p[i];
        mean /= lenD;
        for (std::size_t i = 0; i < len; ++i)
            seg[i] = (p[i] - mean) * window[i];
        for (std::size_t k = 0; k < bins; ++k) {
            // Rotate a phasor instead of calling sin/cos per sample.
            const double w = -2.0 * std::numbers::pi * static_cast<double>(k) / lenD;
            const double cw = std::cos(w);
            const double sw = std::sin(w);
            double re = 0.0;
            double im = 0.0;
            double pr = 1.0;
            double pi = 0.0;
            for (std::size_t i = 0; i < len; ++i) {
                re += seg[i] * pr;
                im += seg[i] * pi;
                const double nr = pr * cw - pi * sw;
                pi = pr * sw + pi * cw;
                pr = nr;
            }
            const double scale = (k == 0 || 2 * k == len) ? 1.0 : 2.0;
            out.density[k] += scale * (re * re + im * im) / (fs * windowPower);
        }
    }
    for (double &d : out.density)
        d /= segments;
    return out;
}

double psdPeakDb(const Psd &psd, double hz, double halfWidthHz) noexcept
{
    if (psd.density.empty() || psd.binHz <= 0.0)
        return std::numeric_limits<double>::quiet_NaN();
    const double lo = std::max(0.0, (hz - halfWidthHz) / psd.binHz);
    const double hi = (hz + halfWidthHz) / psd.binHz;
    double best = 0.0;
    bool any = false;
    for (auto k = static_cast<std::size_t>(std::ceil(lo));
         k < psd.density.size() && static_cast<double>(k) <= hi; ++k) {
        best = std::max(best, psd.density[k]);
        any = true;
    }
    if (!any)
        return std::numeric_limits<double>::quiet_NaN();
    if (best <= 0.0)
        return -std::numeric_limits<double>::infinity();
    return 10.0 * std::log10(best);
}

} // namespace depthtouch::haptics
