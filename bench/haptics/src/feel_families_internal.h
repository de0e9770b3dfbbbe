#pragma once
/// \file
/// \brief What the feel bench's stroke families (feel_families.cpp) and their placement
/// (feel_placement.cpp) share, private to dt_haptics_bench: scene pixels in box metres, seeded
/// draws (feel_strokes.cpp's too) and the feature pixels still strokes are drawn from.
/// Thread-safety: none (plain values).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "depthtouch/haptics/feel_scenes.h"

namespace depthtouch::haptics::bench::detail {

constexpr double kMm = 1e-3; ///< One millimetre, m.

/// \return the box distance between neighbouring pixels of \a s, m.
inline double spacing(const FeelScene &s) noexcept
{
    return s.box.width / (s.width - 1);
}

/// \return the box x–y of pixel column \a c, row \a r of \a s, m.
inline glm::dvec2 pixelXY(const FeelScene &s, double c, double r) noexcept
{
    const double sp = spacing(s);
    return {(c - 0.5 * (s.width - 1)) * sp, (0.5 * (s.height - 1) - r) * sp};
}

/// \return whether \a p is at least \a margin m inside the box of \a s.
inline bool inside(const FeelScene &s, const glm::dvec2 &p, double margin) noexcept
{
    const double hx = 0.5 * s.box.width - margin;
    const double hy = 0.5 * s.box.width * (s.height - 1) / (s.width - 1) - margin;
    return std::fabs(p.x) <= hx && std::fabs(p.y) <= hy;
}

/// Counter-based uniform draws in [0, 1) (splitmix64).
class Draws {
public:
    explicit Draws(std::uint64_t seed) noexcept : state_(seed) {}
    double next() noexcept
    {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
    }
    std::size_t pick(std::size_t n) noexcept
    {
        return std::min(n - 1, static_cast<std::size_t>(next() * static_cast<double>(n)));
    }

private:
    std::uint64_t state_;
};

/// Candidate pixels of a scene, drawn without replacement in a seeded order.
class Candidates {
public:
    void add(std::size_t i) { items_.push_back(i); }
    [[nodiscard]] bool empty() const noexcept { return items_.empty(); }
    /// \return a candidate, or SIZE_MAX when none is left.
    std::size_t draw(Draws &d)
    {
        if (items_.empty())
            return static_cast<std::size_t>(-1);
        const std::size_t k = d.pick(items_.size());
        const std::size_t v = items_[k];
        items_[k] = items_.back();
        items_.pop_back();
        return v;
    }

private:
    std::vector<std::size_t> items_;
};

/// The pixels still strokes are drawn from (every other pixel, 6 mm inside the box), by feature.
struct PlacePixels {
    Candidates moving;   ///< Still pixels beside a moving region.
    Candidates occluded; ///< Pixels something passed over.
    Candidates flicker;  ///< The 2 % that flicker most.
    Candidates holeBorder;
    Candidates still; ///< Quiet: no motion near, flicker at most the median.
};

/// \return the feature pixels of \a scene, whose features \a feat are (analyseScene()).
PlacePixels placePixels(const FeelScene &scene, const SceneFeatures &feat);

/// \return the position (m) along a ping-pong from \a from to \a to and back after travelling
/// \a s (m); \a from when the two are the same point.
inline glm::dvec2 pingPong(const glm::dvec2 &from, const glm::dvec2 &to, double s) noexcept
{
    const double len = glm::length(to - from);
    if (len <= 0.0)
        return from;
    const double m = std::fmod(s, 2.0 * len);
    const double along = m <= len ? m : 2.0 * len - m;
    return from + (to - from) * (along / len);
}

/// The fingertip a moving stroke rolls over the surface, m.
inline constexpr double kTipRadius = 4e-3;

/// \brief The bottom of a fingertip of radius kTipRadius resting on the reference at time \a t
/// over a path (a ball rolled over the surface along it: it rises before a silhouette instead of
/// jumping up it), from \a taps taps either side. \param at the x–y (m) of the path's point at a
/// signed offset (m) from the point under the finger. \return the height, m; NaN when no surface
/// is under it.
template <class At> double rolledHeight(ReferenceSurface &ref, double t, const At &at, int taps)
{
    double best = std::nan("");
    for (int i = -taps; i <= taps; ++i) {
        const double d = kTipRadius * i / taps;
        const glm::dvec2 p = at(d);
        const double h = ref.height(t, p.x, p.y);
        if (!std::isfinite(h))
            continue;
        const double lifted = h + std::sqrt(kTipRadius * kTipRadius - d * d) - kTipRadius;
        if (!(lifted <= best))
            best = lifted;
    }
    return best;
}

} // namespace depthtouch::haptics::bench::detail
