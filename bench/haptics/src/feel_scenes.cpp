/// \file
/// \brief The feel bench's scenes: synthetic rendering, the encode-like mapping, frame views (see
/// feel_scenes.h).

#include "depthtouch/haptics/feel_scenes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

#include <glm/geometric.hpp>

#include "depthtouch/depth/conversion.h"
#include "depthtouch/depth/occupancy.h"
#include "depthtouch/depth/fill.h"
#include "depthtouch/depth/filters.h"
#include "depthtouch/platform/enum_names.h"
#include "feel_scene_internal.h"

namespace depthtouch::haptics::bench {

namespace {

using detail::Camera;
using detail::cylinderZ;
using detail::kInf;
using detail::kTwoPi;
using detail::planeZ;
using detail::Pose;
using detail::sphereZ;

constexpr int kRangeFrames = 5; ///< As `depthtouch encode` (EncodeOptions::rangeFrames).

constexpr double kHeadRadius = 0.2;
constexpr double kBarRadius = 0.04;
const glm::dvec3 kBarAxis{std::cos(0.44), std::sin(0.44), 0.0};

constexpr double kOccluderRadius = 0.045;

// The ridges scene: a board standing on its long edge and a cable lying along X on the table's
// plane Z = 1.0 − 0.6·Y + 0.05·X (as SyntheticScene::Table's, panned the same way), m. The board's
// foot is at world Y = kBoardY; the cable touches the table at kCableY, pulled down the table's
// slope by Pose::cableShift.
constexpr double kBoardThickness = 0.010;
constexpr double kBoardHeight = 0.050;
constexpr double kBoardY = 0.0;
constexpr double kCableRadius = 0.006;
constexpr double kCableY = 0.09;
const glm::dvec3 kRidgeAxis = glm::normalize(glm::dvec3{1.0, 0.0, 0.05});
/// The table's unit normal toward the camera.
const glm::dvec3 kTableUp = glm::normalize(glm::dvec3{0.05, -0.6, -1.0});
/// Down the table's slope, across the ridges (unit).
const glm::dvec3 kDownSlope = glm::normalize(glm::cross(kRidgeAxis, kTableUp));

/// The point of the table at world Y \a y under the optical axis's column, camera frame, m.
glm::dvec3 onTable(const Pose &p, double y) noexcept
{
    return {p.panX, y + p.panY, 1.0 - 0.6 * y};
}

/// Z of the board along \a d (a slab: kBoardThickness across kDownSlope, kBoardHeight along
/// kTableUp from its foot \a foot, endless along kRidgeAxis); +inf when missed.
double boardZ(const glm::dvec3 &foot, const glm::dvec3 &d) noexcept
{
    double in = 0.0;
    double out = kInf;
    const auto between = [&](const glm::dvec3 &n, double lo, double hi) {
        const double dn = glm::dot(d, n);
        const double c = glm::dot(foot, n);
        if (std::fabs(dn) < 1e-12) {
            if (c + lo > 0.0 || c + hi < 0.0) // the ray's n-coordinate is 0 throughout
                out = -kInf;
            return;
        }
        const double a = (c + lo) / dn;
        const double b = (c + hi) / dn;
        in = std::max(in, std::min(a, b));
        out = std::min(out, std::max(a, b));
    };
    between(kDownSlope, -0.5 * kBoardThickness, 0.5 * kBoardThickness);
    between(kTableUp, 0.0, kBoardHeight);
    return in <= out && in > 0.0 ? in : kInf;
}

/// Z of the table of SyntheticScene::Table (and Ridges) along \a d: Z = 1.0 − 0.6·Y + 0.05·X in
/// the world, shifted by the pan (nearer toward the bottom of the view), m.
double tableZ(const Pose &p, const glm::dvec3 &d) noexcept
{
    return planeZ(1.0 + 0.6 * p.panY - 0.05 * p.panX, 0.05, -0.6, d);
}

Pose poseAt(double t, double clipSeconds) noexcept
{
    Pose p{};
    p.panX = 0.01 * t - 0.015;                   // camera pans right at 1 cm/s
    p.panY = 0.002 * std::sin(kTwoPi * 0.5 * t); // and bobs ±2 mm
    p.head = {-0.02 - p.panX + 0.01 * std::sin(kTwoPi * 0.3 * t),
              0.006 * std::sin(kTwoPi * 0.5 * t) - p.panY, 1.0};
    p.bar = {-p.panX + 0.008 * std::sin(kTwoPi * 0.25 * t), 0.06 - p.panY, 0.80};
    // Sweeps from x = -0.3 m to +0.3 m over the clip (0.2 m/s in a 3 s clip), its end 2 cm above
    // the centre of the view.
    const double u = clipSeconds > 0.0 ? t / clipSeconds : 0.5;
    p.occluder = {-0.30 + 0.60 * u - p.panX, -0.02 - p.panY, 0.85};
    p.typing = detail::typingPoseAt(t, p.panX, p.panY);
    p.cableShift = 0.01 * std::sin(kTwoPi * 0.25 * t);
    return p;
}

double sceneDepth(SyntheticScene s, const Pose &p, const glm::dvec3 &d) noexcept
{
    switch (s) {
    case SyntheticScene::Table:
        return tableZ(p, d);
    case SyntheticScene::Head:
        return std::min(planeZ(1.10 - 0.03 * p.panX, 0.03, 0.0, d),
                        sphereZ(p.head, kHeadRadius, d));
    case SyntheticScene::Forearm: {
        double z = planeZ(0.93 - 0.05 * p.panY, 0.0, 0.05, d); // table, its back edge at Y = −0.12
        if (d.y * z < -0.12 - p.panY)
            z = 1.2; // back wall
        return std::min(z, cylinderZ(p.bar, kBarAxis, kBarRadius, d));
    }
    case SyntheticScene::Occluder: {
        const double back = planeZ(1.15 - 0.04 * p.panX, 0.04, 0.0, d);
        // A vertical capsule: the cylinder below its end (camera y down), a sphere at the end.
        double z = cylinderZ(p.occluder, {0.0, 1.0, 0.0}, kOccluderRadius, d);
        if (std::isfinite(z) && d.y * z < p.occluder.y)
            z = kInf;
        return std::min({back, z, sphereZ(p.occluder, kOccluderRadius, d)});
    }
    case SyntheticScene::Typing:
        return detail::typingDepth(p.typing, d);
    case SyntheticScene::Ridges:
        return std::min(
            {tableZ(p, d), boardZ(onTable(p, kBoardY), d),
             cylinderZ(onTable(p, kCableY) + kCableRadius * kTableUp + p.cableShift * kDownSlope,
                       kRidgeAxis, kCableRadius, d)});
    }
    return kInf;
}

/// True where the occluder scene's backdrop carries dark print (blocks of 15 × 20 mm in rows).
bool darkPrint(const Pose &p, const glm::dvec3 &d, double z) noexcept
{
    const double x = d.x * z + p.panX;
    const double y = d.y * z + p.panY;
    const double fx = x / 0.03 - std::floor(x / 0.03);
    const double fy = y / 0.05 - std::floor(y / 0.05);
    return std::fabs(y) < 0.25 && fx < 0.5 && fy < 0.4;
}

/// \param dark when not null, set to the W×H dark-surface mask (the occluder scene's print).
depth::Plane<float> renderClean(SyntheticScene s, int w, int h, double t, double clipSeconds,
                                depth::Plane<std::uint8_t> *dark = nullptr)
{
    const Camera cam(w, h);
    const Pose pose = poseAt(t, clipSeconds);
    depth::Plane<float> z(w, h, 0.0f);
    if (dark != nullptr)
        *dark = depth::Plane<std::uint8_t>(w, h, 0);
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u) {
            const glm::dvec3 d{(u + 0.5 - cam.cx) / cam.f, (v + 0.5 - cam.cy) / cam.f, 1.0};
            bool isDark = false;
            const double zz = s == SyntheticScene::Typing
                                  ? detail::typingDepth(pose.typing, d, &isDark)
                                  : sceneDepth(s, pose, d);
            z.at(u, v) = std::isfinite(zz) ? static_cast<float>(zz) : 0.0f;
            if (dark != nullptr && s == SyntheticScene::Occluder && std::isfinite(zz) && zz > 1.0)
                isDark = darkPrint(pose, d, zz);
            if (dark != nullptr && isDark)
                dark->at(u, v) = 1;
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
    const Pose p = poseAt(tMid, 2.0 * tMid);
    const double mm = (w - 1) / box.width * 1e-3; // px per box mm
    std::vector<SilhouetteCrossing> out;
    const auto add = [&](const char *what, glm::dvec2 edge, glm::dvec2 outward, double reach) {
        const glm::dvec2 a = edge + outward * (reach * mm);
        const glm::dvec2 b = edge - outward * (reach * mm);
        out.push_back({what, pixelToBox(a.x, a.y, w, h, box), pixelToBox(b.x, b.y, w, h, box)});
    };
    if (s == SyntheticScene::Head) {
        const glm::dvec2 c = cam.project(p.head);
        const double rr =
            cam.f * kHeadRadius / std::sqrt(p.head.z * p.head.z - kHeadRadius * kHeadRadius);
        add("head side", c + glm::dvec2{rr, 0.0}, {1.0, 0.0}, 12.0);
        add("head top", c + glm::dvec2{0.0, -rr}, {0.0, -1.0}, 12.0);
    } else if (s == SyntheticScene::Forearm) {
        const glm::dvec2 c = cam.project(p.bar);
        const glm::dvec2 n{-kBarAxis.y, kBarAxis.x}; // across the bar, image frame
        add("forearm", c, n, 16.0);
        add("forearm (2)", c + glm::dvec2{kBarAxis.x, kBarAxis.y} * (20.0 * mm), n, 16.0);
    } else if (s == SyntheticScene::Typing) {
        for (const detail::ImageCrossing &c : detail::typingCrossings(p.typing, cam))
            add(c.what, c.edge, c.outward, c.reach);
    } else if (s == SyntheticScene::Ridges) {
        // Across the board's top under the optical axis's column, the top's middle at the middle.
        add("ridge", cam.project(onTable(p, kBoardY) + kBoardHeight * kTableUp), {0.0, 1.0}, 8.0);
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

/// Median of the measured samples in the 5×5 window of each measured sample; NaN at holes.
depth::Plane<float> maskedMedian(const depth::Plane<float> &n,
                                 const depth::Plane<std::uint8_t> &valid)
{
    depth::Plane<float> out(n.width, n.height, std::numeric_limits<float>::quiet_NaN());
    std::array<float, 25> window{};
    for (int y = 0; y < n.height; ++y)
        for (int x = 0; x < n.width; ++x) {
            if (valid.at(x, y) == 0)
                continue;
            std::size_t k = 0;
            for (int dy = -2; dy <= 2; ++dy) {
                const int yy = y + dy;
                if (yy < 0 || yy >= n.height)
                    continue;
                for (int dx = -2; dx <= 2; ++dx) {
                    const int xx = x + dx;
                    if (xx >= 0 && xx < n.width && valid.at(xx, yy) != 0)
                        window[k++] = n.at(xx, yy);
                }
            }
            auto *mid = window.begin() + static_cast<std::ptrdiff_t>(k / 2);
            std::nth_element(window.begin(), mid, window.begin() + static_cast<std::ptrdiff_t>(k));
            out.at(x, y) = *mid;
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

/// \return an error when \a mm, \a fps, \a bits and \a cleanMetres make no scene
/// (sceneFromSensorDepth()).
Result<void> checkSensorFrames(const std::vector<depth::Plane<std::uint16_t>> &mm, double fps,
                               int bits, const std::vector<depth::Plane<float>> *cleanMetres)
{
    if (mm.empty() || (bits != 8 && bits != 16) || !(fps > 0.0))
        return unexpected(Errc::InvalidArgument,
                          "no frame, or bits not 8 or 16, or fps not positive");
    for (const auto &p : mm)
        if (!p.sameSize(mm.front()) || p.width < 2 || p.height < 2)
            return unexpected(Errc::InvalidArgument, "sensor frames differ in size");
    if (cleanMetres != nullptr && cleanMetres->size() != mm.size())
        return unexpected(Errc::InvalidArgument, "one clean frame per sensor frame needed");
    return {};
}

/// \return the first kRangeFrames frames of \a mm in one row (the samples robustRange() reads).
depth::Plane<std::uint16_t> firstFrames(const std::vector<depth::Plane<std::uint16_t>> &mm)
{
    depth::Plane<std::uint16_t> first;
    for (std::size_t i = 0; i < mm.size() && i < static_cast<std::size_t>(kRangeFrames); ++i)
        first.samples.insert(first.samples.end(), mm[i].samples.begin(), mm[i].samples.end());
    first.width = static_cast<int>(first.samples.size());
    first.height = 1;
    return first;
}

} // namespace

const char *syntheticSceneName(SyntheticScene scene) noexcept
{
    static constexpr std::array<const char *, 6> kNames = {
        "synthetic-table",    "synthetic-head",   "synthetic-forearm",
        "synthetic-occluder", "synthetic-typing", "synthetic-ridges"};
    return platform::enumName(scene, kNames, "?");
}

const char *sensorModelName(SensorModel model) noexcept
{
    static constexpr std::array<const char *, 3> kNames = {"sl", "tof", "stereo"};
    return platform::enumName(model, kNames, "?");
}

DepthFrameView FeelScene::frame(std::size_t i) const noexcept
{
    const std::size_t bps = bytesPerSample(format);
    DepthFrameView v{frames[i].data(), width,
                     height,           static_cast<std::size_t>(width) * bps,
                     format,           static_cast<double>(i) / fps};
    v.holeBelow = holeBelow;
    return v;
}

DepthFrameView FeelScene::referenceFrame(std::size_t i) const noexcept
{
    DepthFrameView v{reinterpret_cast<const std::uint8_t *>(reference[i].data()),
                     width,
                     height,
                     static_cast<std::size_t>(width) * 2,
                     SampleFormat::Gray16,
                     static_cast<double>(i) / fps};
    v.holeBelow = referenceHoleBelow;
    return v;
}

Result<DepthFrameView> SceneFrameProvider::frame(std::size_t i) noexcept
{
    if (i >= scene_.frameCount())
        return unexpected(Errc::InvalidArgument, "frame index past the scene's last frame");
    return scene_.frame(i);
}

ReferenceSurface::ReferenceSurface(const FeelScene &scene) : scene_(scene), field_(scene.box) {}

const HeightField *ReferenceSurface::at(double t)
{
    const std::size_t n = scene_.frameCount();
    if (n == 0)
        return nullptr;
    const double fi = std::floor(t * scene_.fps + 1e-9);
    const std::size_t i = fi <= 0.0 ? 0 : std::min(n - 1, static_cast<std::size_t>(fi));
    if (i != current_) {
        const DepthFrameView a = scene_.referenceFrame(i);
        const DepthFrameView b = i + 1 < n ? scene_.referenceFrame(i + 1) : DepthFrameView{};
        if (!field_.setFrames(a, i + 1 < n ? &b : nullptr))
            return nullptr;
        current_ = i;
    }
    field_.setTime(t, true);
    return &field_;
}

double ReferenceSurface::height(double t, double x, double y)
{
    const HeightField *f = at(t);
    if (f == nullptr || !f->contains(x, y))
        return std::nan("");
    if (scene_.referenceHoleBelow > 0) {
        const DepthFrameView &cur = f->current();
        const int c = std::clamp(static_cast<int>(f->xToColumn(x)), 0, cur.width - 2);
        const int r = std::clamp(static_cast<int>(f->yToRow(y)), 0, cur.height - 2);
        if (!cur.measured(c, r) || !cur.measured(c + 1, r) || !cur.measured(c, r + 1) ||
            !cur.measured(c + 1, r + 1))
            return std::nan("");
    }
    return f->heightAt(x, y);
}

Result<FeelScene> sceneFromSensorDepth(std::string name,
                                       const std::vector<depth::Plane<std::uint16_t>> &mm,
                                       double fps, const SceneBox &box, int bits,
                                       const std::vector<depth::Plane<float>> *cleanMetres,
                                       bool keepHoles)
{
    DT_TRY(checkSensorFrames(mm, fps, bits, cleanMetres));
    // `depthtouch encode`'s defaults: robust range of the first frames, 1/Z, push-pull fill,
    // quantise.
    const depth::Plane<std::uint16_t> first = firstFrames(mm);
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
    const depth::Occupancy occ = depth::occupancyFor(bits, false);
    // Measured nearness (levels of 0..vmax) → the reference's Gray16 code, lifted as the frames.
    const auto lift16 = [&](double n) {
        return static_cast<std::uint16_t>(std::clamp(
            std::lround(depth::occupiedLevel(n, co.vmax, occ) * 65535.0 / co.vmax), 1L, 65535L));
    };
    if (keepHoles) {
        scene.holeBelow = occ.threshold;
        // The reference's Gray16 codes are the frames' scaled to 16 bits, its far plane's code
        // (DepthFrameView::farCode()) too.
        scene.referenceHoleBelow =
            static_cast<std::uint32_t>(std::lround(occ.threshold * 65535.0 / co.vmax));
    }
    // A frame repeated (a still capture played for a while, a short clip looped) has the
    // reference of its first showing: the 5×5 median is most of the cost of a real clip.
    const auto sameAs = [&](std::size_t f) -> std::size_t {
        for (std::size_t g = 0; g < f; ++g)
            if (mm[g].samples == mm[f].samples)
                return g;
        return f;
    };
    for (std::size_t f = 0; f < mm.size(); ++f) {
        auto n = depth::metricToNearness(mm[f], co);
        if (!n)
            return unexpected(n.error());
        for (std::size_t i = 0; i < n->valid.size(); ++i)
            validCount[i] += n->valid.samples[i];
        if (keepHoles) {
            depth::Plane<std::uint16_t> q(scene.width, scene.height, 0);
            for (std::size_t i = 0; i < q.size(); ++i)
                if (n->valid.samples[i] != 0)
                    q.samples[i] = static_cast<std::uint16_t>(std::lround(depth::occupiedLevel(
                        static_cast<double>(n->nearness.samples[i]), co.vmax, occ)));
            scene.frames.push_back(packFrame(q, bits));
            std::vector<std::uint16_t> ref(q.size(), 0);
            if (const std::size_t g = sameAs(f); cleanMetres == nullptr && g < f) {
                ref = scene.reference[g];
            } else if (cleanMetres == nullptr) {
                const depth::Plane<float> m = maskedMedian(n->nearness, n->valid);
                for (std::size_t i = 0; i < ref.size(); ++i)
                    if (std::isfinite(m.samples[i]))
                        ref[i] = lift16(static_cast<double>(m.samples[i]));
            } else {
                const depth::Plane<float> &z = (*cleanMetres)[f];
                for (std::size_t i = 0; i < ref.size(); ++i)
                    if (z.samples[i] > 0.0f && n->valid.samples[i] != 0)
                        ref[i] = lift16(depth::metresToNearness(static_cast<double>(z.samples[i]),
                                                                *range, co.mapping, co.vmax));
            }
            scene.reference.push_back(std::move(ref));
            continue;
        }
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

std::string syntheticFeelSceneName(SyntheticScene which, SensorModel sensor)
{
    std::string name = syntheticSceneName(which);
    if (sensor != SensorModel::StructuredLight)
        name = name + "-" + sensorModelName(sensor);
    return name;
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
    const double clipSeconds = static_cast<double>(frames - 1) / o.fps;
    for (long i = 0; i < frames; ++i) {
        depth::Plane<std::uint8_t> dark;
        clean.push_back(renderClean(which, o.width, o.height, static_cast<double>(i) / o.fps,
                                    clipSeconds, &dark));
        const auto fi = static_cast<std::uint64_t>(i);
        if (o.noisy && o.sensor == SensorModel::TimeOfFlight) {
            sensor.push_back(applyTofNoise(clean.back(), o.tof, fi, &dark));
        } else if (o.noisy && o.sensor == SensorModel::ActiveStereo) {
            StereoNoiseOptions so = o.stereo;
            so.focalPx *= o.width / 640.0;
            sensor.push_back(applyStereoNoise(clean.back(), so, fi));
        } else if (o.noisy) {
            sensor.push_back(applyKinectNoise(clean.back(), o.noise, fi));
        } else {
            depth::Plane<std::uint16_t> p(o.width, o.height, 0);
            for (std::size_t k = 0; k < p.size(); ++k)
                p.samples[k] = static_cast<std::uint16_t>(
                    std::lround(static_cast<double>(clean.back().samples[k]) * 1000.0));
            sensor.push_back(std::move(p));
        }
    }
    auto scene = sceneFromSensorDepth(syntheticFeelSceneName(which, o.sensor), sensor, o.fps, o.box,
                                      o.bits, &clean, o.keepHoles);
    if (scene)
        scene->crossings = crossingsOf(which, o.width, o.height, 0.5 * scene->duration(), o.box);
    return scene;
}

} // namespace depthtouch::haptics::bench
