#pragma once
/// \file
/// \brief What the feel bench's synthetic scenes (feel_scenes.cpp) and the typing scene
/// (feel_scene_typing.cpp) share, private to dt_haptics_bench: the pinhole camera, the ray
/// helpers and where the objects are at a time. Frames: the camera frame, m (x right, y down, Z
/// away from the camera along the optical axis); a ray through a pixel is (dx, dy, 1), so a hit
/// at depth Z is the point Z·(dx, dy, 1). Thread-safety: none needed (pure functions, values).

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace depthtouch::haptics::bench::detail {

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// Pinhole camera (Kinect v1 scaled to the width): pixel (u, v) looks along (dx, dy, 1).
struct Camera {
    double f, cx, cy;
    explicit Camera(int w, int h) : f(585.0 * w / 640.0), cx(0.5 * w), cy(0.5 * h) {}
    /// \return the image point (u, v), px, of camera-frame point \a p (m, p.z > 0).
    [[nodiscard]] glm::dvec2 project(const glm::dvec3 &p) const noexcept
    {
        return {cx + f * p.x / p.z, cy + f * p.y / p.z};
    }
};

/// Z of the plane Z = a + b·X + c·Y along (dx, dy, 1); +inf when missed.
inline double planeZ(double a, double b, double c, const glm::dvec3 &d) noexcept
{
    const double den = 1.0 - b * d.x - c * d.y;
    return den > 1e-9 ? a / den : kInf;
}

/// Nearest root of A·Z² − 2·B·Z + C = 0 (ray–quadric), +inf when missed.
inline double nearRoot(double a, double b, double c) noexcept
{
    const double disc = b * b - a * c;
    if (disc < 0.0 || a <= 0.0)
        return kInf;
    const double z = (b - std::sqrt(disc)) / a;
    return z > 0.0 ? z : kInf;
}

/// Z of the sphere of centre \a c and radius \a r (m) along \a d; +inf when missed.
inline double sphereZ(const glm::dvec3 &c, double r, const glm::dvec3 &d) noexcept
{
    return nearRoot(glm::dot(d, d), glm::dot(d, c), glm::dot(c, c) - r * r);
}

/// Infinite cylinder of radius \a r along unit \a axis through \a p.
inline double cylinderZ(const glm::dvec3 &p, const glm::dvec3 &axis, double r,
                        const glm::dvec3 &d) noexcept
{
    const glm::dvec3 w = d - glm::dot(d, axis) * axis;
    const glm::dvec3 pp = p - glm::dot(p, axis) * axis;
    return nearRoot(glm::dot(w, w), glm::dot(w, pp), glm::dot(pp, pp) - r * r);
}

/// Where the typing scene's hand is (feel_scene_typing.cpp), camera frame, m.
struct TypingPose {
    double panX = 0.0, panY = 0.0; ///< The camera's pan: a world point X is seen at X − pan, m.
    glm::dvec3 palmA{}, palmB{};   ///< The palm capsule's axis, knuckle end and wrist end.
    glm::dvec3 armA{}, armB{};     ///< The forearm capsule's axis, wrist end and far end.
    std::array<glm::dvec3, 4> knuckle{}; ///< The fingers' capsules' axes, from the knuckle ...
    std::array<glm::dvec3, 4> tip{};     ///< ... to the fingertip's centre.
};

/// Where the scene's objects are at time t (camera pan folded in), camera frame (x right, y down).
struct Pose {
    double panX, panY;
    glm::dvec3 head;     ///< Sphere centre, m.
    glm::dvec3 bar;      ///< A point on the bar's axis, m.
    glm::dvec3 occluder; ///< Centre of the occluder's rounded end, m.
    double cableShift;   ///< How far the ridges scene's cable is pulled down the table, m.
    TypingPose typing;   ///< The typing scene's hand.
};

/// \return the typing scene's hand at time \a t (s) seen by a camera panned by (\a panX, \a panY)
/// m.
TypingPose typingPoseAt(double t, double panX, double panY) noexcept;

/// \return the depth Z (m) of the typing scene (desk, keyboard, hand) along ray \a d; +inf when
/// missed. \param dark when not null, set to whether the surface hit is dark (a keycap's legend).
double typingDepth(const TypingPose &p, const glm::dvec3 &d, bool *dark = nullptr) noexcept;

/// A line across a silhouette in the image: through \a edge (px) along \a outward (unit, toward
/// the start, the lower side), \a reach box mm either side.
struct ImageCrossing {
    const char *what;
    glm::dvec2 edge;
    glm::dvec2 outward;
    double reach;
};

/// \return the typing scene's lines across silhouettes ("keys": along a row of keys beside the
/// hand; "forearm": across the forearm) at pose \a p.
std::vector<ImageCrossing> typingCrossings(const TypingPose &p, const Camera &cam);

} // namespace depthtouch::haptics::bench::detail
