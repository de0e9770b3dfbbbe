/// \file
/// \brief `v4l2:DEVICE` sources (see camera_source.h): a CameraShare owns one hal::DepthCamera
/// and hands each capture's color and depth frame to the two sources of the camera.

#include "depthtouch/media/camera_source.h"

#include <chrono>
#include <cmath>
#include <cstring>
#include <deque>
#include <optional>
#include <string>

#include "depthtouch/hal/backends.h"
#include "depthtouch/media/image_convert.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::media {

namespace {

/// Frames kept for the stream that has not asked yet (the other one ran ahead).
constexpr std::size_t kQueuedFrames = 8;
/// Longest wait for one capture.
constexpr auto kCaptureTimeout = std::chrono::seconds(2);

/// Copies a captured frame into an Image: Z16 → Gray16 (millimetres), Gray16 nearness → Gray8
/// (the high byte), Rgb24 as it is.
Result<media::Image> copyFrame(const hal::ImageView &v)
{
    media::PixelFormat format = media::PixelFormat::Rgb24;
    switch (v.format) {
    case hal::PixelFormat::Z16:
        format = media::PixelFormat::Gray16;
        break;
    case hal::PixelFormat::Gray16:
        format = media::PixelFormat::Gray8;
        break;
    case hal::PixelFormat::Rgb24:
        break;
    default:
        return unexpected(Errc::NotSupported, "The camera delivered an unexpected pixel format");
    }
    media::Image out = media::Image::make(v.width, v.height, format);
    for (int y = 0; y < v.height; ++y) {
        const std::uint8_t *src = v.row(0, y);
        std::uint8_t *dst = out.row(y);
        if (v.format == hal::PixelFormat::Gray16) {
            for (int x = 0; x < v.width; ++x) {
                std::uint16_t s = 0;
                std::memcpy(&s, src + 2 * x, sizeof s);
                dst[x] = static_cast<std::uint8_t>(s >> 8);
            }
        } else {
            std::memcpy(dst, src, out.stride);
        }
    }
    return out;
}

/// Splits "key=value,key=value" into the keys this layer reads and the rest (for the backend).
struct SplitOptions {
    std::string ours; ///< size, fps, stream
    std::string rest;
};

SplitOptions splitOptions(std::string_view text)
{
    SplitOptions out;
    while (!text.empty()) {
        const std::size_t comma = text.find(',');
        const std::string_view item = text.substr(0, comma);
        const std::string_view key = item.substr(0, item.find('='));
        std::string &to = (key == "size" || key == "fps" || key == "stream") ? out.ours : out.rest;
        if (!item.empty()) {
            if (!to.empty())
                to += ',';
            to += item;
        }
        text = comma == std::string_view::npos ? std::string_view{} : text.substr(comma + 1);
    }
    return out;
}

} // namespace

/// \brief One camera shared by its color and depth sources. Thread-bound, as the camera.
class CameraShare {
public:
    CameraShare(std::unique_ptr<hal::DepthCamera> camera, const hal::CameraConfig &config)
        : camera_(std::move(camera)), config_(config)
    {
    }
    ~CameraShare()
    {
        if (camera_->state() == hal::DepthCamera::State::Streaming)
            (void)camera_->stop();
    }
    CameraShare(const CameraShare &) = delete;
    CameraShare &operator=(const CameraShare &) = delete;

    [[nodiscard]] const hal::CameraConfig &config() const noexcept { return config_; }
    [[nodiscard]] const hal::DepthCameraCapabilities &capabilities() const noexcept
    {
        return camera_->capabilities();
    }

    void attach(bool depth) noexcept { ++users_[depth ? 1 : 0]; }
    void detach(bool depth) noexcept
    {
        --users_[depth ? 1 : 0];
        if (users_[depth ? 1 : 0] == 0)
            queued_[depth ? 1 : 0].clear();
    }

    /// The next frame of one stream, in the layout copyFrame() gives; PTS from the first capture.
    Result<media::SourceFrame> next(bool depth)
    {
        std::deque<media::SourceFrame> &mine = queued_[depth ? 1 : 0];
        if (!mine.empty()) {
            media::SourceFrame f = std::move(mine.front());
            mine.pop_front();
            return f;
        }
        if (camera_->state() != hal::DepthCamera::State::Streaming)
            DT_TRY(camera_->start());
        platform::Clock &clock = platform::SteadyClock::instance();
        auto capture = camera_->capture(clock.now() + kCaptureTimeout);
        if (!capture)
            return unexpected(capture.error());
        media::SourceFrame frames[2];
        const hal::FrameRef *refs[2] = {&capture->color, &capture->depth};
        for (int s = 0; s < 2; ++s) {
            if (!*refs[s] || (users_[s] == 0 && s != (depth ? 1 : 0)))
                continue;
            const hal::Frame &f = **refs[s];
            if (!firstPts_)
                firstPts_ = f.pts;
            frames[s].pts = platform::toSeconds(f.pts - *firstPts_);
            auto image = copyFrame(f.image);
            if (!image)
                return unexpected(image.error());
            frames[s].image = std::move(*image);
        }
        const int own = depth ? 1 : 0;
        const int other = 1 - own;
        if (frames[own].image.empty())
            return unexpected(Errc::Io, "The camera delivered a capture without that stream");
        if (users_[other] > 0 && !frames[other].image.empty()) {
            queued_[other].push_back(std::move(frames[other]));
            if (queued_[other].size() > kQueuedFrames)
                queued_[other].pop_front(); // the other stream is not read: keep its newest
        }
        return std::move(frames[own]);
    }

private:
    std::unique_ptr<hal::DepthCamera> camera_;
    hal::CameraConfig config_;
    int users_[2] = {0, 0}; ///< Sources of color [0] and depth [1].
    std::deque<media::SourceFrame> queued_[2];
    std::optional<platform::Duration> firstPts_;
};

namespace {

class CameraFrameSource final : public media::ConvertingFrameSource {
public:
    CameraFrameSource(std::shared_ptr<CameraShare> share, bool depth)
        : share_(std::move(share)), depth_(depth)
    {
        share_->attach(depth);
        const hal::CameraConfig &c = share_->config();
        info_.width = c.width;
        info_.height = c.height;
        info_.fps = c.fps;
        info_.frameCount = 0; // live
        const bool nearness = c.depthFormat == hal::PixelFormat::Gray16;
        info_.nativeFormat =
            !depth ? media::PixelFormat::Rgb24
                   : (nearness ? media::PixelFormat::Gray8 : media::PixelFormat::Gray16);
        info_.description = share_->capabilities().name + " " + std::to_string(c.width) + "x" +
                            std::to_string(c.height) + " " + (depth ? "depth" : "color");
    }
    ~CameraFrameSource() override { share_->detach(depth_); }

    Result<media::SourceFrame> next(media::PixelFormat format, int width, int height) override
    {
        auto frame = share_->next(depth_);
        if (!frame)
            return unexpected(frame.error());
        if (auto conformed = converter_.conform(frame->image, format, width, height); !conformed)
            return unexpected(conformed.error());
        return frame;
    }

private:
    std::shared_ptr<CameraShare> share_;
    bool depth_;
};

} // namespace

Result<CameraSpec> parseCameraSpec(std::string_view target, const media::SourceOptions &options)
{
    const std::size_t comma = target.find(',');
    CameraSpec spec;
    spec.device = std::string(target.substr(0, comma));
    if (spec.device.empty())
        return unexpected(Errc::InvalidArgument, "v4l2: needs a device, e.g. v4l2:/dev/video0");
    const SplitOptions split = splitOptions(
        comma == std::string_view::npos ? std::string_view{} : target.substr(comma + 1));
    spec.backendOptions = split.rest;
    const hal::OptionList ours(split.ours);
    DT_TRY(readSpecFrameSize(ours, options, "A V4L2 camera takes no demuxer or pixel format option",
                             "Camera size must be WxH (pixels)", spec.width, spec.height));
    auto fps = ours.getDouble("fps", 0.0);
    if (!fps || *fps < 0.0 || *fps > 1000.0)
        return unexpected(Errc::InvalidArgument, "Camera fps must be 0..1000 frames/s");
    spec.fps = *fps;
    spec.preferredFps = options.fps;
    auto depth = wantsDepthStream(ours.find("stream").value_or(std::string_view{}), options);
    if (!depth)
        return unexpected(depth.error());
    spec.depth = *depth;
    return spec;
}

Result<std::shared_ptr<CameraShare>> shareCamera(std::unique_ptr<hal::DepthCamera> camera,
                                                 const CameraSpec &spec)
{
    const auto sameFps = [](double a, double b) { return std::fabs(a - b) < 1e-3; };
    const hal::CameraMode *best = nullptr;
    int bestScore = -1;
    for (const hal::CameraMode &m : camera->capabilities().modes) {
        if (m.depthFormat != hal::PixelFormat::Z16 && m.depthFormat != hal::PixelFormat::Gray16)
            continue;
        if (spec.width > 0 && (m.width != spec.width || m.height != spec.height))
            continue;
        if (spec.fps > 0.0 && !sameFps(m.fps, spec.fps))
            continue;
        const int score = (sameFps(m.fps, spec.preferredFps) ? 4 : 0) +
                          (m.depthFormat == hal::PixelFormat::Z16 ? 2 : 0) +
                          (m.colorFormat == hal::PixelFormat::Rgb24 ? 1 : 0);
        if (score > bestScore) {
            best = &m;
            bestScore = score;
        }
    }
    if (best == nullptr)
        return unexpected(Errc::NotSupported,
                          "The camera has no depth mode of the size and rate asked");
    hal::CameraConfig cfg;
    cfg.width = best->width;
    cfg.height = best->height;
    cfg.fps = best->fps;
    cfg.depth = true;
    cfg.depthFormat = best->depthFormat;
    cfg.color = best->colorFormat == hal::PixelFormat::Rgb24;
    cfg.colorFormat = hal::PixelFormat::Rgb24;
    DT_TRY(camera->configure(cfg));
    return std::make_shared<CameraShare>(std::move(camera), cfg);
}

Result<std::unique_ptr<media::FrameSource>> openCameraSource(std::shared_ptr<CameraShare> share,
                                                             bool depth)
{
    if (!depth && !share->config().color)
        return unexpected(
            Errc::NotSupported,
            "The camera has no color stream (give its color node: color=/dev/videoM)");
    return std::unique_ptr<media::FrameSource>(
        std::make_unique<CameraFrameSource>(std::move(share), depth));
}

Result<std::unique_ptr<media::FrameSource>>
CameraSourceFactory::open(std::string_view target, const media::SourceOptions &options)
{
    auto spec = parseCameraSpec(target, options);
    if (!spec)
        return unexpected(spec.error());
    const std::string key = spec->device + "," + spec->backendOptions + "," +
                            std::to_string(spec->width) + "x" + std::to_string(spec->height) + "@" +
                            std::to_string(spec->fps);
    const std::lock_guard lock(mutex_);
    std::shared_ptr<CameraShare> share = findShared(cameras_, key);
    if (!share) {
        hal::BackendConfig cfg;
        cfg.device = spec->device;
        cfg.options = hal::OptionList(spec->backendOptions);
        auto camera = openCamera_(cfg);
        if (!camera) {
            Error e = camera.error();
            e.what = persistentText("No V4L2 depth camera at " + spec->device + ": " + e.what);
            return unexpected(e);
        }
        auto shared = shareCamera(std::move(*camera), *spec);
        if (!shared)
            return unexpected(shared.error());
        share = std::move(*shared);
        cameras_.emplace_back(key, share);
    }
    return openCameraSource(std::move(share), spec->depth);
}

} // namespace depthtouch::media
