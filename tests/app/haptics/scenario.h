#pragma once
/// \file
/// \brief What the stability scenarios share: the servo rate, the default stiffness and scene box,
/// the renderer configurations under test and a renderer wrapped with the statistics the scenarios
/// look at (largest force step, largest force, safety trips).

#include <algorithm>
#include <string>
#include <utility>

#include <glm/geometric.hpp>

#include "depthtouch/haptics/renderer.h"

namespace depthtouch::haptics::test {

inline constexpr double kRate = 1000.0; ///< haptic updates per second (servo rate), Hz
inline constexpr double kK = 800.0;     ///< default stiffness, N/m
inline constexpr SceneBox kBox{};       ///< default scene box (0.1 m wide, 0.04 m deep)

/// \return haptic time of update \a n, s.
inline double timeOf(long n)
{
    return static_cast<double>(n) / kRate;
}

inline RendererConfig modified()
{
    return RendererConfig::forMethod(Method::Modified);
}
inline RendererConfig proxyGraph()
{
    return RendererConfig::forMethod(Method::ProxyGraph);
}

/// \return "gray16" or "gray8", for test names.
inline const char *formatName(SampleFormat f)
{
    return f == SampleFormat::Gray8 ? "gray8" : "gray16";
}

/// One renderer under test with the statistics the scenarios look at.
struct Variant {
    std::string name;
    ProxyGraphRenderer renderer;
    HapticOutput last{};
    glm::dvec3 prevForce{0.0};
    double maxStep = 0.0;  ///< largest |F(n) − F(n−1)|, N
    double maxForce = 0.0; ///< largest |F|, N
    int releases = 0;      ///< safety trips (HapticOutput::released)
    explicit Variant(std::string n, const RendererConfig &c) : name(std::move(n)), renderer(c) {}
    const HapticOutput &step(const glm::dvec3 &hip, double t)
    {
        last = renderer.update(hip, t);
        maxStep = std::max(maxStep, glm::length(last.force - prevForce));
        maxForce = std::max(maxForce, glm::length(last.force));
        releases += last.released ? 1 : 0;
        prevForce = last.force;
        return last;
    }
};

} // namespace depthtouch::haptics::test
