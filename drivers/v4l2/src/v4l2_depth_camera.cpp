#include "depthtouch/drivers/v4l2/v4l2_depth_camera.h"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/mman.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <iterator>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "color_converter.h"
#include "depthtouch/drivers/common/frame_pool.h"
#include "depthtouch/drivers/v4l2/v4l2_probe.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(V4l2)

namespace depthtouch::drivers {

namespace {

constexpr const char *kOptionKeys[] = {"device", "color", "pool", "buffers", "hfov"};
constexpr double kPi = 3.14159265358979323846;
constexpr std::uint32_t kMinBuffers = 2;

const char *stateName(hal::DepthCamera::State s) noexcept
{
    switch (s) {
    case hal::DepthCamera::State::Unconfigured:
        return "Unconfigured";
    case hal::DepthCamera::State::Configured:
        return "Configured";
    case hal::DepthCamera::State::Streaming:
        return "Streaming";
    }
    return "?";
}

bool sameFps(double a, double b) noexcept
{
    return std::fabs(a - b) < 1e-3 * std::max(1.0, std::fabs(b));
}

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

std::uint16_t loadLe16(const std::uint8_t *p) noexcept
{
    return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}

/// A buffer taken off a queue with VIDIOC_DQBUF.
struct Dequeued {
    std::uint32_t index = 0;
    std::uint32_t bytesUsed = 0;
    std::uint32_t sequence = 0;
    platform::TimePoint time{};
    bool damaged = false;
};

/// One mmap'ed buffer.
struct Mapping {
    void *data = nullptr;
    std::size_t length = 0;
};

} // namespace

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

/// One V4L2 node (depth or color) and its streaming state.
struct Node {
    std::string path;
    V4l2NodeInfo info;
    V4l2Fd fd;
    std::uint32_t fourcc = 0; ///< Negotiated format.
    int width = 0;
    int height = 0;
    double fps = 0.0;
    std::uint32_t bytesPerLine = 0;
    std::uint32_t sizeImage = 0;
    std::vector<Mapping> buffers;
    bool streaming = false;
    bool active = false; ///< Part of the configured streams.
};

/// Where the frames of a mode come from.
struct ModeSource {
    std::uint32_t depthFourcc = 0;
    std::uint32_t colorFourcc = 0; ///< 0: the mode has no color.
};

struct V4l2DepthCamera::Impl {
    Impl(std::unique_ptr<V4l2Device> d, platform::Clock &c, V4l2CameraSettings s)
        : dev(std::move(d)), clock(c), settings(std::move(s))
    {
    }

    Unexpected denied(const char *call, const char *required) const noexcept
    {
        DT_LOG(V4l2, Error, "In state %s trying %s() requiring %s", stateName(state), call,
               required);
        return unexpected(Errc::InvalidState, "Call not allowed in the camera's state");
    }
    /// Turns a failed ioctl into an error; ENODEV and friends mark the camera unplugged.
    Unexpected fail(const Node &n, int err, const char *what) noexcept
    {
        const Errc code = errcOfErrno(err);
        if (code == Errc::NoDevice) {
            if (!lost)
                DT_LOG(V4l2, Error, "V4L2 node %s is gone: %s", n.path.c_str(), std::strerror(err));
            lost = true;
            return unexpected(Errc::NoDevice, "V4L2 camera unplugged", err);
        }
        DT_LOG(V4l2, Error, "%s on %s: %s", what, n.path.c_str(), std::strerror(err));
        return unexpected(code, what, err);
    }

    Result<void> buildModes();
    Result<void> openNodes();
    void closeNodes() noexcept;
    Result<void> applyFormat(Node &n);
    Result<void> startNode(Node &n);
    void stopNode(Node &n) noexcept;
    Result<std::optional<Dequeued>> dequeue(Node &n);
    Result<void> requeue(Node &n, std::uint32_t index);
    Result<short> waitReadable(Node &n, hal::Deadline until);
    Result<Dequeued> newestDepth(hal::Deadline until);
    /// A matched color buffer, or nullopt when the depth buffer has no partner.
    Result<std::optional<Dequeued>> pairColor(platform::TimePoint depthTime, hal::Deadline until);
    void dropReady() noexcept;
    /// Sets the nodes' formats, the converter and the pools for mode \a mode of caps.
    Result<void> applyConfig(const hal::CameraConfig &cfg, std::size_t mode);
    Result<hal::Capture> deliver(const Dequeued &d, const std::optional<Dequeued> &c);
    void convertDepth(const std::uint8_t *src, hal::Frame &out) const noexcept;
    [[nodiscard]] bool colorActive() const noexcept { return color.active; }

    std::unique_ptr<V4l2Device> dev;
    platform::Clock &clock;
    const V4l2CameraSettings settings;
    hal::DepthCameraCapabilities caps;
    std::vector<ModeSource> modeSources; ///< Parallel to caps.modes.
    Node depth;
    Node color; ///< path empty: no color node.
    State state = State::Unconfigured;
    hal::CameraConfig config;
    FramePool depthPool;
    FramePool colorPool;
    std::unique_ptr<v4l2::ColorConverter> converter;
    std::vector<std::uint16_t> nearnessLut; ///< Millimetres → Gray16 nearness.
    bool lost = false;
    platform::TimePoint startTime{};
    std::optional<Dequeued> pendingDepth; ///< Dequeued, waiting for its color partner.
    std::optional<Dequeued> heldColor;    ///< Dequeued, newer than the last depth buffer.
    V4l2CameraStats stats;
};

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

Result<void> V4l2DepthCamera::Impl::startNode(Node &n)
{
    v4l2_requestbuffers req{};
    req.count = static_cast<std::uint32_t>(settings.buffers);
    req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    req.memory = V4L2_MEMORY_MMAP;
    if (const int err = v4l2Ioctl(*dev, n.fd.get(), VIDIOC_REQBUFS, &req); err != 0)
        return fail(n, err, "Failed to request V4L2 mmap buffers");
    if (req.count < kMinBuffers) {
        stopNode(n);
        return unexpected(Errc::OutOfResources, "V4L2 driver gave fewer than 2 buffers");
    }
    n.buffers.assign(req.count, Mapping{});
    for (std::uint32_t i = 0; i < req.count; ++i) {
        v4l2_buffer b{};
        b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        b.memory = V4L2_MEMORY_MMAP;
        b.index = i;
        if (const int err = v4l2Ioctl(*dev, n.fd.get(), VIDIOC_QUERYBUF, &b); err != 0) {
            stopNode(n);
            return fail(n, err, "Failed to query a V4L2 buffer");
        }
        void *p = dev->mmap(b.length, PROT_READ | PROT_WRITE, MAP_SHARED, n.fd.get(), b.m.offset);
        if (p == MAP_FAILED) {
            const int err = errno;
            stopNode(n);
            return fail(n, err, "Failed to map a V4L2 buffer");
        }
        n.buffers[i] = {p, b.length};
        if (b.length < n.sizeImage && n.fourcc != V4L2_PIX_FMT_MJPEG) {
            stopNode(n);
            return unexpected(Errc::Io, "V4L2 buffer smaller than the image");
        }
    }
    for (std::uint32_t i = 0; i < req.count; ++i)
        if (auto r = requeue(n, i); !r) {
            stopNode(n);
            return r;
        }
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (const int err = v4l2Ioctl(*dev, n.fd.get(), VIDIOC_STREAMON, &type); err != 0) {
        stopNode(n);
        return fail(n, err, "Failed to start V4L2 streaming");
    }
    n.streaming = true;
    return ok();
}

void V4l2DepthCamera::Impl::stopNode(Node &n) noexcept
{
    if (n.fd.isOpen() && n.streaming) {
        int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        (void)v4l2Ioctl(*dev, n.fd.get(), VIDIOC_STREAMOFF, &type); // fails once unplugged
    }
    n.streaming = false;
    for (Mapping &m : n.buffers)
        if (m.data != nullptr)
            dev->munmap(m.data, m.length);
    const bool hadBuffers = !n.buffers.empty();
    n.buffers.clear();
    if (n.fd.isOpen() && hadBuffers) {
        v4l2_requestbuffers req{};
        req.count = 0;
        req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        req.memory = V4L2_MEMORY_MMAP;
        (void)v4l2Ioctl(*dev, n.fd.get(), VIDIOC_REQBUFS, &req);
    }
}

Result<std::optional<Dequeued>> V4l2DepthCamera::Impl::dequeue(Node &n)
{
    v4l2_buffer b{};
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    const int err = v4l2Ioctl(*dev, n.fd.get(), VIDIOC_DQBUF, &b);
    if (err == EAGAIN)
        return std::optional<Dequeued>();
    if (err != 0)
        return fail(n, err, "Failed to dequeue a V4L2 buffer");
    if (b.index >= n.buffers.size())
        return unexpected(Errc::Io, "V4L2 driver returned an unknown buffer");
    Dequeued d;
    d.index = b.index;
    d.bytesUsed = b.bytesused;
    d.sequence = b.sequence;
    if ((b.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC)
        d.time = platform::TimePoint(std::chrono::seconds(b.timestamp.tv_sec) +
                                     std::chrono::microseconds(b.timestamp.tv_usec));
    else
        d.time = clock.now();
    const std::uint32_t need =
        n.fourcc == V4L2_PIX_FMT_MJPEG ? 1U : n.bytesPerLine * static_cast<std::uint32_t>(n.height);
    d.damaged = (b.flags & V4L2_BUF_FLAG_ERROR) != 0 || b.bytesused < need ||
                b.bytesused > n.buffers[b.index].length;
    return std::optional<Dequeued>(d);
}

Result<void> V4l2DepthCamera::Impl::requeue(Node &n, std::uint32_t index)
{
    v4l2_buffer b{};
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = index;
    if (const int err = v4l2Ioctl(*dev, n.fd.get(), VIDIOC_QBUF, &b); err != 0)
        return fail(n, err, "Failed to queue a V4L2 buffer");
    return ok();
}

Result<short> V4l2DepthCamera::Impl::waitReadable(Node &n, hal::Deadline until)
{
    for (;;) {
        const platform::Duration left = std::max(platform::Duration::zero(), until - clock.now());
        pollfd p{n.fd.get(), POLLIN, 0};
        const int r = dev->poll(&p, 1, left);
        if (r < 0) {
            const int err = errno;
            if (err == EINTR)
                continue;
            return fail(n, err, "Failed to poll the V4L2 node");
        }
        if (r == 0)
            return unexpected(Errc::Timeout, "No camera frame before the deadline");
        return p.revents;
    }
}

Result<Dequeued> V4l2DepthCamera::Impl::newestDepth(hal::Deadline until)
{
    std::optional<Dequeued> held = std::exchange(pendingDepth, std::nullopt);
    bool damagedSeen = false;
    bool pollError = false;
    for (;;) {
        for (;;) {
            auto d = dequeue(depth);
            if (!d)
                return unexpected(d.error());
            if (!*d)
                break;
            if ((*d)->damaged) {
                ++stats.framesDamaged;
                damagedSeen = true;
                DT_TRY(requeue(depth, (*d)->index));
                continue;
            }
            if (held) {
                ++stats.framesDropped; // a newer frame is ready: the caller is late
                DT_TRY(requeue(depth, held->index));
            }
            held = **d;
        }
        if (held)
            return *held;
        if (pollError)
            return unexpected(Errc::Io, "V4L2 node reports an error");
        auto w = waitReadable(depth, until);
        if (!w) {
            if (w.error().code == Errc::Timeout && damagedSeen)
                return unexpected(Errc::Io, "Only damaged camera frames before the deadline");
            return unexpected(w.error());
        }
        pollError = (*w & POLLIN) == 0;
    }
}

Result<std::optional<Dequeued>> V4l2DepthCamera::Impl::pairColor(platform::TimePoint depthTime,
                                                                 hal::Deadline until)
{
    const platform::Duration tolerance = platform::fromSeconds(0.5 / color.fps);
    bool pollError = false;
    for (;;) {
        std::optional<Dequeued> c = std::exchange(heldColor, std::nullopt);
        if (!c) {
            auto d = dequeue(color);
            if (!d)
                return unexpected(d.error());
            c = *d;
        }
        if (c) {
            pollError = false;
            if (c->damaged) {
                ++stats.framesDamaged;
                DT_TRY(requeue(color, c->index));
                continue;
            }
            if (c->time < depthTime - tolerance) {
                ++stats.framesDropped; // older than the depth frame: its partner was dropped
                DT_TRY(requeue(color, c->index));
                continue;
            }
            if (c->time <= depthTime + tolerance)
                return c;
            heldColor = c; // belongs to a later depth frame
            return std::optional<Dequeued>();
        }
        if (pollError)
            return unexpected(Errc::Io, "V4L2 color node reports an error");
        auto w = waitReadable(color, until);
        if (!w)
            return unexpected(w.error());
        pollError = (*w & POLLIN) == 0;
    }
}

void V4l2DepthCamera::Impl::dropReady() noexcept
{
    if (pendingDepth) {
        ++stats.framesDropped;
        (void)requeue(depth, pendingDepth->index);
        pendingDepth.reset();
    }
    for (Node *n : {&depth, &color}) {
        if (!n->active)
            continue;
        for (int guard = 0; guard < 64; ++guard) {
            auto d = dequeue(*n);
            if (!d || !*d)
                break;
            ++stats.framesDropped;
            if (!requeue(*n, (*d)->index))
                break;
        }
    }
}

void V4l2DepthCamera::Impl::convertDepth(const std::uint8_t *src, hal::Frame &out) const noexcept
{
    const int w = depth.width;
    for (int y = 0; y < depth.height; ++y) {
        const std::uint8_t *row = src + static_cast<std::size_t>(y) * depth.bytesPerLine;
        std::uint8_t *dst = out.image.row(0, y);
        if (depth.fourcc == V4L2_PIX_FMT_GREY) {
            for (int x = 0; x < w; ++x) {
                const auto v = static_cast<std::uint16_t>(row[x] * 257);
                std::memcpy(dst + 2 * x, &v, sizeof(v));
            }
        } else if (out.image.format == hal::PixelFormat::Z16) {
            if constexpr (std::endian::native == std::endian::little) {
                std::memcpy(dst, row, static_cast<std::size_t>(2 * w));
            } else {
                for (int x = 0; x < w; ++x) {
                    const std::uint16_t v = loadLe16(row + 2 * x);
                    std::memcpy(dst + 2 * x, &v, sizeof(v));
                }
            }
        } else {
            for (int x = 0; x < w; ++x) {
                const std::uint16_t v = nearnessLut[loadLe16(row + 2 * x)];
                std::memcpy(dst + 2 * x, &v, sizeof(v));
            }
        }
    }
}

Result<hal::Capture> V4l2DepthCamera::Impl::deliver(const Dequeued &d,
                                                    const std::optional<Dequeued> &c)
{
    std::uint32_t depthSlot = 0;
    std::uint32_t colorSlot = 0;
    hal::Frame *df = depthPool.acquire(depthSlot);
    hal::Frame *cf = c ? colorPool.acquire(colorSlot) : nullptr;
    bool damaged = false;
    convertDepth(static_cast<const std::uint8_t *>(depth.buffers[d.index].data), *df);
    if (cf != nullptr) {
        const auto *src = static_cast<const std::uint8_t *>(color.buffers[c->index].data);
        if (config.colorFormat == hal::PixelFormat::Yuyv) {
            const auto rowBytes = std::min<std::size_t>(
                static_cast<std::size_t>(cf->image.planes[0].strideBytes), color.bytesPerLine);
            for (int y = 0; y < color.height; ++y)
                std::memcpy(cf->image.row(0, y),
                            src + static_cast<std::size_t>(y) * color.bytesPerLine, rowBytes);
        } else {
            damaged = !converter->convert(src, c->bytesUsed, static_cast<int>(color.bytesPerLine),
                                          cf->image);
        }
    }
    auto rd = requeue(depth, d.index);
    auto rc = c ? requeue(color, c->index) : Result<void>(ok());
    if (!rd || !rc || damaged) {
        depthPool.abandon(depthSlot);
        if (cf != nullptr)
            colorPool.abandon(colorSlot);
        if (!rd)
            return unexpected(rd.error());
        if (!rc)
            return unexpected(rc.error());
        ++stats.framesDamaged;
        return unexpected(Errc::Io, "Camera color frame could not be decoded");
    }
    const hal::Pts pts = std::max(hal::Pts::zero(), d.time - startTime);
    df->kind = hal::StreamKind::Depth;
    for (hal::Frame *f : {df, cf}) {
        if (f == nullptr)
            continue;
        f->pts = pts;
        f->time = d.time;
        f->sequence = d.sequence;
        f->corrupt = false;
    }
    if (cf != nullptr)
        cf->kind = hal::StreamKind::Color;
    ++stats.captures;
    hal::Capture out;
    out.depth = depthPool.lend(depthSlot);
    if (cf != nullptr)
        out.color = colorPool.lend(colorSlot);
    return out;
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

V4l2DepthCamera::V4l2DepthCamera(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

V4l2DepthCamera::~V4l2DepthCamera()
{
    if (impl_->state == State::Streaming)
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
    auto info = queryV4l2Node(*d.dev, d.depth.path);
    if (!info) {
        DT_LOG(V4l2, Error, "Failed to open V4L2 depth node %s: %s", d.depth.path.c_str(),
               info.error().what);
        return unexpected(info.error());
    }
    d.depth.info = std::move(*info);
    if (bestDepthFourcc(d.depth.info) == 0) {
        DT_LOG(V4l2, Error, "%s (%s) offers no depth format (Z16, Y16, GREY) for video capture",
               d.depth.path.c_str(), d.depth.info.card.c_str());
        return unexpected(Errc::NotSupported, "V4L2 node offers no depth format");
    }
    if (!d.settings.colorNode.empty()) {
        d.color.path = d.settings.colorNode;
        auto cinfo = queryV4l2Node(*d.dev, d.color.path);
        if (!cinfo) {
            DT_LOG(V4l2, Error, "Failed to open V4L2 color node %s: %s", d.color.path.c_str(),
                   cinfo.error().what);
            return unexpected(cinfo.error());
        }
        d.color.info = std::move(*cinfo);
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

const hal::DepthCameraCapabilities &V4l2DepthCamera::capabilities() const noexcept
{
    return impl_->caps;
}

hal::DepthCamera::State V4l2DepthCamera::state() const noexcept
{
    return impl_->state;
}

Result<void> V4l2DepthCamera::configure(const hal::CameraConfig &cfg)
{
    Impl &d = *impl_;
    if (d.state == State::Streaming)
        return d.denied("configure", "Unconfigured or Configured");
    if (!cfg.depth && !cfg.color)
        return unexpected(Errc::InvalidArgument, "No stream requested");
    if (cfg.depth && cfg.depthFormat == hal::PixelFormat::Gray16 &&
        !(cfg.nearMetres > 0.0 && cfg.farMetres > cfg.nearMetres))
        return unexpected(Errc::InvalidArgument, "Nearness needs 0 < near < far");
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
        d.state = State::Unconfigured;
        d.depth.active = false;
        d.color.active = false;
        d.converter.reset();
        (void)d.depthPool.allocate(0, hal::PixelFormat::Unknown, 0, 0);
        (void)d.colorPool.allocate(0, hal::PixelFormat::Unknown, 0, 0);
        return r;
    }
    d.state = State::Configured;
    return ok();
}

hal::CameraIntrinsics V4l2DepthCamera::intrinsics() const noexcept
{
    const Impl &d = *impl_;
    if (d.state == State::Unconfigured)
        return {};
    const double f = 0.5 * d.config.width / std::tan(0.5 * d.settings.hfovDegrees * kPi / 180.0);
    return {f, f, 0.5 * (d.config.width - 1), 0.5 * (d.config.height - 1)};
}

Result<void> V4l2DepthCamera::start()
{
    Impl &d = *impl_;
    if (d.state != State::Configured)
        return d.denied("start", "Configured");
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
    d.state = State::Streaming;
    return ok();
}

Result<void> V4l2DepthCamera::stop()
{
    Impl &d = *impl_;
    if (d.state != State::Streaming)
        return d.denied("stop", "Streaming");
    d.stopNode(d.depth);
    d.stopNode(d.color);
    d.pendingDepth.reset();
    d.heldColor.reset();
    if (d.lost)
        d.closeNodes();
    d.state = State::Configured;
    return ok();
}

Result<hal::Capture> V4l2DepthCamera::capture(hal::Deadline until)
{
    Impl &d = *impl_;
    if (d.state != State::Streaming)
        return d.denied("capture", "Streaming");
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
    return impl_->state == State::Unconfigured ? 0 : impl_->depth.fourcc;
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
