#pragma once
/// \file
/// \brief The force log of a fingertip-renderer scenario and the finger it runs, shared by the
/// occluder and hole tests (finger_occluder_test.cpp, finger_hole_test.cpp): 1 kHz updates, the
/// default config (the device maximum 8.5 N), at the servo rate kRate (scenario.h).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <glm/geometric.hpp>

#include "app/haptics/scenario.h"
#include "depthtouch/haptics/finger_renderer.h"
#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics::test {

inline constexpr double kFingerRate = 1000.0;  ///< Updates per second.
inline constexpr double kFingerMaxForce = 8.5; ///< N, the device maximum of the default config.

/// What a run of updates gave, judged from its force log.
struct Log {
    std::vector<HapticOutput> out;
    std::vector<double> t;

    /// The longest run of consecutive changes of |F| that alternate in sign, each over \a
    /// threshold N (a limit cycle), from update \a from on, in updates.
    [[nodiscard]] int longestAlternation(std::size_t from, double threshold = 0.05) const
    {
        int best = 0;
        int run = 0;
        double lastSign = 0.0;
        for (std::size_t i = from + 1; i < out.size(); ++i) {
            const double d = glm::length(out[i].force) - glm::length(out[i - 1].force);
            if (std::fabs(d) <= threshold) {
                run = 0;
                lastSign = 0.0;
                continue;
            }
            const double s = d > 0.0 ? 1.0 : -1.0;
            run = (lastSign != 0.0 && s != lastSign) ? run + 1 : 1;
            lastSign = s;
            best = std::max(best, run);
        }
        return best;
    }
    /// Updates from \a from on whose force magnitude is at the device maximum with no release.
    [[nodiscard]] int updatesAtMax(std::size_t from) const
    {
        int n = 0;
        for (std::size_t i = from; i < out.size(); ++i)
            n += glm::length(out[i].force) >= kFingerMaxForce - 1e-6 && !out[i].released ? 1 : 0;
        return n;
    }
    [[nodiscard]] double largestStep(std::size_t from) const
    {
        double worst = 0.0;
        for (std::size_t i = std::max<std::size_t>(from, 1); i < out.size(); ++i)
            worst = std::max(worst, glm::length(out[i].force - out[i - 1].force));
        return worst;
    }
};

/// \return a new fingertip renderer with the default config and the contact \a contact.
inline FingerRenderer makeFinger(FingerContact contact = FingerContact::GodObject)
{
    RendererConfig c = RendererConfig::forMethod(Method::Finger);
    c.fingerContact = contact;
    return FingerRenderer(c);
}

} // namespace depthtouch::haptics::test
