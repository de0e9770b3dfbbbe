/// \file
/// \brief The feel bench's typing scene (SyntheticScene::Typing, feel_scenes.h): a hand typing on
/// a keyboard on a desk, seen from about 1 m above. Frames and units: feel_scene_internal.h (the
/// world frame is the camera frame before its pan, m).

#include <algorithm>
#include <cmath>

#include "feel_scene_internal.h"

namespace depthtouch::haptics::bench::detail {

namespace {

// The desk: Z = kDeskZ + kDeskB·X + kDeskC·Y (nearer toward the bottom of the view).
constexpr double kDeskZ = 1.06;
constexpr double kDeskB = 0.02;
constexpr double kDeskC = -0.03;

// The keyboard: a plate kPlateHeight over the desk carrying kColumns × kRows keycaps (flat tops
// kCap square on a kPitch grid, kKeyHeight over the plate, a dark legend on each), m.
constexpr double kPlateHeight = 0.012;
constexpr double kKeyHeight = 0.010;
constexpr double kPitch = 0.015;
constexpr double kCap = 0.011;
constexpr int kColumns = 29;
constexpr int kRows = 6;
constexpr double kKeysLeft = -0.5 * kColumns * kPitch; ///< X of the key grid's left side.
constexpr double kKeysTop = -0.075;                    ///< Y of its top (far) side.
constexpr double kPlateMargin = 0.008;                 ///< Plate around the key grid.

// The hand: a right hand over the right part of the keyboard, swaying sideways with its forearm.
constexpr double kHandX = 0.09;     ///< Mean X of the hand's axis, m.
constexpr double kSway = 0.02;      ///< Sideways sway, ± m ...
constexpr double kSwayHz = 0.3;     ///< ... at this rate (3.8 cm/s at most).
constexpr double kKnuckleY = 0.035; ///< m.
constexpr double kKnuckleZ = 1.005; ///< m.
constexpr double kPalmZ = 1.010;    ///< The palm's axis, m.
constexpr double kPalmRadius = 0.032;
constexpr double kArmRadius = 0.030;
constexpr double kFingerRadius = 0.008;
/// Index, middle, ring and little finger: knuckle X from the hand's axis, length (knuckle to the
/// tip's centre), strike rate, phase, lift at the top of a stroke (the tip goes up and down by
/// it) and sideways reach (the strikes alternate between keys ± this from the knuckle's X).
struct Finger {
    double x, length, hz, phase, lift, reach;
};
constexpr std::array<Finger, 4> kFingers = {{
    {-0.030, 0.062, 4.4, 0.0, 0.035, 0.0075},
    {-0.010, 0.068, 3.1, 1.9, 0.025, 0.0075},
    {0.010, 0.064, 5.7, 0.7, 0.030, 0.0075},
    {0.030, 0.052, 3.7, 2.6, 0.020, 0.0075},
}};

/// The height over the desk of a surface parallel to it (along Z), m → its plane's a.
double deskA(const TypingPose &p, double height) noexcept
{
    return kDeskZ + kDeskB * p.panX + kDeskC * p.panY - height;
}

/// Z of the key tops at world (X, Y), m.
double keyTopZ(double x, double y) noexcept
{
    return kDeskZ + kDeskB * x + kDeskC * y - kPlateHeight - kKeyHeight;
}

/// World (X, Y) of the hit at \a z along \a d.
glm::dvec2 worldXY(const TypingPose &p, const glm::dvec3 &d, double z) noexcept
{
    return {d.x * z + p.panX, d.y * z + p.panY};
}

bool onPlate(const glm::dvec2 &w) noexcept
{
    return w.x >= kKeysLeft - kPlateMargin && w.x <= -kKeysLeft + kPlateMargin &&
           w.y >= kKeysTop - kPlateMargin && w.y <= kKeysTop + kRows * kPitch + kPlateMargin;
}

/// \return whether world (X, Y) \a w is on a keycap's top; \a legend: on its dark legend (3 mm
/// square up and left of its centre).
bool onKeycap(const glm::dvec2 &w, bool &legend) noexcept
{
    const double gx = (w.x - kKeysLeft) / kPitch;
    const double gy = (w.y - kKeysTop) / kPitch;
    if (gx < 0.0 || gy < 0.0 || gx >= kColumns || gy >= kRows)
        return false;
    const double fx = (gx - std::floor(gx) - 0.5) * kPitch; // from the key's centre, m
    const double fy = (gy - std::floor(gy) - 0.5) * kPitch;
    if (std::fabs(fx) > 0.5 * kCap || std::fabs(fy) > 0.5 * kCap)
        return false;
    legend = fx > -4e-3 && fx < -1e-3 && fy > -4e-3 && fy < -1e-3;
    return true;
}

/// Z of the capsule of radius \a r around segment \a a–\a b along \a d; +inf when missed.
double capsuleZ(const glm::dvec3 &a, const glm::dvec3 &b, double r, const glm::dvec3 &d) noexcept
{
    const glm::dvec3 mid = 0.5 * (a + b);
    const double len = glm::length(b - a);
    const double bound = 0.5 * len + r;
    const double dm = glm::dot(d, mid);
    if (glm::dot(mid, mid) - dm * dm / glm::dot(d, d) > bound * bound)
        return kInf; // the ray misses the sphere around the capsule
    const glm::dvec3 axis = (b - a) / len;
    double z = cylinderZ(a, axis, r, d);
    if (std::isfinite(z)) {
        const double along = glm::dot(z * d - a, axis);
        if (along < 0.0 || along > len)
            z = kInf;
    }
    return std::min({z, sphereZ(a, r, d), sphereZ(b, r, d)});
}

/// Z of the hand (palm, fingers, forearm) along \a d; +inf when missed.
double handZ(const TypingPose &p, const glm::dvec3 &d) noexcept
{
    double z = std::min(capsuleZ(p.palmA, p.palmB, kPalmRadius, d),
                        capsuleZ(p.armA, p.armB, kArmRadius, d));
    for (std::size_t i = 0; i < kFingers.size(); ++i)
        z = std::min(z, capsuleZ(p.knuckle[i], p.tip[i], kFingerRadius, d));
    return z;
}

} // namespace

TypingPose typingPoseAt(double t, double panX, double panY) noexcept
{
    TypingPose p;
    p.panX = panX;
    p.panY = panY;
    const glm::dvec3 seen{-panX, -panY, 0.0}; // world → camera frame
    const double hx = kHandX + kSway * std::sin(kTwoPi * kSwayHz * t);
    p.palmA = glm::dvec3{hx, kKnuckleY + 0.010, kPalmZ} + seen;
    p.palmB = glm::dvec3{hx, 0.115, kPalmZ} + seen;
    // The forearm comes in from the bottom of the view, its far end out of it.
    p.armA = glm::dvec3{hx, 0.13, 0.995} + seen;
    p.armB = glm::dvec3{hx + 0.06, 0.60, 1.0} + seen;
    for (std::size_t i = 0; i < kFingers.size(); ++i) {
        const Finger &f = kFingers[i];
        const glm::dvec3 k{hx + f.x, kKnuckleY, kKnuckleZ};
        // |sin|: the tip strikes the key (lift 0, a sharp turn) and rises smoothly to `lift`;
        // between strikes it moves sideways to the key on the other side.
        const double a = std::numbers::pi * f.hz * t + f.phase;
        const double tipX = k.x + f.reach * std::cos(a);
        const double rest = keyTopZ(tipX, k.y - 0.06) - kFingerRadius;
        const double tipZ = rest - f.lift * std::fabs(std::sin(a));
        const double dz = tipZ - k.z;
        const double dy = std::sqrt(std::max(0.0, f.length * f.length - dz * dz));
        p.knuckle[i] = k + seen;
        p.tip[i] = glm::dvec3{tipX, k.y - dy, tipZ} + seen;
    }
    return p;
}

double typingDepth(const TypingPose &p, const glm::dvec3 &d, bool *dark) noexcept
{
    double z = planeZ(deskA(p, 0.0), kDeskB, kDeskC, d);
    bool legend = false;
    const double plate = planeZ(deskA(p, kPlateHeight), kDeskB, kDeskC, d);
    if (std::isfinite(plate) && onPlate(worldXY(p, d, plate))) {
        z = plate;
        const double top = planeZ(deskA(p, kPlateHeight + kKeyHeight), kDeskB, kDeskC, d);
        if (std::isfinite(top) && onKeycap(worldXY(p, d, top), legend))
            z = top;
        else
            legend = false;
    }
    const double hand = handZ(p, d);
    if (dark != nullptr)
        *dark = legend && !(hand < z);
    return std::min(z, hand);
}

std::vector<ImageCrossing> typingCrossings(const TypingPose &p, const Camera &cam)
{
    std::vector<ImageCrossing> out;
    // Along the third row of keys, centred on its seventh key (left of the hand): 6 mm in the box
    // either side, over about nine keys and their gaps.
    const double kx = kKeysLeft + 6.5 * kPitch;
    const double ky = kKeysTop + 2.5 * kPitch;
    const glm::dvec3 key{kx - p.panX, ky - p.panY, keyTopZ(kx, ky)};
    out.push_back({"keys", cam.project(key), {1.0, 0.0}, 6.0});
    // Across the forearm, 0.28 m below the centre of the view.
    const double s = (0.28 - p.armA.y) / (p.armB.y - p.armA.y);
    const glm::dvec3 onAxis = p.armA + s * (p.armB - p.armA);
    const glm::dvec2 along = glm::normalize(cam.project(p.armB) - cam.project(p.armA));
    out.push_back({"forearm", cam.project(onAxis), {along.y, -along.x}, 14.0});
    return out;
}

} // namespace depthtouch::haptics::bench::detail
