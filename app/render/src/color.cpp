#include "depthtouch/render/color.h"

namespace depthtouch::render {

YuvToRgb yuvToRgb(const ColorSpec &spec) noexcept
{
    const double kr = spec.matrix == YuvMatrix::Bt709 ? 0.2126 : 0.299;
    const double kb = spec.matrix == YuvMatrix::Bt709 ? 0.0722 : 0.114;
    const double kg = 1.0 - kr - kb;
    // Limited range: Y' 16..235 (219 steps), Cb/Cr 16..240 (224 steps) in 8-bit codes.
    const double ys = spec.fullRange ? 1.0 : 255.0 / 219.0;
    const double cs = spec.fullRange ? 1.0 : 255.0 / 224.0;
    YuvToRgb out;
    // glm is column-major: matrix[column][row]; columns multiply Y', Cb, Cr.
    out.matrix[0] = glm::vec3(static_cast<float>(ys));
    out.matrix[1] = glm::vec3(0.0f, static_cast<float>(-2.0 * (1.0 - kb) * kb / kg * cs),
                              static_cast<float>(2.0 * (1.0 - kb) * cs));
    out.matrix[2] = glm::vec3(static_cast<float>(2.0 * (1.0 - kr) * cs),
                              static_cast<float>(-2.0 * (1.0 - kr) * kr / kg * cs), 0.0f);
    out.offset = glm::vec3(spec.fullRange ? 0.0f : 16.0f / 255.0f, 128.0f / 255.0f, 128.0f / 255.0f);
    return out;
}

} // namespace depthtouch::render
