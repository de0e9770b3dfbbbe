#include "depthtouch/drivers/v4l2/v4l2_probe.h"

#include <fcntl.h>
#include <linux/videodev2.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <iterator>

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(V4l2)

namespace depthtouch::drivers {

static_assert(kV4l2DepthFourccs[0] == V4L2_PIX_FMT_Z16);
static_assert(kV4l2DepthFourccs[1] == V4L2_PIX_FMT_Y16);
static_assert(kV4l2DepthFourccs[2] == V4L2_PIX_FMT_GREY);

namespace {

constexpr int kMaxEnumerations = 256; // a broken driver must not make a probe loop forever

std::uint32_t deviceCapsOf(const v4l2_capability &cap) noexcept
{
    return (cap.capabilities & V4L2_CAP_DEVICE_CAPS) != 0 ? cap.device_caps : cap.capabilities;
}

Result<V4l2Fd> openNode(V4l2Device &dev, const std::string &path)
{
    const int fd = dev.open(path.c_str(), O_RDWR | O_NONBLOCK);
    if (fd < 0) {
        const int err = errno;
        return unexpected(errcOfErrno(err), "Failed to open V4L2 node", err);
    }
    return V4l2Fd(dev, fd);
}

void addRates(V4l2Device &dev, int fd, std::uint32_t fourcc, V4l2FrameSize &size)
{
    for (int i = 0; i < kMaxEnumerations; ++i) {
        v4l2_frmivalenum iv{};
        iv.index = static_cast<std::uint32_t>(i);
        iv.pixel_format = fourcc;
        iv.width = static_cast<std::uint32_t>(size.width);
        iv.height = static_cast<std::uint32_t>(size.height);
        if (v4l2Ioctl(dev, fd, VIDIOC_ENUM_FRAMEINTERVALS, &iv) != 0)
            break;
        if (iv.type == V4L2_FRMIVAL_TYPE_DISCRETE) {
            if (iv.discrete.numerator != 0 && iv.discrete.denominator != 0)
                size.fps.push_back(static_cast<double>(iv.discrete.denominator) /
                                   static_cast<double>(iv.discrete.numerator));
            continue;
        }
        // Stepwise or continuous: sample the range (intervals, so the fastest rate is 1/min).
        const auto rate = [](const v4l2_fract &f) {
            return f.numerator != 0
                       ? static_cast<double>(f.denominator) / static_cast<double>(f.numerator)
                       : 0.0;
        };
        const double fastest = rate(iv.stepwise.min);
        const double slowest = rate(iv.stepwise.max);
        for (const double r : {15.0, 30.0, 60.0})
            if (r >= slowest - 1e-9 && r <= fastest + 1e-9)
                size.fps.push_back(r);
        if (fastest > 0.0 && std::find(size.fps.begin(), size.fps.end(), fastest) == size.fps.end())
            size.fps.push_back(fastest);
        break;
    }
}

void addSizes(V4l2Device &dev, int fd, V4l2FormatDesc &format)
{
    for (int i = 0; i < kMaxEnumerations; ++i) {
        v4l2_frmsizeenum fs{};
        fs.index = static_cast<std::uint32_t>(i);
        fs.pixel_format = format.fourcc;
        if (v4l2Ioctl(dev, fd, VIDIOC_ENUM_FRAMESIZES, &fs) != 0)
            break;
        if (fs.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
            format.sizes.push_back(
                {static_cast<int>(fs.discrete.width), static_cast<int>(fs.discrete.height), {}});
            continue;
        }
        const v4l2_frmsize_stepwise &s = fs.stepwise;
        const auto fits = [&s](std::uint32_t w, std::uint32_t h) {
            const std::uint32_t sw = std::max(1U, s.step_width);
            const std::uint32_t sh = std::max(1U, s.step_height);
            return w >= s.min_width && w <= s.max_width && h >= s.min_height && h <= s.max_height &&
                   (w - s.min_width) % sw == 0 && (h - s.min_height) % sh == 0;
        };
        struct Wh {
            std::uint32_t w, h;
        };
        for (const Wh wh : {Wh{s.min_width, s.min_height}, Wh{320, 240}, Wh{640, 480},
                            Wh{1280, 720}, Wh{s.max_width, s.max_height}}) {
            const bool dup = std::any_of(format.sizes.begin(), format.sizes.end(), [&](auto &z) {
                return z.width == static_cast<int>(wh.w) && z.height == static_cast<int>(wh.h);
            });
            if (fits(wh.w, wh.h) && !dup && wh.w > 0 && wh.h > 0)
                format.sizes.push_back({static_cast<int>(wh.w), static_cast<int>(wh.h), {}});
        }
        break;
    }
    for (V4l2FrameSize &size : format.sizes)
        addRates(dev, fd, format.fourcc, size);
}

} // namespace

const V4l2FormatDesc *V4l2NodeInfo::find(std::uint32_t fourcc) const noexcept
{
    for (const V4l2FormatDesc &f : capture)
        if (f.fourcc == fourcc)
            return &f;
    return nullptr;
}

Result<V4l2NodeInfo> queryV4l2Node(V4l2Device &dev, const std::string &path)
{
    auto fd = openNode(dev, path);
    if (!fd)
        return unexpected(fd.error());
    v4l2_capability cap{};
    if (const int err = v4l2Ioctl(dev, fd->get(), VIDIOC_QUERYCAP, &cap); err != 0) {
        const Errc code = errcOfErrno(err);
        return unexpected(code == Errc::NotSupported ? Errc::Io : code,
                          "Failed to query V4L2 capabilities (not a V4L2 node?)", err);
    }
    V4l2NodeInfo info;
    info.path = path;
    info.card.assign(reinterpret_cast<const char *>(cap.card),
                     strnlen(reinterpret_cast<const char *>(cap.card), sizeof(cap.card)));
    info.deviceCaps = deviceCapsOf(cap);
    if ((info.deviceCaps & V4L2_CAP_VIDEO_CAPTURE) == 0)
        return info;
    for (int i = 0; i < kMaxEnumerations; ++i) {
        v4l2_fmtdesc fd2{};
        fd2.index = static_cast<std::uint32_t>(i);
        fd2.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        const int err = v4l2Ioctl(dev, fd->get(), VIDIOC_ENUM_FMT, &fd2);
        if (err == EINVAL)
            break;
        if (err != 0)
            return unexpected(errcOfErrno(err), "Failed to enumerate V4L2 formats", err);
        V4l2FormatDesc desc;
        desc.fourcc = fd2.pixelformat;
        addSizes(dev, fd->get(), desc);
        info.capture.push_back(std::move(desc));
    }
    return info;
}

std::uint32_t bestDepthFourcc(const V4l2NodeInfo &node) noexcept
{
    if ((node.deviceCaps & V4L2_CAP_VIDEO_CAPTURE) == 0)
        return 0;
    for (const std::uint32_t f : kV4l2DepthFourccs)
        if (node.find(f) != nullptr)
            return f;
    return 0;
}

Result<std::string> findDepthCameraNode(V4l2Device &dev)
{
    std::string best;
    std::size_t bestRank = std::size(kV4l2DepthFourccs);
    for (const std::string &path : dev.listNodes()) {
        auto info = queryV4l2Node(dev, path);
        if (!info) {
            DT_LOG(V4l2, Debug, "Skipping %s: %s", path.c_str(), info.error().what);
            continue;
        }
        const std::uint32_t f = bestDepthFourcc(*info);
        const auto *it = std::find(std::begin(kV4l2DepthFourccs), std::end(kV4l2DepthFourccs), f);
        const auto rank = static_cast<std::size_t>(it - std::begin(kV4l2DepthFourccs));
        if (f != 0 && rank < bestRank) {
            bestRank = rank;
            best = path;
        }
    }
    if (best.empty())
        return unexpected(Errc::NoDevice, "No V4L2 capture node offers a depth format");
    return best;
}

Result<std::string> findM2mH264Decoder(V4l2Device &dev)
{
    for (const std::string &path : dev.listNodes()) {
        auto fd = openNode(dev, path);
        if (!fd)
            continue;
        v4l2_capability cap{};
        if (v4l2Ioctl(dev, fd->get(), VIDIOC_QUERYCAP, &cap) != 0)
            continue;
        const std::uint32_t caps = deviceCapsOf(cap);
        std::uint32_t type = 0;
        if ((caps & V4L2_CAP_VIDEO_M2M_MPLANE) != 0)
            type = V4L2_BUF_TYPE_VIDEO_OUTPUT_MPLANE;
        else if ((caps & V4L2_CAP_VIDEO_M2M) != 0)
            type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
        else
            continue;
        for (int i = 0; i < kMaxEnumerations; ++i) {
            v4l2_fmtdesc desc{};
            desc.index = static_cast<std::uint32_t>(i);
            desc.type = type;
            if (v4l2Ioctl(dev, fd->get(), VIDIOC_ENUM_FMT, &desc) != 0)
                break;
            if (desc.pixelformat == V4L2_PIX_FMT_H264) {
                DT_LOG(V4l2, Debug, "%s is a V4L2 M2M H.264 decoder", path.c_str());
                return path;
            }
        }
    }
    return unexpected(Errc::NoDevice, "No V4L2 M2M device decodes H.264");
}

} // namespace depthtouch::drivers
