#include "depthtouch/render/color.h"

#include <algorithm>
#include <bit>
#include <cmath>

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
    out.offset =
        glm::vec3(spec.fullRange ? 0.0f : 16.0f / 255.0f, 128.0f / 255.0f, 128.0f / 255.0f);
    return out;
}

namespace {

/// Fixed point: chroma weights in 1/256, colour coefficients in 1/4096.
constexpr int kWeightOne = 256;
constexpr int kCoefShift = 12;

/// GL_LINEAR, clamp-to-edge lookup of a \a chroma-sample axis at the centre of luma sample \a i of
/// \a luma: the two samples and the second one's weight (1/256; exact for even sizes: 64 or 192).
void chromaTap(int i, int luma, int chroma, int &i0, int &i1, int &w) noexcept
{
    const double t = (i + 0.5) / luma * chroma - 0.5;
    const double f = std::floor(t);
    const int k = static_cast<int>(f);
    w = static_cast<int>(std::lround((t - f) * kWeightOne));
    i0 = std::clamp(k, 0, chroma - 1);
    i1 = std::clamp(k + 1, 0, chroma - 1);
}

/// The conversion in fixed point: R = ry·Y' + rv·Cr, G = gy·Y' + gu·Cb + gv·Cr, B = by·Y' + bu·Cb
/// (1/4096), with Y' offset by offY (1/256 code units).
struct Coefficients {
    int ry, rv, gy, gu, gv, by, bu, offY;
};

/// One row: luma bytes and chroma at every luma sample (offset removed, 1/256 units) → RGBA words.
/// Separate, with restrict parameters, so the loop vectorises without alias checks.
void convertRow(const std::uint8_t *__restrict luma, const int *__restrict u,
                const int *__restrict v, std::uint32_t *__restrict out, std::size_t n,
                const Coefficients k) noexcept
{
    constexpr int kShift = kCoefShift + 8;
    constexpr int kHalf = 1 << (kShift - 1);
    // Round to nearest and clamp to 0..255, branch-free.
    const auto toByte = [](int x) {
        return static_cast<std::uint32_t>(std::min(std::max((x + kHalf) >> kShift, 0), 255));
    };
    for (std::size_t x = 0; x < n; ++x) {
        const int l = luma[x] * kWeightOne - k.offY;
        // R, G, B, A bytes in memory order (little-endian word).
        out[x] = toByte(k.ry * l + k.rv * v[x]) |
                 toByte(k.gy * l + k.gu * u[x] + k.gv * v[x]) << 8 |
                 toByte(k.by * l + k.bu * u[x]) << 16 | 0xff000000u;
    }
}

int fixedCoef(float c) noexcept
{
    return static_cast<int>(std::lround(static_cast<double>(c) * (1 << kCoefShift)));
}

} // namespace

static_assert(std::endian::native == std::endian::little,
              "RGBA8 pixels are packed as little-endian words");

const std::vector<std::uint32_t> &YuvConverter::convert(const hal::ImageView &image,
                                                        const ColorSpec &spec)
{
    const int w = image.width;
    const int h = image.height;
    const bool yuv = image.format == hal::PixelFormat::Yuv420p;
    if ((!yuv && image.format != hal::PixelFormat::Gray8) || w <= 0 || h <= 0 || image.empty()) {
        packed_.clear();
        return packed_;
    }
    const int cw = (w + 1) / 2;
    const int ch = (h + 1) / 2;
    const auto wu = static_cast<std::size_t>(w);
    packed_.resize(wu * static_cast<std::size_t>(h));
    col0_.resize(wu);
    col1_.resize(wu);
    colW_.resize(wu);
    uFull_.resize(wu);
    vFull_.resize(wu);
    // Neutral chroma (Gray8): 128 in 1/256 units, both passes.
    uRow_.assign(static_cast<std::size_t>(cw), 128 * kWeightOne);
    vRow_.assign(static_cast<std::size_t>(cw), 128 * kWeightOne);
    for (std::size_t x = 0; x < wu; ++x)
        chromaTap(static_cast<int>(x), w, cw, col0_[x], col1_[x], colW_[x]);
    // rgb = M · (yuv − 255·offset), all terms in 1/256 code units times 1/4096 coefficients.
    const YuvToRgb conv = yuvToRgb(spec);
    const glm::mat3 &m = conv.matrix;
    const Coefficients coef{
        fixedCoef(m[0][0]),
        fixedCoef(m[2][0]),
        fixedCoef(m[0][1]),
        fixedCoef(m[1][1]),
        fixedCoef(m[2][1]),
        fixedCoef(m[0][2]),
        fixedCoef(m[1][2]),
        static_cast<int>(std::lround(static_cast<double>(conv.offset.x) * 255.0 * kWeightOne))};
    const int offU =
        static_cast<int>(std::lround(static_cast<double>(conv.offset.y) * 255.0 * kWeightOne));
    const int offV =
        static_cast<int>(std::lround(static_cast<double>(conv.offset.z) * 255.0 * kWeightOne));
    for (int y = 0; y < h; ++y) {
        if (yuv) {
            int r0 = 0;
            int r1 = 0;
            int fy = 0;
            chromaTap(y, h, ch, r0, r1, fy);
            const std::uint8_t *u0 = image.row(1, r0);
            const std::uint8_t *u1 = image.row(1, r1);
            const std::uint8_t *v0 = image.row(2, r0);
            const std::uint8_t *v1 = image.row(2, r1);
            for (std::size_t k = 0; k < static_cast<std::size_t>(cw); ++k) {
                uRow_[k] = u0[k] * (kWeightOne - fy) + u1[k] * fy;
                vRow_[k] = v0[k] * (kWeightOne - fy) + v1[k] * fy;
            }
        }
        // Horizontal chroma taps for the whole row (back to 1/256 units, rounded), then the
        // conversion streams over the row.
        for (std::size_t x = 0; x < wu; ++x) {
            const auto i0 = static_cast<std::size_t>(col0_[x]);
            const auto i1 = static_cast<std::size_t>(col1_[x]);
            const int fx = colW_[x];
            uFull_[x] =
                ((uRow_[i0] * (kWeightOne - fx) + uRow_[i1] * fx + kWeightOne / 2) >> 8) - offU;
            vFull_[x] =
                ((vRow_[i0] * (kWeightOne - fx) + vRow_[i1] * fx + kWeightOne / 2) >> 8) - offV;
        }
        convertRow(image.row(0, y), uFull_.data(), vFull_.data(),
                   packed_.data() + static_cast<std::size_t>(y) * wu, wu, coef);
    }
    return packed_;
}

} // namespace depthtouch::render
