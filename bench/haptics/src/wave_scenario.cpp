#include "depthtouch/haptics/wave_scenario.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace depthtouch::haptics::bench {

namespace {

constexpr int kPeriodFrames = 16; // the surface motion repeats every 16 frames (cached frames)
constexpr double kA = 0.003;      // m, wave amplitude
constexpr double kKx = 2.0 * std::numbers::pi / 0.04;
constexpr double kKy = 2.0 * std::numbers::pi / 0.05;
constexpr double kOmega = 2.0 * std::numbers::pi * kVideoFps / kPeriodFrames; // rad/s
constexpr double kPen = 0.002;    // m, stroke depth under the surface

void derivatives(double x, double y, double t, double &zx, double &zy, double &zxx, double &zyy,
                 double &zxy) noexcept
{
    const double s = std::sin(kKx * x - kOmega * t);
    const double c = std::cos(kKx * x - kOmega * t);
    const double cy = std::cos(kKy * y);
    const double sy = std::sin(kKy * y);
    zx = kA * kKx * c * cy;
    zy = -kA * kKy * s * sy;
    zxx = -kA * kKx * kKx * s * cy;
    zyy = -kA * kKy * kKy * s * cy;
    zxy = -kA * kKx * kKy * c * sy;
}

} // namespace

WaveScenario::WaveScenario(int width, int height, const SceneBox &box)
    : width_(width), height_(height), frames_(kPeriodFrames)
{
    const auto w = static_cast<std::size_t>(width);
    const auto h = static_cast<std::size_t>(height);
    const double s = box.width / (width - 1);
    std::vector<double> cy(h);
    for (std::size_t r = 0; r < h; ++r)
        cy[r] = std::cos(kKy * ((height - 1) * 0.5 - static_cast<double>(r)) * s);
    std::vector<double> sx(w);
    for (int i = 0; i < kPeriodFrames; ++i) {
        for (std::size_t c = 0; c < w; ++c)
            sx[c] = std::sin(kKx * (static_cast<double>(c) - (width - 1) * 0.5) * s -
                             kOmega * i / kVideoFps);
        std::vector<std::uint16_t> &f = frames_[static_cast<std::size_t>(i)];
        f.resize(w * h);
        for (std::size_t r = 0; r < h; ++r)
            for (std::size_t c = 0; c < w; ++c) {
                const double z = kA * sx[c] * cy[r];
                const double v = std::round((z / box.depth + 0.5) * 65535.0);
                f[r * w + c] = static_cast<std::uint16_t>(std::clamp(v, 0.0, 65535.0));
            }
    }
}

double WaveScenario::surfaceZ(double x, double y, double t) noexcept
{
    return kA * std::sin(kKx * x - kOmega * t) * std::cos(kKy * y);
}

glm::dvec3 WaveScenario::hipAt(double speed, double t) noexcept
{
    const double y = 0.002;
    if (speed == 0.0)
        return {0.003, y, -kA - kPen};
    // back and forth along x over ±35 mm (triangle wave), 2 mm under the moving surface
    const double span = 0.07;
    double d = std::fmod(speed * t, 2.0 * span);
    if (d > span)
        d = 2.0 * span - d;
    const double x = -0.035 + d;
    return {x, y, surfaceZ(x, y, t) - kPen};
}

glm::dvec3 WaveScenario::hipAtUpdate(double speed, std::size_t n, std::size_t settle) noexcept
{
    const glm::dvec3 target = hipAt(speed, timeAt(n));
    if (n >= settle)
        return target;
    // Approach from above during the settle period, then follow the motion.
    const glm::dvec3 start = hipAt(speed, 0.0) + glm::dvec3(0, 0, 0.012);
    return start + (hipAt(speed, timeAt(settle)) - start) *
                       (static_cast<double>(n) / static_cast<double>(settle));
}

int WaveScenario::frameIndexAt(double t) noexcept
{
    return static_cast<int>(std::floor(t * kVideoFps + 1e-9));
}

DepthFrameView WaveScenario::frame(int index) const noexcept
{
    const std::vector<std::uint16_t> &f = frames_[static_cast<std::size_t>(index % kPeriodFrames)];
    return DepthFrameView{reinterpret_cast<const std::uint8_t *>(f.data()), width_, height_,
                          static_cast<std::size_t>(width_) * 2, SampleFormat::Gray16,
                          index / kVideoFps};
}

glm::dvec3 WaveScenario::trueForce(const glm::dvec3 &hip, double t,
                                   const RendererConfig &cfg) noexcept
{
    if (hip.z >= surfaceZ(hip.x, hip.y, t))
        return glm::dvec3(0.0);
    double x = hip.x;
    double y = hip.y;
    for (int it = 0; it < 12; ++it) {
        double zx = 0;
        double zy = 0;
        double zxx = 0;
        double zyy = 0;
        double zxy = 0;
        derivatives(x, y, t, zx, zy, zxx, zyy, zxy);
        const double dz = surfaceZ(x, y, t) - hip.z;
        const double gx = (x - hip.x) + dz * zx;
        const double gy = (y - hip.y) + dz * zy;
        const double hxx = 1.0 + zx * zx + dz * zxx;
        const double hyy = 1.0 + zy * zy + dz * zyy;
        const double hxy = zx * zy + dz * zxy;
        const double det = hxx * hyy - hxy * hxy;
        if (!(std::fabs(det) > 1e-18))
            break;
        const double sx = (hyy * gx - hxy * gy) / det;
        const double sy = (hxx * gy - hxy * gx) / det;
        x -= sx;
        y -= sy;
        if (std::fabs(sx) + std::fabs(sy) < 1e-13)
            break;
    }
    glm::dvec3 f = cfg.stiffness * (glm::dvec3(x, y, surfaceZ(x, y, t)) - hip);
    const double len = glm::length(f);
    if (len > cfg.maxForce)
        f *= cfg.maxForce / len;
    return f;
}

bool poppedThrough(const HapticRenderer &renderer, const glm::dvec3 &proxy,
                   const HeightField *fallback) noexcept
{
    const HeightField *own = renderer.heightField();
    if (own == nullptr)
        own = fallback;
    if (own == nullptr)
        return false;
    const HeightField &surf = *own;
    const double radius = renderer.fingertipRadius();
    const double slack = radius > 0.0 ? 0.25 * radius : 1e-6 * surf.spacing();
    return surf.contains(proxy.x, proxy.y) && proxy.z < surf.heightAt(proxy.x, proxy.y) - slack;
}

} // namespace depthtouch::haptics::bench
