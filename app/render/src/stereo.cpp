#include "depthtouch/render/stereo.h"

#include <algorithm>
#include <array>
#include <cstddef>

#include <glm/gtc/matrix_transform.hpp>

#include "depthtouch/platform/enum_names.h"

namespace depthtouch::render {

namespace {
/// The names of StereoMode's enumerators, in declaration order.
constexpr std::array<const char *, 5> kStereoModeNames = {"mono", "sbs", "tab", "anaglyph",
                                                          "interleaved"};
static_assert(static_cast<std::size_t>(StereoMode::RowInterleaved) + 1 == kStereoModeNames.size());
} // namespace

const char *stereoModeName(StereoMode mode) noexcept
{
    return platform::enumName(mode, kStereoModeNames, "unknown");
}

std::optional<StereoMode> parseStereoMode(std::string_view name) noexcept
{
    for (const StereoMode m : {StereoMode::Mono, StereoMode::SideBySide, StereoMode::TopAndBottom,
                               StereoMode::Anaglyph, StereoMode::RowInterleaved})
        if (name == stereoModeName(m))
            return m;
    return std::nullopt;
}

EyeView eyeView(const StereoParams &params, double eyeX, double aspect, Viewport viewport,
                double boxWidth, double boxHeight, double boxDepth)
{
    const double d = params.viewDistance;
    // Window that shows the picture with a margin, widened to the eye image's aspect.
    double hw = 0.5 * boxWidth * params.margin;
    double hh = 0.5 * boxHeight * params.margin;
    if (hw / hh < aspect)
        hw = hh * aspect;
    else
        hh = hw / aspect;
    // The outermost pixel centres fall on the picture's outer samples; pull the window 1/128 pixel
    // inside so the rasteriser's fill rule (which drops centres exactly on right and top edges)
    // keeps them.
    hw *= 1.0 - 1.0 / (128.0 * std::max(1, viewport.width));
    hh *= 1.0 - 1.0 / (128.0 * std::max(1, viewport.height));
    // Shift-sensor parallax (Fehn 2004): each eye sees the picture straight on, shifted in x by
    // -eyeX·(z − zc)/convergence, zc the zero-parallax plane. No point is scaled by its depth, so
    // the mono view is the source picture pixel for pixel.
    const double zc = d - params.convergence;
    const double shear = -eyeX / params.convergence;
    const double zNear = d - 1.5 * boxDepth;
    const double zFar = d + 1.5 * boxDepth;

    EyeView e;
    e.eyeOffset = eyeX;
    e.viewport = viewport;
    e.projection =
        glm::ortho(static_cast<float>(-hw), static_cast<float>(hw), static_cast<float>(-hh),
                   static_cast<float>(hh), static_cast<float>(zNear), static_cast<float>(zFar));
    glm::mat4 shift(1.0f); // x' = x + shear·(z − zc)
    shift[2][0] = static_cast<float>(shear);
    shift[3][0] = static_cast<float>(-shear * zc);
    e.view = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, static_cast<float>(-d))) * shift;
    return e;
}

std::array<EyeView, 2> eyeViews(StereoMode mode, const StereoParams &params, int width, int height,
                                double boxWidth, double boxHeight, double boxDepth, int &count)
{
    const double aspect = static_cast<double>(width) / static_cast<double>(height);
    const double half = 0.5 * params.eyeSeparation;
    const Viewport full{0, 0, width, height};
    const auto eye = [&](double x, Viewport vp) {
        return eyeView(params, x, aspect, vp, boxWidth, boxHeight, boxDepth);
    };
    std::array<EyeView, 2> out{};
    count = 2;
    switch (mode) {
    case StereoMode::Mono:
        out[0] = eye(0.0, full);
        count = 1;
        break;
    case StereoMode::SideBySide: {
        const int leftW = width / 2;
        const double a = params.frameCompatible ? aspect : 0.5 * aspect;
        out[0] =
            eyeView(params, -half, a, Viewport{0, 0, leftW, height}, boxWidth, boxHeight, boxDepth);
        out[1] = eyeView(params, half, a, Viewport{leftW, 0, width - leftW, height}, boxWidth,
                         boxHeight, boxDepth);
        break;
    }
    case StereoMode::TopAndBottom: {
        const int topH = height / 2;
        const double a = params.frameCompatible ? aspect : 2.0 * aspect;
        out[0] = eyeView(params, -half, a, Viewport{0, height - topH, width, topH}, boxWidth,
                         boxHeight, boxDepth);
        out[1] = eyeView(params, half, a, Viewport{0, 0, width, height - topH}, boxWidth, boxHeight,
                         boxDepth);
        break;
    }
    case StereoMode::Anaglyph:
        out[0] = eye(-half, full);
        out[0].colorMask = 0x1;
        out[1] = eye(half, full);
        out[1].colorMask = 0x6;
        break;
    case StereoMode::RowInterleaved:
        // Rows counted from the top: top row is window row height−1.
        out[0] = eye(-half, full);
        out[0].rowParity = (height - 1) & 1;
        out[1] = eye(half, full);
        out[1].rowParity = height & 1;
        break;
    }
    return out;
}

EyeView topView(int width, int height, double boxWidth, double boxHeight, double boxDepth)
{
    // One pixel per sample: pixel centres on the sample columns and rows.
    // The outermost pixel centres fall on the box edges; pull them 1/128 pixel inside so the
    // rasteriser's fill rule (which drops centres exactly on right and bottom edges) keeps them.
    const double px = boxWidth / std::max(1, width - 1);
    const double py = boxHeight / std::max(1, height - 1);
    const double hx = 0.5 * px * width - px / 128.0;
    const double hy = 0.5 * py * height - py / 128.0;
    EyeView e;
    e.viewport = Viewport{0, 0, width, height};
    e.view = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, static_cast<float>(-boxDepth)));
    e.projection =
        glm::ortho(static_cast<float>(-hx), static_cast<float>(hx), static_cast<float>(-hy),
                   static_cast<float>(hy), 0.0f, static_cast<float>(2.0 * boxDepth));
    return e;
}

} // namespace depthtouch::render
