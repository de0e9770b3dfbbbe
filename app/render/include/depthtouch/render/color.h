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
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "depthtouch/hal/types.h"

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

/// \brief Where a colour frame is converted to R'G'B'.
enum class ColorConversion : std::uint8_t {
    Auto,   ///< Cpu on a software rasterizer (GL_RENDERER llvmpipe, softpipe, swrast), else Shader.
    Shader, ///< Three planes uploaded; the surface's fragment shader converts every fragment.
    Cpu,    ///< YuvConverter once per frame; the surface samples one RGBA8 texture.
};

/// \brief How the surface samples its colour texture.
///
/// The colour frame and each eye's viewport are usually about the same size (a 720×486 frame in a
/// 720×486 side-by-side half), so bilinear filtering changes little on screen; on llvmpipe it costs
/// about a tenth of a stereo frame's CPU time (four texel fetches and the blend per fragment),
/// which Auto saves there.
enum class ColorFilter : std::uint8_t {
    Auto,    ///< Nearest on a software rasterizer (as ColorConversion::Auto), else Linear.
    Linear,  ///< GL_LINEAR: bilinear.
    Nearest, ///< GL_NEAREST: the nearest texel.
};

/// \brief Y'CbCr 4:2:0 (or luma only) → RGBA8 on the CPU, the same conversion the fragment shader
/// does: chroma is sampled bilinearly at each luma sample's centre as a GL_LINEAR, clamp-to-edge
/// lookup of the half-size chroma planes does (for even sizes: weights 3/4 and 1/4 of the two
/// nearest chroma samples per axis), then `rgb = matrix · (yuv − offset)` (yuvToRgb()), rounded and
/// clamped to 0..255; alpha 255. Gray8 takes neutral chroma (128). Fixed point (weights in 1/256,
/// coefficients in 1/4096): within one code of the exact value.
/// Thread-safety: thread-bound (holds scratch buffers; no allocation once grown to a frame size).
class YuvConverter {
public:
    /// \brief Converts \a image (Yuv420p or Gray8, \pre not empty).
    /// \return W·H pixels, rows top first, tightly packed, each the bytes R, G, B, A in memory
    /// order (GL_RGBA/GL_UNSIGNED_BYTE); valid until the next call. Empty for other pixel formats.
    const std::vector<std::uint32_t> &convert(const hal::ImageView &image, const ColorSpec &spec);

private:
    std::vector<std::uint32_t> packed_;
    std::vector<int> col0_;  ///< Per luma column: left chroma sample.
    std::vector<int> col1_;  ///< Per luma column: right chroma sample.
    std::vector<int> colW_;  ///< Per luma column: weight of the right sample, 1/256.
    std::vector<int> uRow_; ///< Chroma row interpolated vertically for the current luma row, 1/256.
    std::vector<int> vRow_;
    std::vector<int>
        uFull_; ///< Chroma at every luma sample of the current row minus the offset, 1/256.
    std::vector<int> vFull_;
};

} // namespace depthtouch::render
