#pragma once
/// \file
/// \brief Coulomb friction on the proxy: the friction cone of Ruspini, Kolarov and Khatib, "The
/// haptic display of complex graphical environments" (SIGGRAPH 1997, §"Friction"), as CHAI3D's
/// finger-proxy (cAlgorithmFingerProxy) renders static and dynamic friction on the god-object.
///
/// The renderer first finds the frictionless proxy, the goal g: the surface point the god-object
/// would take (on the surface, closest to the HIP h). The normal force is the frictionless spring
/// force, Fn = k·|g − h|, along n = (g − h)/|g − h| (out of the surface). The proxy held by
/// friction p (the last update's, moved onto the plane through g normal to n) is offset from g by
/// the tangential vector t = p − g, and the spring force k·(p − h) has the tangential part k·t:
/// - **stick**: while |t| ≤ μ·|g − h| (the tangential force is within μ·Fn: the HIP lies in the
///   cone of half-angle atan μ about n with its apex at p), the proxy stays at p;
/// - **slide**: otherwise the proxy moves toward g until |t| = μd·|g − h|, so that the tangential
///   force is μd·Fn.
/// μ is μs (static) while the proxy sticks and μd (dynamic) while it slides, as in Ruspini's two
/// cones. A sliding proxy that comes within the dynamic cone (the HIP stopped pushing) stays where
/// it is, and is back under the static cone once it has stayed kRestickTime: not at once, because
/// on a triangulated, quantised surface the tangential offset of a steady slide wobbles about
/// μd·|g − h| by rounding, and a static cone after every dip would be stick-slip at the servo rate.
///
/// Depth video carries heights, not the tangential motion of what is filmed, so a held proxy stays
/// where it is in x–y while the surface moves under it (its height follows the tangent plane at g).
/// On a curved surface the held proxy lies on the tangent plane at g, within μ·|g − h| of it: off
/// the surface by less than that distance squared times the curvature. Units: m; μ dimensionless.
/// Thread-safety: thread-bound (the haptic thread); no allocation, noexcept.

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace depthtouch::haptics {

/// Time a sliding proxy must stay held before the static cone applies again, s.
inline constexpr double kRestickTime = 0.02;

/// \brief The friction state of one proxy (see the file comment).
class FrictionCone {
public:
    /// \param staticMu μs ≥ 0, \param dynamicMu μd ≥ 0 (checked by RendererConfig::validate()).
    /// Both 0: enabled() is false and the renderer skips friction (its frictionless proxy, bit for
    /// bit).
    FrictionCone(double staticMu, double dynamicMu) noexcept
        : staticMu_(staticMu), dynamicMu_(dynamicMu), enabled_(staticMu > 0.0 || dynamicMu > 0.0)
    {
    }

    [[nodiscard]] bool enabled() const noexcept { return enabled_; }
    /// \brief Sets μs and μd (≥ 0, finite) for the next apply(): a per-pixel material under the
    /// proxy (material_field.h). The state (held, sliding) is kept.
    void setCoefficients(double staticMu, double dynamicMu) noexcept
    {
        staticMu_ = staticMu;
        dynamicMu_ = dynamicMu;
    }
    /// \return true while the dynamic cone applies: the proxy slid, or has been held for less than
    /// kRestickTime since it slid.
    [[nodiscard]] bool sliding() const noexcept { return sliding_; }

    /// \brief One update in contact.
    /// \param goal the frictionless proxy, m (scene-box frame, on the surface).
    /// \param hip the HIP, m.
    /// \param t haptic time, s (for kRestickTime; a clock that restarted only delays the re-stick).
    /// \return the proxy under friction, m: \a goal on the first contact (or when \a goal and
    /// \a hip meet or are not finite), else the held or sliding proxy, within
    /// max(μs, μd)·|goal − hip| of \a goal, finite.
    glm::dvec3 apply(const glm::dvec3 &goal, const glm::dvec3 &hip, double t) noexcept
    {
        const glm::dvec3 toGoal = goal - hip;
        const double depth = glm::length(toGoal);
        if (!holding_ || !(depth > 0.0) || !std::isfinite(depth)) {
            held_ = goal;
            holding_ = std::isfinite(depth);
            sliding_ = false;
            stopped_ = false;
            return goal;
        }
        const glm::dvec3 n = toGoal / depth;
        // The held proxy on the plane through the goal normal to n (the surface may have moved or
        // turned under it since the last update): the tangential offset t.
        glm::dvec3 offset = held_ - goal;
        offset -= glm::dot(offset, n) * n;
        const double tangential = glm::length(offset);
        const double mu = sliding_ ? dynamicMu_ : staticMu_;
        // Stick while the tangential force is within μ·Fn.
        if (tangential <= mu * depth) {
            if (sliding_ && !stopped_) { // a slide held: it stopped now
                stopped_ = true;
                stopT_ = t;
            } else if (sliding_ && !(t >= stopT_ && t - stopT_ < kRestickTime)) {
                // Held for kRestickTime (or the clock restarted): the static cone again.
                sliding_ = false;
                stopped_ = false;
            }
        } else { // slide toward the goal, keeping the tangential force at μd·Fn
            offset *= dynamicMu_ * depth / tangential;
            sliding_ = true;
            stopped_ = false;
        }
        held_ = goal + offset;
        return held_;
    }

    /// \brief The caller moved the proxy to \a proxy (m, scene-box frame; the fingertip's output
    /// stage handing a ramp's force to its spring, finger_output.h): a held proxy is held there
    /// from the next apply(), in the same phase (static or sliding). Nothing while not holding.
    void moveTo(const glm::dvec3 &proxy) noexcept
    {
        if (holding_)
            held_ = proxy;
    }

    /// \brief The contact ended (free HIP, a safety trip, a reset): the next contact starts at its
    /// own goal.
    void release() noexcept
    {
        holding_ = false;
        sliding_ = false;
        stopped_ = false;
    }

private:
    double staticMu_;
    double dynamicMu_;
    bool enabled_;
    bool holding_ = false;
    /// Under the dynamic cone (sliding, or held for less than kRestickTime).
    bool sliding_ = false;
    bool stopped_ = false; ///< A slide held since stopT_.
    double stopT_ = 0.0;   ///< s.
    glm::dvec3 held_{};
};

} // namespace depthtouch::haptics
