#include "depthtouch/drivers/mock/mock_depth_camera.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string_view>

#include "depthtouch/drivers/common/backend_options.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/drivers/common/frame_pool.h"

DT_LOG_CATEGORY(Mock)

namespace depthtouch::drivers {

namespace {

constexpr NumericOption<MockCameraSettings> kOptions[] = {
    {.key = "pool", .integer = &MockCameraSettings::poolFrames, .min = 1, .max = 32},
};
constexpr double kPi = 3.14159265358979323846;
constexpr double kHalfFovRadians = 30.0 * kPi / 180.0;
constexpr double kMotionPeriodSeconds = 2.0;

/// Depth along the optical axis of the first hit of the ray through (u, v), and whether it is the
/// sphere.
struct Hit {
    double z = kMockWallMetres;
    bool sphere = false;
    hal::Vec3 normal; ///< Sphere hits only.
};

Hit trace(double rx, double ry, const hal::Vec3 &centre) noexcept
{
    // Ray p = t·(rx, ry, 1); the depth of p is t.
    const hal::Vec3 d{rx, ry, 1.0};
    const double a = hal::dot(d, d);
    const double b = -2.0 * hal::dot(d, centre);
    const double c = hal::dot(centre, centre) - kMockSphereRadius * kMockSphereRadius;
    const double disc = b * b - 4.0 * a * c;
    Hit hit;
    if (disc >= 0.0) {
        const double t = (-b - std::sqrt(disc)) / (2.0 * a);
        if (t > 0.0 && t < kMockWallMetres) {
            hit.z = t;
            hit.sphere = true;
            hit.normal = (d * t - centre) * (1.0 / kMockSphereRadius);
        }
    }
    return hit;
}

} // namespace

hal::Vec3 mockSphereCentre(double seconds) noexcept
{
    const double phase = 2.0 * kPi * seconds / kMotionPeriodSeconds;
    return {0.15 * std::sin(phase), 0.05 * std::cos(phase), kMockSphereDepth};
}

Result<MockCameraSettings> MockCameraSettings::parse(hal::OptionList options)
{
    return parseNumericOptions(options, kOptions, kLogCategoryMock,
                               "Unknown mock depth camera option",
                               "Mock depth camera option out of range");
}

Result<std::unique_ptr<hal::DepthCamera>> MockDepthCamera::create(const hal::BackendConfig &cfg)
{
    return createFromSettings<hal::DepthCamera, MockDepthCamera, MockCameraSettings>(cfg);
}

MockDepthCamera::MockDepthCamera(platform::Clock &clock, const MockCameraSettings &settings)
    : clock_(clock), settings_(settings), depthPool_(std::make_unique<FramePool>()),
      colorPool_(std::make_unique<FramePool>())
{
    caps_.name = "Mock RGB-D camera";
    caps_.poolFrames = settings.poolFrames;
    struct Size {
        int w, h;
        double fps;
    };
    for (const Size s :
         {Size{160, 120, 30.0}, Size{320, 240, 30.0}, Size{640, 480, 30.0}, Size{640, 480, 15.0}})
        for (const hal::PixelFormat depth : {hal::PixelFormat::Z16, hal::PixelFormat::Gray16})
            caps_.modes.push_back({s.w, s.h, s.fps, depth, hal::PixelFormat::Rgb24});
}

MockDepthCamera::~MockDepthCamera() = default;

Result<void> MockDepthCamera::configureDevice(const hal::CameraConfig &cfg)
{
    if (!present_)
        return unexpected(Errc::NoDevice, "Mock depth camera unplugged");
    const auto match =
        std::find_if(caps_.modes.begin(), caps_.modes.end(), [&](const hal::CameraMode &m) {
            return m.width == cfg.width && m.height == cfg.height &&
                   std::fabs(m.fps - cfg.fps) < 1e-6 &&
                   (!cfg.depth || m.depthFormat == cfg.depthFormat) &&
                   (!cfg.color || m.colorFormat == cfg.colorFormat);
        });
    if (match == caps_.modes.end())
        return unexpected(Errc::NotSupported, "No such camera mode");
    if (depthPool_->lent() != 0 || colorPool_->lent() != 0)
        return unexpected(Errc::Busy, "Frames are still lent");
    DT_TRY(depthPool_->allocate(cfg.depth ? settings_.poolFrames : 0, cfg.depthFormat, cfg.width,
                                cfg.height));
    DT_TRY(colorPool_->allocate(cfg.color ? settings_.poolFrames : 0, cfg.colorFormat, cfg.width,
                                cfg.height));
    config_ = cfg;
    return ok();
}

hal::CameraIntrinsics MockDepthCamera::intrinsicsDevice() const noexcept
{
    const double f = 0.5 * config_.width / std::tan(kHalfFovRadians);
    return {f, f, 0.5 * (config_.width - 1), 0.5 * (config_.height - 1)};
}

Result<void> MockDepthCamera::startDevice()
{
    if (!present_)
        return unexpected(Errc::NoDevice, "Mock depth camera unplugged");
    start_ = clock_.now();
    next_ = 0;
    pendingDrops_ = 0;
    dropped_ = 0;
    return ok();
}

platform::TimePoint MockDepthCamera::exposure(std::uint64_t k) const noexcept
{
    return start_ + platform::fromSeconds(static_cast<double>(k) / config_.fps);
}

Result<hal::Capture> MockDepthCamera::captureDevice(hal::Deadline until)
{
    if (!present_)
        return unexpected(Errc::NoDevice, "Mock depth camera unplugged");
    next_ += pendingDrops_;
    dropped_ += pendingDrops_;
    pendingDrops_ = 0;

    platform::TimePoint now = clock_.now();
    if (exposure(next_) > until) {
        if (until > now)
            clock_.sleepUntil(until);
        return unexpected(Errc::Timeout, "No camera frame before the deadline");
    }
    if (exposure(next_) > now) {
        clock_.sleepUntil(exposure(next_));
        now = clock_.now();
    }
    // A late consumer gets the newest exposed frame; the ones in between are lost.
    auto newest =
        static_cast<std::uint64_t>(std::floor(platform::toSeconds(now - start_) * config_.fps));
    while (newest > 0 && exposure(newest) > now)
        --newest;
    while (exposure(newest + 1) <= now)
        ++newest;
    if (newest > next_) {
        dropped_ += newest - next_;
        next_ = newest;
    }
    const std::uint64_t k = next_++;

    std::uint32_t depthSlot = 0;
    std::uint32_t colorSlot = 0;
    hal::Frame *depth = config_.depth ? depthPool_->acquire(depthSlot) : nullptr;
    hal::Frame *color = config_.color ? colorPool_->acquire(colorSlot) : nullptr;
    if ((config_.depth && depth == nullptr) || (config_.color && color == nullptr)) {
        if (depth != nullptr)
            depthPool_->abandon(depthSlot);
        if (color != nullptr)
            colorPool_->abandon(colorSlot);
        ++dropped_;
        return unexpected(Errc::Busy, "Every capture buffer is lent");
    }
    const platform::TimePoint t = exposure(k);
    for (hal::Frame *f : {depth, color}) {
        if (f == nullptr)
            continue;
        f->pts = t - start_;
        f->time = t;
        f->sequence = k;
        f->corrupt = false;
    }
    if (depth != nullptr)
        depth->kind = hal::StreamKind::Depth;
    if (color != nullptr)
        color->kind = hal::StreamKind::Color;
    render(depth, color, platform::toSeconds(t - start_));

    hal::Capture c;
    if (depth != nullptr)
        c.depth = depthPool_->lend(depthSlot);
    if (color != nullptr)
        c.color = colorPool_->lend(colorSlot);
    return c;
}

void MockDepthCamera::render(hal::Frame *depth, hal::Frame *color, double seconds) const noexcept
{
    const hal::CameraIntrinsics k = intrinsics();
    const hal::Vec3 centre = mockSphereCentre(seconds);
    const int w = config_.width;
    const int h = config_.height;
    const int shadowPixels = std::max(1, w / 80);
    const double invNear = 1.0 / config_.nearMetres;
    const double invFar = 1.0 / config_.farMetres;
    for (int v = 0; v < h; ++v) {
        const double ry = (v - k.cy) / k.fy;
        std::uint8_t *depthRow = depth != nullptr ? depth->image.row(0, v) : nullptr;
        std::uint8_t *colorRow = color != nullptr ? color->image.row(0, v) : nullptr;
        for (int u = 0; u < w; ++u) {
            const Hit hit = trace((u - k.cx) / k.fx, ry, centre);
            // The projector sits to the right of the sensor: wall pixels just left of the sphere
            // are shadowed.
            const bool shadow =
                !hit.sphere && trace((u + shadowPixels - k.cx) / k.fx, ry, centre).sphere;
            if (depthRow != nullptr) {
                std::uint16_t value = 0;
                if (!shadow) {
                    if (config_.depthFormat == hal::PixelFormat::Z16) {
                        value = static_cast<std::uint16_t>(std::lround(hit.z * 1000.0));
                    } else {
                        const double n = (1.0 / hit.z - invFar) / (invNear - invFar);
                        value = static_cast<std::uint16_t>(
                            std::lround(std::clamp(n, 0.0, 1.0) * 65535.0));
                    }
                }
                std::memcpy(depthRow + 2 * u, &value, sizeof(value));
            }
            if (colorRow != nullptr) {
                std::uint8_t *px = colorRow + 3 * u;
                if (hit.sphere) {
                    const double shade = 0.3 + 0.7 * std::max(0.0, -hit.normal.z);
                    px[0] = static_cast<std::uint8_t>(std::lround(220.0 * shade));
                    px[1] = static_cast<std::uint8_t>(std::lround(40.0 * shade));
                    px[2] = static_cast<std::uint8_t>(std::lround(40.0 * shade));
                } else {
                    std::uint8_t g = ((u / 16 + v / 16) % 2) != 0 ? 200 : 160;
                    if (shadow)
                        g = static_cast<std::uint8_t>(g / 2);
                    px[0] = px[1] = px[2] = g;
                }
            }
        }
    }
}

} // namespace depthtouch::drivers
