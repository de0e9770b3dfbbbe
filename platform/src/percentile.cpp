/// \file
/// \brief percentile(): see percentile.h.

#include "depthtouch/platform/percentile.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace depthtouch::platform {

double percentile(std::vector<double> samples, double p)
{
    if (samples.empty())
        return 0.0;
    const double rank = std::ceil(std::clamp(p, 0.0, 1.0) * static_cast<double>(samples.size()));
    const auto k =
        static_cast<std::size_t>(std::clamp(rank, 1.0, static_cast<double>(samples.size()))) - 1;
    std::nth_element(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(k),
                     samples.end());
    return samples[k];
}

} // namespace depthtouch::platform
