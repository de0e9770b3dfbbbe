/// \file
/// \brief The feel bench's scenes: synthetic rendering, the encode-like mapping, frame views (see
/// feel_scenes.h).

#include "depthtouch/haptics/feel_scenes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <utility>

#include <glm/geometric.hpp>

#include "depthtouch/depth/conversion.h"
#include "depthtouch/depth/fill.h"
#include "depthtouch/depth/filters.h"
#include "depthtouch/platform/enum_names.h"

namespace depthtouch::haptics::bench {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kRangeFrames = 5; ///< As `depthtouch encode` (EncodeOptions::rangeFrames).

/// Pinhole camera (Kinect v1 scaled to the width): pixel (u, v) looks along (dx, dy, 1).
struct Camera {
    double f, cx, cy;
    explicit Camera(int w, int h) : f(585.0 * w / 640.0), cx(0.5 * w), cy(0.5 * h) {}
};

/// Z of the plane Z = a + b·X + c·Y along (dx, dy, 1); +inf when missed.
double planeZ(double a, double b, double c, const glm::dvec3 &d) noexcept
{
    const double den = 1.0 - b * d.x - c * d.y;
    return den > 1e-9 ? a / den : kInf;
}

/// Nearest root of A·Z² − 2·B·Z + C = 0 (ray–quadric), +inf when missed.
double nearRoot(double a, double b, double c) noexcept
{
    const double disc = b * b - a * c;
    if (disc < 0.0 || a <= 0.0)
        return kInf;
    const double z = (b - std::sqrt(disc)) / a;
    return z > 0.0 ? z : kInf;
}

double sphereZ(const glm::dvec3 &c, double r, const glm::dvec3 &d) noexcept
{
    return nearRoot(glm::dot(d, d), glm::dot(d, c), glm::dot(c, c) - r * r);
}

/// Infinite cylinder of radius \a r along unit \a axis through \a p.
double cylinderZ(const glm::dvec3 &p, const glm::dvec3 &axis, double r,
                 const glm::dvec3 &d) noexcept
{
    const glm::dvec3 w = d - glm::dot(d, axis) * axis;
    const glm::dvec3 pp = p - glm::dot(p, axis) * axis;
    return nearRoot(glm::dot(w, w), glm::dot(w, pp), glm::dot(pp, pp) - r * r);
}

/// Where the scene's objects are at time t (camera pan folded in), camera frame (x right, y down).
struct Pose {
    double panX, panY;
    glm::dvec3 head;   ///< Sphere centre, m.
    glm::dvec3 bar;    ///< A point on the bar's axis, m.
};

constexpr double kHeadRadius = 0.2;
constexpr double kBarRadius = 0.04;
const glm::dvec3 kBarAxis{std::cos(0.44), std::sin(0.44), 0.0};

Pose poseAt(double t) noexcept
{
    Pose p{};
    p.panX = 0.01 * t - 0.015;                 // camera pans right at 1 cm/s
    p.panY = 0.002 * std::sin(kTwoPi * 0.5 * t); // and bobs ±2 mm
    p.head = {-0.02 - p.panX + 0.01 * std::sin(kTwoPi * 0.3 * t),
              0.006 * std::sin(kTwoPi * 0.5 * t) - p.panY, 1.0};
    p.bar = {-p.panX + 0.008 * std::sin(kTwoPi * 0.25 * t), 0.06 - p.panY, 0.80};
    return p;
}

double sceneDepth(SyntheticScene s, const Pose &p, const glm::dvec3 &d) noexcept
{
    switch (s) {
    case SyntheticScene::Table:
        // Z = 1.0 − 0.6·Y + 0.05·X in the world, shifted by the pan: nearer toward the bottom.
        return planeZ(1.0 + 0.6 * p.panY - 0.05 * p.panX, 0.05, -0.6, d);
    case SyntheticScene::Head:
        return std::min(planeZ(1.10 - 0.03 * p.panX, 0.03, 0.0, d),
                        sphereZ(p.head, kHeadRadius, d));
    case SyntheticScene::Forearm: {
        double z = planeZ(0.93 - 0.05 * p.panY, 0.0, 0.05, d); // table, its back edge at Y = −0.12
        if (d.y * z < -0.12 - p.panY)
            z = 1.2; // back wall
        return std::min(z, cylinderZ(p.bar, kBarAxis, kBarRadius, d));
    }
    }
    return kInf;
}

depth::Plane<float> renderClean(SyntheticScene s, int w, int h, double t)
{
    const Camera cam(w, h);
    const Pose pose = poseAt(t);
    depth::Plane<float> z(w, h, 0.0f);
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u) {
            const glm::dvec3 d{(u + 0.5 - cam.cx) / cam.f, (v + 0.5 - cam.cy) / cam.f, 1.0};
            const double zz = sceneDepth(s, pose, d);
            z.at(u, v) = std::isfinite(zz) ? static_cast<float>(zz) : 0.0f;
        }
    return z;
}

/// Pixel (u, v) → box (x, y), m.
glm::dvec2 pixelToBox(double u, double v, int w, int h, const SceneBox &box) noexcept
{
    const double s = box.width / (w - 1);
    return {(u - 0.5 * (w - 1)) * s, (0.5 * (h - 1) - v) * s};
}

/// Lines across the silhouettes of \a s as they are at mid-clip (they sway by a few mm).
std::vector<SilhouetteCrossing> crossingsOf(SyntheticScene s, int w, int h, double tMid,
                                            const SceneBox &box)
{
    const Camera cam(w, h);
    const Pose p = poseAt(tMid);
    const double mm = (w - 1) / box.width * 1e-3; // px per box mm
    std::vector<SilhouetteCrossing> out;
    const auto add = [&](const char *what, glm::dvec2 edge, glm::dvec2 outward, double reach) {
        const glm::dvec2 a = edge + outward * (reach * mm);
        const glm::dvec2 b = edge - outward * (reach * mm);
        out.push_back({what, pixelToBox(a.x, a.y, w, h, box), pixelToBox(b.x, b.y, w, h, box)});
    };
    if (s == SyntheticScene::Head) {
        const glm::dvec2 c{cam.cx + cam.f * p.head.x / p.head.z,
                           cam.cy + cam.f * p.head.y / p.head.z};
        const double rr =
            cam.f * kHeadRadius / std::sqrt(p.head.z * p.head.z - kHeadRadius * kHeadRadius);
        add("head side", c + glm::dvec2{rr, 0.0}, {1.0, 0.0}, 12.0);
        add("head top", c + glm::dvec2{0.0, -rr}, {0.0, -1.0}, 12.0);
    } else if (s == SyntheticScene::Forearm) {
        const glm::dvec2 c{cam.cx + cam.f * p.bar.x / p.bar.z, cam.cy + cam.f * p.bar.y / p.bar.z};
        const glm::dvec2 n{-kBarAxis.y, kBarAxis.x}; // across the bar, image frame
        add("forearm", c, n, 16.0);
        add("forearm (2)", c + glm::dvec2{kBarAxis.x, kBarAxis.y} * (20.0 * mm), n, 16.0);
    }
    return out;
}

std::vector<std::uint8_t> packFrame(const depth::Plane<std::uint16_t> &q, int bits)
{
    std::vector<std::uint8_t> out(q.size() * (bits == 8 ? 1 : 2));
    for (std::size_t i = 0; i < q.size(); ++i) {
        if (bits == 8)
            out[i] = static_cast<std::uint8_t>(q.samples[i]);
        else
            std::memcpy(out.data() + 2 * i, &q.samples[i], 2);
    }
    return out;
}

std::vector<std::uint16_t> medianReference(const depth::Plane<float> &nearness, double vmax)
{
    const depth::Plane<float> m = depth::medianFilter(nearness, 2);
    std::vector<std::uint16_t> out(m.size());
    for (std::size_t i = 0; i < m.size(); ++i)
        out[i] = static_cast<std::uint16_t>(std::clamp(
            std::lround(static_cast<double>(m.samples[i]) * 65535.0 / vmax), 0L, 65535L));
    return out;
}

/// A scene with no frames yet, the size of \a like.
FeelScene emptyScene(std::string name, const SceneBox &box, double fps,
                     const depth::Plane<std::uint16_t> &like, SampleFormat format)
{
    FeelScene scene;
    scene.name = std::move(name);
    scene.box = box;
    scene.fps = fps;
    scene.width = like.width;
    scene.height = like.height;
    scene.format = format;
    return scene;
}

} // namespace

const char *syntheticSceneName(SyntheticScene scene) noexcept
{
    static constexpr std::array<const char *, 3> kNames = {"synthetic-table", "synthetic-head",
                                                           "synthetic-forearm"};
    return platform::enumName(scene, kNames, "?");
}

DepthFrameView FeelScene::frame(std::size_t i) const noexcept
{
    const std::size_t bps = bytesPerSample(format);
    return DepthFrameView{frames[i].data(), width,
                          height,           static_cast<std::size_t>(width) * bps,
                          format,           static_cast<double>(i) / fps};
}

DepthFrameView FeelScene::referenceFrame(std::size_t i) const noexcept
{
    return DepthFrameView{reinterpret_cast<const std::uint8_t *>(reference[i].data()),
                          width,
                          height,
                          static_cast<std::size_t>(width) * 2,
                          SampleFormat::Gray16,
                          static_cast<double>(i) / fps};
}

Result<DepthFrameView> SceneFrameProvider::frame(std::size_t i) noexcept
{
    if (i >= scene_.frameCount())
        return unexpected(Errc::InvalidArgument, "frame index past the scene's last frame");
    return scene_.frame(i);
}

ReferenceSurface::ReferenceSurface(const FeelScene &scene) : scene_(scene), field_(scene.box) {}

double ReferenceSurface::height(double t, double x, double y)
{
    const std::size_t n = scene_.frameCount();
    if (n == 0)
        return std::nan("");
    const double fi = std::floor(t * scene_.fps + 1e-9);
    const std::size_t i = fi <= 0.0 ? 0 : std::min(n - 1, static_cast<std::size_t>(fi));
    if (i != current_) {
        const DepthFrameView a = scene_.referenceFrame(i);
        const DepthFrameView b = i + 1 < n ? scene_.referenceFrame(i + 1) : DepthFrameView{};
        if (!field_.setFrames(a, i + 1 < n ? &b : nullptr))
            return std::nan("");
        current_ = i;
    }
    field_.setTime(t, true);
    return field_.contains(x, y) ? field_.heightAt(x, y) : std::nan("");
}

Result<FeelScene> sceneFromSensorDepth(std::string name,
                                       const std::vector<depth::Plane<std::uint16_t>> &mm,
                                       double fps, const SceneBox &box, int bits,
                                       const std::vector<depth::Plane<float>> *cleanMetres)
{
    if (mm.empty() || (bits != 8 && bits != 16) || !(fps > 0.0))
        return unexpected(Errc::InvalidArgument,
                          "no frame, or bits not 8 or 16, or fps not positive");
    for (const auto &p : mm)
        if (!p.sameSize(mm.front()) || p.width < 2 || p.height < 2)
            return unexpected(Errc::InvalidArgument, "sensor frames differ in size");
    if (cleanMetres != nullptr && cleanMetres->size() != mm.size())
        return unexpected(Errc::InvalidArgument, "one clean frame per sensor frame needed");
    // `depthtouch encode`'s defaults: robust range of the first frames, 1/Z, push-pull fill,
    // quantise.
    depth::Plane<std::uint16_t> first;
    for (std::size_t i = 0; i < mm.size() && i < static_cast<std::size_t>(kRangeFrames); ++i)
        first.samples.insert(first.samples.end(), mm[i].samples.begin(), mm[i].samples.end());
    first.width = static_cast<int>(first.samples.size());
    first.height = 1;
    depth::ConvertOptions co;
    co.vmax = bits == 8 ? 255.0 : 65535.0;
    auto range = depth::robustRange(first, co.raw);
    if (!range)
        return unexpected(Errc::InvalidArgument, "the first sensor frames have no valid sample");
    co.range = *range;

    FeelScene scene = emptyScene(std::move(name), box, fps, mm.front(),
                                 bits == 8 ? SampleFormat::Gray8 : SampleFormat::Gray16);
    std::vector<int> validCount(mm.front().size(), 0);
    depth::Plane<float> last;
    for (std::size_t f = 0; f < mm.size(); ++f) {
        auto n = depth::metricToNearness(mm[f], co);
        if (!n)
            return unexpected(n.error());
        for (std::size_t i = 0; i < n->valid.size(); ++i)
            validCount[i] += n->valid.samples[i];
        if (n->invalidCount == n->valid.size()) {
            if (last.empty())
                return unexpected(Errc::InvalidArgument,
                                  "the first sensor frame has no valid sample");
        } else {
            if (n->invalidCount > 0)
                DT_TRY(depth::fillInvalid(n->nearness, n->valid));
            last = std::move(n->nearness);
        }
        scene.frames.push_back(packFrame(depth::quantize(last, co.vmax), bits));
        if (cleanMetres == nullptr) {
            scene.reference.push_back(medianReference(last, co.vmax));
            continue;
        }
        const depth::Plane<float> &z = (*cleanMetres)[f];
        std::vector<std::uint16_t> ref(z.size(), 0);
        for (std::size_t i = 0; i < z.size(); ++i)
            if (z.samples[i] > 0.0f)
                ref[i] = static_cast<std::uint16_t>(std::lround(depth::metresToNearness(
                    static_cast<double>(z.samples[i]), *range, co.mapping, 65535.0)));
        scene.reference.push_back(std::move(ref));
    }
    scene.valid = depth::Plane<std::uint8_t>(scene.width, scene.height, 0);
    for (std::size_t i = 0; i < validCount.size(); ++i)
        scene.valid.samples[i] = validCount[i] >= 0.9 * static_cast<double>(mm.size()) ? 1 : 0;
    return scene;
}

Result<FeelScene> sceneFromNearness(std::string name,
                                    const std::vector<depth::Plane<std::uint16_t>> &frames,
                                    SampleFormat format, double fps, const SceneBox &box)
{
    if (frames.empty() || !(fps > 0.0))
        return unexpected(Errc::InvalidArgument, "no frame, or fps not positive");
    FeelScene scene = emptyScene(std::move(name), box, fps, frames.front(), format);
    const double vmax = maxSampleValue(format);
    for (const auto &p : frames) {
        if (!p.sameSize(frames.front()) || p.width < 2 || p.height < 2)
            return unexpected(Errc::InvalidArgument, "frames differ in size");
        scene.frames.push_back(packFrame(p, format == SampleFormat::Gray8 ? 8 : 16));
        depth::Plane<float> n(p.width, p.height);
        for (std::size_t i = 0; i < p.size(); ++i)
            n.samples[i] = static_cast<float>(p.samples[i]);
        scene.reference.push_back(medianReference(n, vmax));
    }
    scene.valid = depth::Plane<std::uint8_t>(scene.width, scene.height, 1);
    return scene;
}

Result<FeelScene> makeSyntheticScene(SyntheticScene which, const SyntheticSceneOptions &o)
{
    const long frames = std::lround(o.seconds * o.fps);
    if (o.width < 16 || o.height < 16 || !(o.fps > 0.0) || frames < 1 ||
        (o.bits != 8 && o.bits != 16))
        return unexpected(
            Errc::InvalidArgument,
            "synthetic scene: size >= 16x16, fps > 0, at least one frame, bits 8 or 16");
    std::vector<depth::Plane<float>> clean;
    std::vector<depth::Plane<std::uint16_t>> sensor;
    for (long i = 0; i < frames; ++i) {
        clean.push_back(renderClean(which, o.width, o.height, static_cast<double>(i) / o.fps));
        if (o.noisy) {
            sensor.push_back(
                applyKinectNoise(clean.back(), o.noise, static_cast<std::uint64_t>(i)));
        } else {
            depth::Plane<std::uint16_t> p(o.width, o.height, 0);
            for (std::size_t k = 0; k < p.size(); ++k)
                p.samples[k] = static_cast<std::uint16_t>(
                    std::lround(static_cast<double>(clean.back().samples[k]) * 1000.0));
            sensor.push_back(std::move(p));
        }
    }
    auto scene =
        sceneFromSensorDepth(syntheticSceneName(which), sensor, o.fps, o.box, o.bits, &clean);
    if (scene)
        scene->crossings = crossingsOf(which, o.width, o.height, 0.5 * scene->duration(), o.box);
    return scene;
}

} // namespace depthtouch::haptics::bench
