#include <linux/videodev2.h>
#include <poll.h>
#include <sys/mman.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>
#include <optional>
#include <utility>

#include "depthtouch/platform/log.h"
#include "v4l2_camera_impl.h"

DT_LOG_CATEGORY(V4l2)

// V4l2DepthCamera's streaming: mmap buffers, dequeue and requeue, pairing depth with color by
// time, and copying or converting a pair into pool frames.

namespace depthtouch::drivers {

namespace {

constexpr std::uint32_t kMinBuffers = 2;

std::uint16_t loadLe16(const std::uint8_t *p) noexcept
{
    return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}

} // namespace

Unexpected V4l2DepthCamera::Impl::fail(const Node &n, int err, const char *what) noexcept
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

} // namespace depthtouch::drivers
