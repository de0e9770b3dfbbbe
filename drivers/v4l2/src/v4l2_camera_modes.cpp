#include <fcntl.h>
#include <linux/videodev2.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <iterator>
#include <string_view>
#include <utility>
#include <vector>

#include "depthtouch/platform/log.h"
#include "v4l2_camera_impl.h"

DT_LOG_CATEGORY(V4l2)

// V4l2DepthCamera's settings, modes and formats: what the nodes offer, and setting one mode on
// them.

namespace depthtouch::drivers {

using v4l2::sameFps;

namespace {

constexpr const char *kOptionKeys[] = {"device", "color", "pool", "buffers", "hfov"};

/// The hal depth formats a V4L2 depth format is delivered as.
std::vector<hal::PixelFormat> halDepthFormatsOf(std::uint32_t fourcc)
{
    if (fourcc == V4L2_PIX_FMT_Z16 || fourcc == V4L2_PIX_FMT_Y16)
        return {hal::PixelFormat::Z16, hal::PixelFormat::Gray16};
    if (fourcc == V4L2_PIX_FMT_GREY)
        return {hal::PixelFormat::Gray16};
    return {};
}

bool offers(const V4l2FormatDesc *f, int w, int h, double fps) noexcept
{
    if (f == nullptr)
        return false;
    for (const V4l2FrameSize &s : f->sizes)
        if (s.width == w && s.height == h)
            for (const double r : s.fps)
                if (sameFps(r, fps))
                    return true;
    return false;
}

} // namespace

namespace v4l2 {

bool sameFps(double a, double b) noexcept
{
    return std::fabs(a - b) < 1e-3 * std::max(1.0, std::fabs(b));
}

} // namespace v4l2

Result<V4l2CameraSettings> V4l2CameraSettings::parse(const hal::BackendConfig &cfg)
{
    const hal::OptionList &o = cfg.options;
    const std::string_view unknown = o.firstUnknownKey(kOptionKeys, std::size(kOptionKeys));
    if (!unknown.empty()) {
        DT_LOG(V4l2, Error,
               "Unknown v4l2 depth camera option '%.*s' (known: device, color, pool, "
               "buffers, hfov)",
               static_cast<int>(unknown.size()), unknown.data());
        return unexpected(Errc::InvalidArgument, "Unknown v4l2 depth camera option");
    }
    V4l2CameraSettings s;
    const auto device = o.find("device");
    if (device && !cfg.device.empty() && *device != cfg.device)
        return unexpected(Errc::InvalidArgument,
                          "v4l2 option device= disagrees with the device path given");
    if (device)
        s.depthNode = std::string(*device);
    else
        s.depthNode = std::string(cfg.device);
    if (const auto color = o.find("color"))
        s.colorNode = std::string(*color);
    if (s.colorNode == "none")
        s.colorNode.clear();
    if (!s.depthNode.empty() && s.depthNode == s.colorNode)
        return unexpected(Errc::InvalidArgument, "v4l2 depth and color nodes must differ");
    const auto pool = o.getInt("pool", s.poolFrames);
    const auto buffers = o.getInt("buffers", s.buffers);
    const auto hfov = o.getDouble("hfov", s.hfovDegrees);
    if (!pool || *pool < 1 || *pool > 32)
        return unexpected(Errc::InvalidArgument, "v4l2 option pool must be 1..32");
    if (!buffers || *buffers < 2 || *buffers > 32)
        return unexpected(Errc::InvalidArgument, "v4l2 option buffers must be 2..32");
    if (!hfov || !(*hfov >= 1.0 && *hfov <= 179.0))
        return unexpected(Errc::InvalidArgument, "v4l2 option hfov must be 1..179 degrees");
    s.poolFrames = *pool;
    s.buffers = *buffers;
    s.hfovDegrees = *hfov;
    return s;
}

Result<void> V4l2DepthCamera::Impl::buildModes()
{
    std::vector<std::uint32_t> colorFourccs;
    if (!color.path.empty()) {
        bool mjpegOnly = false;
        if (color.info.find(V4L2_PIX_FMT_YUYV) != nullptr)
            colorFourccs.push_back(V4L2_PIX_FMT_YUYV);
        if (color.info.find(V4L2_PIX_FMT_MJPEG) != nullptr) {
            if (v4l2::canConvertToRgb(V4L2_PIX_FMT_MJPEG))
                colorFourccs.push_back(V4L2_PIX_FMT_MJPEG);
            else
                mjpegOnly = colorFourccs.empty();
        }
        if (mjpegOnly) {
            DT_LOG(V4l2, Error,
                   "Color node %s offers MJPEG only, and this build has no FFmpeg to "
                   "decode it (configure with DT_WITH_FFMPEG)",
                   color.path.c_str());
            return unexpected(Errc::NotSupported,
                              "MJPEG color needs the FFmpeg feature to decode it");
        }
        if (colorFourccs.empty()) {
            DT_LOG(V4l2, Error, "Color node %s offers neither YUYV nor MJPEG", color.path.c_str());
            return unexpected(Errc::NotSupported, "V4L2 color node offers no YUYV or MJPEG");
        }
    }
    for (const std::uint32_t df : kV4l2DepthFourccs) {
        const V4l2FormatDesc *desc = depth.info.find(df);
        if (desc == nullptr)
            continue;
        for (const V4l2FrameSize &size : desc->sizes) {
            for (const double fps : size.fps) {
                for (const hal::PixelFormat hf : halDepthFormatsOf(df)) {
                    struct Choice {
                        hal::PixelFormat format;
                        std::uint32_t fourcc;
                    };
                    std::vector<Choice> choices;
                    for (const std::uint32_t cf : colorFourccs) {
                        if (!offers(color.info.find(cf), size.width, size.height, fps))
                            continue;
                        if (v4l2::canConvertToRgb(cf) &&
                            std::none_of(choices.begin(), choices.end(), [](const Choice &c) {
                                return c.format == hal::PixelFormat::Rgb24;
                            }))
                            choices.push_back({hal::PixelFormat::Rgb24, cf});
                        if (cf == V4L2_PIX_FMT_YUYV)
                            choices.push_back({hal::PixelFormat::Yuyv, cf});
                    }
                    if (choices.empty())
                        choices.push_back({hal::PixelFormat::Unknown, 0});
                    for (const Choice &c : choices) {
                        const hal::CameraMode m{size.width, size.height, fps, hf, c.format};
                        const bool known = std::any_of(
                            caps.modes.begin(), caps.modes.end(), [&](const hal::CameraMode &k) {
                                return k.width == m.width && k.height == m.height &&
                                       sameFps(k.fps, m.fps) && k.depthFormat == m.depthFormat &&
                                       k.colorFormat == m.colorFormat;
                            });
                        if (known)
                            continue; // a more preferred depth format already gives this mode
                        caps.modes.push_back(m);
                        modeSources.push_back({df, c.fourcc});
                    }
                }
            }
        }
    }
    if (caps.modes.empty())
        return unexpected(Errc::NotSupported, "V4L2 depth node lists no size or rate");
    return ok();
}

Result<void> V4l2DepthCamera::Impl::openNodes()
{
    for (Node *n : {&depth, &color}) {
        if (n->path.empty() || n->fd.isOpen())
            continue;
        const int fd = dev->open(n->path.c_str(), O_RDWR | O_NONBLOCK);
        if (fd < 0) {
            const int err = errno;
            closeNodes();
            return unexpected(errcOfErrno(err) == Errc::NoDevice ? Errc::NoDevice : Errc::Io,
                              "Failed to open the V4L2 camera node", err);
        }
        n->fd = V4l2Fd(*dev, fd);
    }
    lost = false;
    return ok();
}

void V4l2DepthCamera::Impl::closeNodes() noexcept
{
    depth.fd.reset();
    color.fd.reset();
}

Result<void> V4l2DepthCamera::Impl::applyFormat(Node &n)
{
    v4l2_format f{};
    f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    f.fmt.pix.width = static_cast<std::uint32_t>(n.width);
    f.fmt.pix.height = static_cast<std::uint32_t>(n.height);
    f.fmt.pix.pixelformat = n.fourcc;
    f.fmt.pix.field = V4L2_FIELD_NONE;
    if (const int err = v4l2Ioctl(*dev, n.fd.get(), VIDIOC_S_FMT, &f); err != 0)
        return fail(n, err, "Failed to set the V4L2 format");
    // S_FMT never refuses: the driver adjusts to what it can do, so check what it chose.
    if (f.fmt.pix.pixelformat != n.fourcc ||
        f.fmt.pix.width != static_cast<std::uint32_t>(n.width) ||
        f.fmt.pix.height != static_cast<std::uint32_t>(n.height)) {
        char want[5];
        char got[5];
        DT_LOG(V4l2, Error, "%s refused %s %dx%d (offers %s %ux%u)", n.path.c_str(),
               fourccName(n.fourcc, want), n.width, n.height,
               fourccName(f.fmt.pix.pixelformat, got), f.fmt.pix.width, f.fmt.pix.height);
        return unexpected(Errc::NotSupported, "V4L2 driver refused the format");
    }
    const std::uint32_t minLine =
        static_cast<std::uint32_t>(n.width) * (n.fourcc == V4L2_PIX_FMT_GREY ? 1U : 2U);
    n.bytesPerLine = std::max(f.fmt.pix.bytesperline, minLine);
    n.sizeImage = f.fmt.pix.sizeimage;
    if (n.fourcc != V4L2_PIX_FMT_MJPEG)
        n.sizeImage = std::max(n.sizeImage, n.bytesPerLine * static_cast<std::uint32_t>(n.height));

    v4l2_streamparm p{};
    p.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    p.parm.capture.timeperframe.numerator = 1000;
    p.parm.capture.timeperframe.denominator =
        static_cast<std::uint32_t>(std::lround(n.fps * 1000.0));
    if (const int err = v4l2Ioctl(*dev, n.fd.get(), VIDIOC_S_PARM, &p); err != 0) {
        if (errcOfErrno(err) == Errc::NoDevice)
            return fail(n, err, "Failed to set the frame rate");
        // Drivers without a settable rate answer EINVAL or ENOTTY: they run at their own rate.
        DT_LOG(V4l2, Warning, "%s: frame rate not settable (%s)", n.path.c_str(),
               std::strerror(err));
    }
    return ok();
}

Result<void> V4l2DepthCamera::Impl::applyConfig(const hal::CameraConfig &cfg, std::size_t mode)
{
    const ModeSource src = modeSources[mode];
    // The depth node always streams: it paces the captures and stamps their time.
    depth.fourcc = src.depthFourcc;
    depth.width = cfg.width;
    depth.height = cfg.height;
    depth.fps = cfg.fps;
    depth.active = true;
    DT_TRY(applyFormat(depth));
    color.active = cfg.color;
    converter.reset();
    if (cfg.color) {
        color.fourcc = src.colorFourcc;
        color.width = cfg.width;
        color.height = cfg.height;
        color.fps = cfg.fps;
        DT_TRY(applyFormat(color));
        if (cfg.colorFormat == hal::PixelFormat::Rgb24) {
            auto conv = v4l2::makeColorConverter(src.colorFourcc, cfg.width, cfg.height);
            if (!conv)
                return unexpected(conv.error());
            converter = std::move(*conv);
        }
    }
    const hal::PixelFormat depthOut = cfg.depth ? cfg.depthFormat : caps.modes[mode].depthFormat;
    if (depthOut == hal::PixelFormat::Gray16 && src.depthFourcc != V4L2_PIX_FMT_GREY) {
        const double nearMm = (cfg.nearMetres > 0.0 ? cfg.nearMetres : 0.3) * 1000.0;
        const double farMm = (cfg.farMetres > nearMm / 1000.0 ? cfg.farMetres * 1000.0 : 3000.0);
        nearnessLut.assign(65536, 0);
        for (std::size_t mm = 1; mm < nearnessLut.size(); ++mm) {
            const double v =
                (1.0 / static_cast<double>(mm) - 1.0 / farMm) / (1.0 / nearMm - 1.0 / farMm);
            nearnessLut[mm] =
                static_cast<std::uint16_t>(std::lround(std::clamp(v, 0.0, 1.0) * 65535.0));
        }
    }
    // Depth frames are always converted (they pace and stamp the captures); without the depth
    // stream they are simply not lent.
    DT_TRY(depthPool.allocate(settings.poolFrames, depthOut, cfg.width, cfg.height));
    DT_TRY(colorPool.allocate(cfg.color ? settings.poolFrames : 0, cfg.colorFormat, cfg.width,
                              cfg.height));
    config = cfg;
    config.depthFormat = depthOut;
    return ok();
}

} // namespace depthtouch::drivers
