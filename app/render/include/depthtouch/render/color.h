#pragma once
/// \file
/// \brief Y'CbCr → R'G'B' conversion of decoded video (ITU-R BT.601 and BT.709, limited or full
/// range), as the fragment shader applies it: `rgb = matrix · (yuv − offset)` with yuv the texture
/// values in [0, 1].
///
/// Sources: ITU-R BT.601-7 §2.5 (Kr = 0.299, Kb = 0.114) and BT.709-6 §3 (Kr = 0.2126,
/// Kb = 0.0722); limited range puts Y' in 16..235 and Cb, Cr in 16..240 (8 bit).
/// Thread-safety: pure functions.

#include <cstdint>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace depthtouch::render {

/// \brief The colour matrix of a stream.
enum class YuvMatrix : std::uint8_t { Bt601, Bt709 };

/// \brief How the stream signals its colour (AVFrame colorspace and color_range).
struct ColorSpec {
    YuvMatrix matrix = YuvMatrix::Bt601;
    bool fullRange = false; ///< false: limited ("TV", 16..235), true: full ("PC", 0..255).
};

/// \brief `rgb = matrix · (yuv − offset)`, every value normalised to [0, 1] (8-bit code / 255).
struct YuvToRgb {
    glm::mat3 matrix{1.0f};
    glm::vec3 offset{0.0f};
};

/// \return the conversion for \a spec.
YuvToRgb yuvToRgb(const ColorSpec &spec) noexcept;

} // namespace depthtouch::render
