#pragma once
/// \file
/// \brief Per-pixel haptic materials carried with depth video: the material track's coding
/// (docs/materials.md). One RGB24 pixel per depth sample, on the depth frame's grid:
/// - **R**: stiffness as a scale of the renderer's stiffness (`--stiffness`), code / 64
///   (64 = 1.0 = as given; 0..255 → 0..3.98);
/// - **G**: static friction μs, code / 100 (0..2.55);
/// - **B**: dynamic friction μd, code / 100 (0..2.55).
///
/// The track is a third video stream titled `material` (kMaterialTitle), H.264 4:4:4 RGB coded
/// losslessly (libx264rgb, qp 0), with the plane meanings and scales in its tags
/// (kMaterialPlanesTag, kMaterialScalesTag). The scales are fixed by this format, so a container
/// that drops stream tags (MP4, MPEG-TS) loses nothing. A producer's maps from elsewhere (glTF
/// `MPEG_haptic_material` stiffness and friction textures) convert by these scales
/// (docs/materials.md).
///
/// Source: the per-pixel haptic image of Cha, Eid and El Saddik, "Touchable 3D video system"
/// (ACM TOMCCAP 2009), with stiffness, static and dynamic friction; units as in
/// docs/references.md. Thread-safety: value types and pure functions.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace depthtouch::scene {

/// Title (and MP4 handler name) of the material stream.
inline constexpr const char *kMaterialTitle = "material";
/// Stream tag naming the planes, in R, G, B order.
inline constexpr const char *kMaterialPlanesTag = "MATERIAL_PLANES";
inline constexpr const char *kMaterialPlanesValue =
    "stiffness_scale,static_friction,dynamic_friction";
/// Stream tag giving each plane's value per code, in R, G, B order.
inline constexpr const char *kMaterialScalesTag = "MATERIAL_SCALES";
inline constexpr const char *kMaterialScalesValue = "0.015625,0.01,0.01";

/// Stiffness scale per R code (1/64).
inline constexpr double kStiffnessScalePerCode = 1.0 / 64.0;
/// Friction coefficient per G or B code (1/100).
inline constexpr double kFrictionPerCode = 0.01;
/// The R code of stiffness scale 1 (the renderer's stiffness as given).
inline constexpr std::uint8_t kUnitStiffnessCode = 64;

/// \brief One material: what the haptic renderer needs of a surface point.
struct Material {
    double stiffnessScale = 1.0;  ///< Scale of the renderer's stiffness (N/m), 0..3.98.
    double staticFriction = 0.0;  ///< μs, 0..2.55.
    double dynamicFriction = 0.0; ///< μd, 0..2.55.
};

/// \return the material of the codes \a r, \a g, \a b (see the file comment).
constexpr Material decodeMaterial(double r, double g, double b) noexcept
{
    return {r * kStiffnessScalePerCode, g * kFrictionPerCode, b * kFrictionPerCode};
}

/// \brief The RGB codes of \a m, each rounded to the nearest code and clamped to 0..255
/// (non-finite values give 0). \param[out] rgb three bytes: R, G, B.
inline void encodeMaterial(const Material &m, std::uint8_t *rgb) noexcept
{
    auto code = [](double v) {
        return static_cast<std::uint8_t>(std::isfinite(v) ? std::clamp(std::lround(v), 0L, 255L)
                                                          : 0L);
    };
    rgb[0] = code(m.stiffnessScale / kStiffnessScalePerCode);
    rgb[1] = code(m.staticFriction / kFrictionPerCode);
    rgb[2] = code(m.dynamicFriction / kFrictionPerCode);
}

/// \brief A borrowed W×H material image: RGB24 codes, row r at `data + r·strideBytes`, pixel
/// (c, r) at byte 3c of that row. Same grid as the depth frame it belongs to.
struct MaterialView {
    const std::uint8_t *data = nullptr; ///< Null: no material (the renderer's own settings).
    std::size_t strideBytes = 0;        ///< ≥ 3·W.

    [[nodiscard]] bool present() const noexcept { return data != nullptr; }
    /// \return the three codes of pixel (\a c, \a r). \pre present(), inside the frame.
    [[nodiscard]] const std::uint8_t *at(int c, int r) const noexcept
    {
        return data + static_cast<std::size_t>(r) * strideBytes + 3 * static_cast<std::size_t>(c);
    }
};

} // namespace depthtouch::scene
