/// \file
/// \brief The soundtrack of a built-in scene: see soundtrack.h.

#include "depthtouch/synthetic/soundtrack.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace depthtouch::synthetic {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kHeadPeriod = 4.0; ///< s: the head's yaw 35°·sin(2πt / 4 s) (scene_shots.cpp).

/// Adds a burst of \a hz at \a level (of full scale) for \a length s from \a at s, with 1 ms
/// raised-cosine edges, to \a out.
void addBurst(std::vector<double> &out, int rate, double at, double length, double hz, double level)
{
    const auto first = static_cast<std::size_t>(std::llround(at * rate));
    const auto n = static_cast<std::size_t>(std::llround(length * rate));
    const double edge = 0.001 * rate;
    for (std::size_t i = 0; i < n && first + i < out.size(); ++i) {
        const double k = static_cast<double>(i);
        const double fromEnd = static_cast<double>(n - 1 - i);
        const double ramp = std::min({1.0, k / edge, fromEnd / edge});
        const double window = 0.5 - 0.5 * std::cos(std::numbers::pi * ramp);
        out[first + i] += level * window * std::sin(kTwoPi * hz * k / rate);
    }
}

} // namespace

std::vector<double> soundtrackEvents(std::string_view scene, double seconds)
{
    std::vector<double> events{0.0};
    if (scene == "head")
        for (double t = kHeadPeriod / 4.0; t < seconds; t += kHeadPeriod / 2.0)
            events.push_back(t);
    return events;
}

std::vector<std::int16_t> sceneSoundtrack(std::string_view scene, double seconds, int rate)
{
    if (!(seconds > 0.0) || rate <= 0)
        return {};
    std::vector<double> mix(static_cast<std::size_t>(std::llround(seconds * rate)), 0.0);
    if (scene == "head") {
        for (std::size_t i = 0; i < mix.size(); ++i) {
            const double t = static_cast<double>(i) / rate;
            const double speed = std::abs(std::cos(kTwoPi * t / kHeadPeriod)); // |d yaw/dt|, 0..1
            mix[i] += 0.15 * speed * std::sin(kTwoPi * 220.0 * t);
        }
    }
    const std::vector<double> events = soundtrackEvents(scene, seconds);
    addBurst(mix, rate, events[0], 0.005, 1000.0, 0.5);
    for (std::size_t e = 1; e < events.size(); ++e)
        addBurst(mix, rate, events[e], 0.002, 2000.0, 0.3);
    std::vector<std::int16_t> out(mix.size());
    std::transform(mix.begin(), mix.end(), out.begin(), [](double v) {
        return static_cast<std::int16_t>(std::lround(std::clamp(v, -1.0, 1.0) * 32767.0));
    });
    return out;
}

} // namespace depthtouch::synthetic
