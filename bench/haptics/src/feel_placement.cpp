/// \file
/// \brief Where the feel bench's stroke families go: feature maps of a scene (motion, flicker,
/// holes, passing occluders: analyseScene()), its silhouettes (findSilhouettes()) and the pixels
/// still strokes are drawn from (detail::placePixels(); the strokes: feel_families.cpp).

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <utility>

#include <glm/geometric.hpp>

#include "feel_families_internal.h"

namespace depthtouch::haptics::bench {

using detail::inside;
using detail::pixelXY;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

/// Reference sample → box z, m (NaN at holes).
float referenceZ(const FeelScene &s, std::size_t frame, std::size_t i) noexcept
{
    const std::uint16_t v = s.reference[frame][i];
    if (s.referenceHoleBelow > 0 && v < s.referenceHoleBelow)
        return kNaN;
    const double far = 2.0 * s.referenceHoleBelow; // DepthFrameView::farCode()
    return static_cast<float>(((v - far) / (65535.0 - far) - 0.5) * s.box.depth);
}

/// Touched sample → box z, m (NaN at holes).
float touchedZ(const FeelScene &s, std::size_t frame, std::size_t i) noexcept
{
    const std::vector<std::uint8_t> &f = s.frames[frame];
    std::uint32_t v = 0;
    if (s.format == SampleFormat::Gray8) {
        v = f[i];
    } else {
        std::uint16_t w;
        std::memcpy(&w, f.data() + 2 * i, 2);
        v = w;
    }
    if (v < s.holeBelow)
        return kNaN;
    const double far = 2.0 * s.holeBelow; // DepthFrameView::farCode()
    return static_cast<float>(((v - far) / (maxSampleValue(s.format) - far) - 0.5) * s.box.depth);
}

/// \return the flicker of the 2 % that flicker most and the median flicker of \a feat (pixels
/// that are never a hole); infinity and 0 when there is none.
std::pair<float, float> flickerLevels(const SceneFeatures &feat)
{
    std::vector<float> flick;
    for (std::size_t i = 0; i < feat.flicker.size(); ++i)
        if (std::isfinite(feat.flicker.samples[i]) && feat.holeFraction.samples[i] == 0.0f)
            flick.push_back(feat.flicker.samples[i]);
    float flickTop = std::numeric_limits<float>::infinity();
    float flickMedian = 0.0f;
    if (!flick.empty()) {
        auto top =
            flick.begin() + static_cast<std::ptrdiff_t>(0.98 * static_cast<double>(flick.size()));
        std::nth_element(flick.begin(), top, flick.end());
        flickTop = *top;
        auto mid = flick.begin() + static_cast<std::ptrdiff_t>(flick.size() / 2);
        std::nth_element(flick.begin(), mid, flick.end());
        flickMedian = *mid;
    }
    return {flickTop, flickMedian};
}

} // namespace

SceneFeatures analyseScene(const FeelScene &s)
{
    SceneFeatures f;
    const int w = s.width;
    const int h = s.height;
    f.motion = depth::Plane<float>(w, h, kNaN);
    f.flicker = depth::Plane<float>(w, h, kNaN);
    f.holeFraction = depth::Plane<float>(w, h, 0.0f);
    f.rise = depth::Plane<float>(w, h, 0.0f);
    f.firstCovered = depth::Plane<std::uint16_t>(w, h, 0);
    f.lastCovered = depth::Plane<std::uint16_t>(w, h, 0);
    const std::size_t n = s.frameCount();
    if (n == 0)
        return f;
    for (std::size_t i = 0; i < f.motion.size(); ++i) {
        double motion = -1.0;
        double sq = 0.0;
        std::size_t sqN = 0;
        std::size_t holes = 0;
        float prev = kNaN;
        float top = -1e9f;
        for (std::size_t k = 0; k < n; ++k) {
            const float r = referenceZ(s, k, i);
            const float t = touchedZ(s, k, i);
            holes += std::isnan(t) ? 1u : 0u;
            if (!std::isnan(r) && !std::isnan(t)) {
                sq += static_cast<double>((t - r) * (t - r));
                ++sqN;
            }
            if (!std::isnan(r) && !std::isnan(prev))
                motion = std::max(motion, static_cast<double>(std::fabs(r - prev)));
            if (!std::isnan(r)) {
                prev = r;
                top = std::max(top, r);
            }
        }
        if (motion >= 0.0)
            f.motion.samples[i] = static_cast<float>(motion);
        if (sqN > 0)
            f.flicker.samples[i] = static_cast<float>(std::sqrt(sq / static_cast<double>(sqN)));
        f.holeFraction.samples[i] = static_cast<float>(holes) / static_cast<float>(n);
        const float a = referenceZ(s, 0, i);
        const float b = referenceZ(s, n - 1, i);
        if (!std::isnan(a) && !std::isnan(b) && std::fabs(a - b) < 2e-3f) {
            const float base = std::max(a, b);
            f.rise.samples[i] = std::max(0.0f, top - base);
            bool seen = false;
            for (std::size_t k = 0; k < n; ++k) {
                const float r = referenceZ(s, k, i);
                if (!std::isnan(r) && r > base + 3e-3f) {
                    if (!seen)
                        f.firstCovered.samples[i] = static_cast<std::uint16_t>(k);
                    f.lastCovered.samples[i] = static_cast<std::uint16_t>(k);
                    seen = true;
                }
            }
        }
    }
    return f;
}

std::vector<SilhouettePoint> findSilhouettes(const FeelScene &s, std::size_t frame, double minStep,
                                             double margin)
{
    std::vector<SilhouettePoint> out;
    if (frame >= s.frameCount())
        return out;
    const auto z = [&](int c, int r) {
        return referenceZ(s, frame,
                          static_cast<std::size_t>(r) * static_cast<std::size_t>(s.width) +
                              static_cast<std::size_t>(c));
    };
    for (int r = 2; r + 2 < s.height; r += 2)
        for (int c = 2; c + 2 < s.width; c += 2) {
            const float l = z(c - 2, r);
            const float rr = z(c + 2, r);
            const float u = z(c, r - 2);
            const float d = z(c, r + 2);
            if (std::isnan(l) || std::isnan(rr) || std::isnan(u) || std::isnan(d))
                continue;
            const glm::dvec2 g{static_cast<double>(rr - l), static_cast<double>(u - d)};
            const double step = glm::length(g);
            if (step < minStep)
                continue;
            const glm::dvec2 at = pixelXY(s, c, r);
            if (!inside(s, at, margin))
                continue;
            out.push_back({c, r, at, g / step, step});
        }
    return out;
}

namespace detail {

PlacePixels placePixels(const FeelScene &scene, const SceneFeatures &feat)
{
    PlacePixels px;
    const double margin = 6 * kMm;
    const std::size_t w = static_cast<std::size_t>(scene.width);
    const auto [flickTop, flickMedian] = flickerLevels(feat);
    const auto motionAt = [&](int c, int r) {
        if (c < 0 || r < 0 || c >= scene.width || r >= scene.height)
            return 0.0f;
        const float v = feat.motion.at(c, r);
        return std::isfinite(v) ? v : 0.0f;
    };
    const auto holeAt = [&](int c, int r) {
        if (c < 0 || r < 0 || c >= scene.width || r >= scene.height)
            return 0.0f;
        return feat.holeFraction.at(c, r);
    };
    for (int r = 0; r < scene.height; r += 2)
        for (int c = 0; c < scene.width; c += 2) {
            const std::size_t i = static_cast<std::size_t>(r) * w + static_cast<std::size_t>(c);
            if (!inside(scene, pixelXY(scene, c, r), margin))
                continue;
            const float mot = motionAt(c, r);
            const float hole = feat.holeFraction.samples[i];
            if (!std::isfinite(feat.motion.samples[i]))
                continue;
            if (feat.rise.samples[i] > 5e-3f && feat.holeFraction.samples[i] < 0.5f)
                px.occluded.add(i);
            if (mot < 1e-3f && hole == 0.0f) {
                // Beside a moving object: something within 12 px moves by more than 5 mm a frame.
                bool beside = false;
                for (int k = 0; k < 8 && !beside; ++k) {
                    const double a = std::numbers::pi * k / 4.0;
                    beside = motionAt(c + static_cast<int>(12 * std::cos(a)),
                                      r + static_cast<int>(12 * std::sin(a))) > 5e-3f;
                }
                if (beside)
                    px.moving.add(i);
                else if (feat.flicker.samples[i] <= flickMedian && mot < 0.5e-3f &&
                         motionAt(c + 10, r) < 1e-3f && motionAt(c - 10, r) < 1e-3f &&
                         motionAt(c, r + 10) < 1e-3f && motionAt(c, r - 10) < 1e-3f)
                    px.still.add(i);
                if (feat.flicker.samples[i] >= flickTop)
                    px.flicker.add(i);
            }
            if (hole <= 0.2f) {
                bool border = false;
                for (int dr = -3; dr <= 3 && !border; ++dr)
                    for (int dc = -3; dc <= 3 && !border; ++dc)
                        border = holeAt(c + dc, r + dr) >= 0.2f;
                if (border)
                    px.holeBorder.add(i);
            }
        }
    return px;
}

} // namespace detail

} // namespace depthtouch::haptics::bench
