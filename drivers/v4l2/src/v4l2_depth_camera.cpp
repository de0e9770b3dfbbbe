#include "depthtouch/drivers/v4l2/v4l2_depth_camera.h"

#include <linux/videodev2.h>

#include <cmath>
#include <optional>
#include <utility>

#include "depthtouch/platform/log.h"
#include "v4l2_camera_impl.h"

DT_LOG_CATEGORY(V4l2)

namespace depthtouch::drivers {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Queries the \a role ("depth" or "color") node at node.path on \a dev into node.info.
/// \return Errors: those of queryV4l2Node() (logged with the node's role and path).
Result<void> queryNode(V4l2Device &dev, Node &node, const char *role)
{
    auto info = queryV4l2Node(dev, node.path);
    if (!info) {
        DT_LOG(V4l2, Error, "Failed to open V4L2 %s node %s: %s", role, node.path.c_str(),
               info.error().what);
        return unexpected(info.error());
    }
    node.info = std::move(*info);
    return ok();
}

} // namespace

using v4l2::sameFps;

V4l2DepthCamera::V4l2DepthCamera(std::unique_ptr<Impl> impl) : impl_(std::move(impl))
{
    caps_ = impl_->caps;
}

V4l2DepthCamera::~V4l2DepthCamera()
{
    if (state() == State::Streaming)
        (void)stop();
}

Result<std::unique_ptr<hal::DepthCamera>> V4l2DepthCamera::create(const hal::BackendConfig &cfg)
{
    auto settings = V4l2CameraSettings::parse(cfg);
    if (!settings)
        return unexpected(settings.error());
    auto cam = open(makeV4l2Device(cfg.clockRef()), cfg.clockRef(), *settings);
    if (!cam)
        return unexpected(cam.error());
    return std::unique_ptr<hal::DepthCamera>(std::move(*cam));
}

Result<std::unique_ptr<V4l2DepthCamera>> V4l2DepthCamera::open(std::unique_ptr<V4l2Device> device,
                                                               platform::Clock &clock,
                                                               const V4l2CameraSettings &settings)
{
    auto impl = std::make_unique<Impl>(std::move(device), clock, settings);
    Impl &d = *impl;
    if (d.settings.depthNode.empty()) {
        auto found = findDepthCameraNode(*d.dev);
        if (!found)
            return unexpected(found.error());
        d.depth.path = *found;
    } else {
        d.depth.path = d.settings.depthNode;
    }
    DT_TRY(queryNode(*d.dev, d.depth, "depth"));
    if (bestDepthFourcc(d.depth.info) == 0) {
        DT_LOG(V4l2, Error, "%s (%s) offers no depth format (Z16, Y16, GREY) for video capture",
               d.depth.path.c_str(), d.depth.info.card.c_str());
        return unexpected(Errc::NotSupported, "V4L2 node offers no depth format");
    }
    if (!d.settings.colorNode.empty()) {
        d.color.path = d.settings.colorNode;
        DT_TRY(queryNode(*d.dev, d.color, "color"));
        if ((d.color.info.deviceCaps & V4L2_CAP_VIDEO_CAPTURE) == 0)
            return unexpected(Errc::NotSupported, "V4L2 color node cannot capture video");
    }
    DT_TRY(d.buildModes());
    DT_TRY(d.openNodes());
    d.caps.name = d.depth.info.card.empty() ? std::string("V4L2 camera") : d.depth.info.card;
    d.caps.poolFrames = d.settings.poolFrames;
    DT_LOG(V4l2, Info, "V4L2 camera '%s': depth %s%s%s, %zu modes", d.caps.name.c_str(),
           d.depth.path.c_str(), d.color.path.empty() ? "" : ", color ", d.color.path.c_str(),
           d.caps.modes.size());
    return std::unique_ptr<V4l2DepthCamera>(new V4l2DepthCamera(std::move(impl)));
}

Result<void> V4l2DepthCamera::configureDevice(const hal::CameraConfig &cfg)
{
    Impl &d = *impl_;
    std::size_t mode = d.caps.modes.size();
    for (std::size_t i = 0; i < d.caps.modes.size(); ++i) {
        const hal::CameraMode &m = d.caps.modes[i];
        if (m.width == cfg.width && m.height == cfg.height && sameFps(m.fps, cfg.fps) &&
            (!cfg.depth || m.depthFormat == cfg.depthFormat) &&
            (!cfg.color ||
             (m.colorFormat == cfg.colorFormat && cfg.colorFormat != hal::PixelFormat::Unknown))) {
            mode = i;
            break;
        }
    }
    if (mode == d.caps.modes.size()) {
        if (cfg.color && d.color.path.empty())
            DT_LOG(V4l2, Error, "Color requested but no color node given (option color=)");
        return unexpected(Errc::NotSupported, "No such camera mode");
    }
    if (d.depthPool.lent() != 0 || d.colorPool.lent() != 0)
        return unexpected(Errc::Busy, "Frames are still lent");
    if (d.lost)
        d.closeNodes();
    DT_TRY(d.openNodes());

    // From here the nodes change: a failure leaves the camera Unconfigured, never with pools
    // that do not match the nodes' formats.
    if (auto r = d.applyConfig(cfg, mode); !r) {
        markUnconfigured();
        d.depth.active = false;
        d.color.active = false;
        d.converter.reset();
        (void)d.depthPool.allocate(0, hal::PixelFormat::Unknown, 0, 0);
        (void)d.colorPool.allocate(0, hal::PixelFormat::Unknown, 0, 0);
        return r;
    }
    return ok();
}

hal::CameraIntrinsics V4l2DepthCamera::intrinsicsDevice() const noexcept
{
    const Impl &d = *impl_;
    const double f = 0.5 * d.config.width / std::tan(0.5 * d.settings.hfovDegrees * kPi / 180.0);
    return {f, f, 0.5 * (d.config.width - 1), 0.5 * (d.config.height - 1)};
}

Result<void> V4l2DepthCamera::startDevice()
{
    Impl &d = *impl_;
    if (d.lost)
        d.closeNodes();
    DT_TRY(d.openNodes());
    // A reopened node (after an unplug) has lost its format: apply it again every time.
    DT_TRY(d.applyFormat(d.depth));
    if (d.color.active)
        DT_TRY(d.applyFormat(d.color));
    d.stats = {};
    d.pendingDepth.reset();
    d.heldColor.reset();
    d.startTime = d.clock.now();
    DT_TRY(d.startNode(d.depth));
    if (d.color.active) {
        if (auto r = d.startNode(d.color); !r) {
            d.stopNode(d.depth);
            return r;
        }
    }
    return ok();
}

void V4l2DepthCamera::stopDevice() noexcept
{
    Impl &d = *impl_;
    d.stopNode(d.depth);
    d.stopNode(d.color);
    d.pendingDepth.reset();
    d.heldColor.reset();
    if (d.lost)
        d.closeNodes();
}

Result<hal::Capture> V4l2DepthCamera::captureDevice(hal::Deadline until)
{
    Impl &d = *impl_;
    if (d.lost)
        return unexpected(Errc::NoDevice, "V4L2 camera unplugged");
    if (!d.depthPool.hasFree() || (d.colorActive() && !d.colorPool.hasFree())) {
        d.dropReady();
        if (d.lost)
            return unexpected(Errc::NoDevice, "V4L2 camera unplugged");
        return unexpected(Errc::Busy, "Every capture buffer is lent");
    }
    for (;;) {
        auto depthBuf = d.newestDepth(until);
        if (!depthBuf)
            return unexpected(depthBuf.error());
        if (!d.colorActive())
            return d.deliver(*depthBuf, std::nullopt);
        auto colorBuf = d.pairColor(depthBuf->time, until);
        if (!colorBuf) {
            if (colorBuf.error().code == Errc::Timeout)
                d.pendingDepth = *depthBuf; // its color may still come: keep it for the next call
            return unexpected(colorBuf.error());
        }
        if (*colorBuf) {
            auto out = d.deliver(*depthBuf, *colorBuf);
            if (out && !d.config.depth)
                out->depth.reset();
            return out;
        }
        ++d.stats.framesUnpaired;
        DT_TRY(d.requeue(d.depth, depthBuf->index));
    }
}

V4l2CameraStats V4l2DepthCamera::stats() const noexcept
{
    return impl_->stats;
}

std::uint32_t V4l2DepthCamera::depthFourcc() const noexcept
{
    return state() == State::Unconfigured ? 0 : impl_->depth.fourcc;
}

std::uint32_t V4l2DepthCamera::colorFourcc() const noexcept
{
    return impl_->color.active ? impl_->color.fourcc : 0;
}

V4l2Device &V4l2DepthCamera::device() noexcept
{
    return *impl_->dev;
}

} // namespace depthtouch::drivers
