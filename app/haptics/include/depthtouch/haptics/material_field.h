#pragma once
/// \file
/// \brief The haptic material under a point of the touchable surface: the material track's codes
/// (depthtouch/scene/material.h, docs/materials.md) read at the proxy, interpolated like the depth
/// itself — bilinear between the four samples around the point, and in time between frames i and
/// i+1 by the haptic time (paper IV.B, Eq. 1, the weight α of HeightField::setTime()).
///
/// A material boundary (skin next to cloth) is so a ramp over one pixel and one frame period, not
/// a step: crossing it at 10 cm/s over a 0.1 m wide 720-pixel frame changes the stiffness over
/// about 1.4 updates at 1 kHz, which the force stage's slew limit smooths.
///
/// Cost: 4 samples of 3 codes per frame (8 with the next frame), no allocation. Thread-safety:
/// reentrant; the frames must stay alive while set on the field.

#include <algorithm>

#include "depthtouch/haptics/friction.h"
#include "depthtouch/haptics/height_field.h"
#include "depthtouch/scene/material.h"

namespace depthtouch::haptics {

using scene::Material;

namespace detail {

/// The bilinear mean of the codes of \a view around grid point (c + fu, r + fv), channel by
/// channel. \pre 0 ≤ c < W − 1, 0 ≤ r < H − 1, fu, fv in [0, 1].
inline void bilinearCodes(const scene::MaterialView &view, int c, int r, double fu, double fv,
                          double (&codes)[3]) noexcept
{
    const std::uint8_t *p00 = view.at(c, r);
    const std::uint8_t *p10 = p00 + 3;
    const std::uint8_t *p01 = view.at(c, r + 1);
    const std::uint8_t *p11 = p01 + 3;
    for (int k = 0; k < 3; ++k) {
        const double top = p00[k] + fu * (p10[k] - p00[k]);
        const double bottom = p01[k] + fu * (p11[k] - p01[k]);
        codes[k] = top + fv * (bottom - top);
    }
}

} // namespace detail

/// \brief The material at (\a x, \a y) (m, scene-box frame) on \a field's frames.
/// \return \a fallback when the current frame carries no material (or the field has no frames);
/// otherwise the decoded codes, bilinear in space and, when frame i+1 carries material too,
/// interpolated in time by field.alpha(). Points off the grid take the nearest border samples.
inline Material materialAt(const HeightField &field, double x, double y,
                           const Material &fallback) noexcept
{
    const DepthFrameView &cur = field.current();
    if (!field.valid() || !cur.material.present())
        return fallback;
    const double u = std::clamp(field.xToColumn(x), 0.0, static_cast<double>(cur.width - 1));
    const double v = std::clamp(field.yToRow(y), 0.0, static_cast<double>(cur.height - 1));
    const int c = std::min(static_cast<int>(u), cur.width - 2);
    const int r = std::min(static_cast<int>(v), cur.height - 2);
    const double fu = u - c;
    const double fv = v - r;
    double codes[3];
    detail::bilinearCodes(cur.material, c, r, fu, fv, codes);
    const double alpha = field.alpha();
    if (alpha > 0.0 && field.hasNext() && field.next().material.present()) {
        double later[3];
        detail::bilinearCodes(field.next().material, c, r, fu, fv, later);
        for (int k = 0; k < 3; ++k)
            codes[k] += alpha * (later[k] - codes[k]);
    }
    return scene::decodeMaterial(codes[0], codes[1], codes[2]);
}

/// \brief The material step of the renderers: in contact, on frames with a material track, sets
/// \a friction's μs and μd to the material's under the frictionless proxy \a goal (m).
/// \return the stiffness scale there; 1 without a material track or contact (\a friction keeps
/// its coefficients).
inline double applyMaterial(const HeightField &field, const glm::dvec3 &goal, bool contact,
                            FrictionCone &friction) noexcept
{
    if (!contact || !field.current().material.present())
        return 1.0;
    const Material m = materialAt(field, goal.x, goal.y, Material{});
    friction.setCoefficients(m.staticFriction, m.dynamicFriction);
    return m.stiffnessScale;
}

} // namespace depthtouch::haptics
