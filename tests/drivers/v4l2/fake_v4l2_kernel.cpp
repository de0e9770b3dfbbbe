#include "fake_v4l2_kernel.h"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/mman.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

namespace depthtouch::drivers::fake {

namespace {

constexpr std::uint32_t kOffsetStride = 0x100000; ///< m.offset of buffer i is i × this.

std::uint32_t bytesPerPixel(std::uint32_t fourcc) noexcept
{
    switch (fourcc) {
    case V4L2_PIX_FMT_GREY:
        return 1;
    case V4L2_PIX_FMT_MJPEG:
        return 0;
    default:
        return 2; // Z16, Y16, YUYV
    }
}

void copyName(std::uint8_t *dst, std::size_t size, const std::string &src) noexcept
{
    std::memset(dst, 0, size);
    std::memcpy(dst, src.data(), std::min(size - 1, src.size()));
}

} // namespace

struct FakeV4l2Kernel::Buffer {
    std::vector<std::uint8_t> mem;
    bool queued = false; ///< In the incoming or done queue.
    std::uint32_t bytesUsed = 0;
    std::uint32_t flags = 0;
    std::uint32_t sequence = 0;
    platform::TimePoint time{};
};

struct FakeV4l2Kernel::Node {
    FakeNodeSpec spec;
    bool present = true;
    std::uint64_t generation = 0; ///< Bumped by unplug(): older descriptors are dead.
    std::uint32_t fourcc = 0;
    int width = 0;
    int height = 0;
    double fps = 0.0;
    std::vector<std::shared_ptr<Buffer>> buffers;
    int owner = -1; ///< Descriptor that holds the buffers.
    bool streaming = false;
    bool stalled = false;
    platform::TimePoint streamOn{};
    std::uint64_t nextFrame = 0;
    std::uint64_t lost = 0;
    std::deque<std::uint32_t> incoming;
    std::deque<std::uint32_t> done;
    std::vector<std::uint32_t> queuedOrder;
    std::vector<std::uint32_t> dequeuedOrder;
    int damage = 0;
    int shorten = 0;
    int garble = 0;

    [[nodiscard]] const FakeFormat *format(std::uint32_t f) const noexcept
    {
        for (const FakeFormat &x : spec.capture)
            if (x.fourcc == f)
                return &x;
        return nullptr;
    }
    [[nodiscard]] std::uint32_t bytesPerLine() const noexcept
    {
        const std::uint32_t bpp = bytesPerPixel(fourcc);
        return bpp == 0 ? 0 : static_cast<std::uint32_t>(width) * bpp + spec.linePadding;
    }
    [[nodiscard]] std::uint32_t sizeImage() const noexcept
    {
        return fourcc == V4L2_PIX_FMT_MJPEG ? static_cast<std::uint32_t>(width * height * 2)
                                            : bytesPerLine() * static_cast<std::uint32_t>(height);
    }
};

FakeNodeSpec fakeCameraNode(std::string path, std::vector<std::uint32_t> fourccs,
                            std::vector<std::pair<int, int>> sizes, std::vector<double> fps)
{
    FakeNodeSpec s;
    s.path = std::move(path);
    s.deviceCaps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING;
    for (const std::uint32_t f : fourccs)
        s.capture.push_back({f, sizes, fps});
    return s;
}

FakeNodeSpec fakeM2mNode(std::string path, std::vector<std::uint32_t> bitstreams, bool mplane)
{
    FakeNodeSpec s;
    s.path = std::move(path);
    s.card = "Fake M2M codec";
    s.deviceCaps = (mplane ? V4L2_CAP_VIDEO_M2M_MPLANE : V4L2_CAP_VIDEO_M2M) | V4L2_CAP_STREAMING;
    s.output = std::move(bitstreams);
    return s;
}

FakeV4l2Kernel::FakeV4l2Kernel(platform::Clock &clock) : clock_(clock) {}
FakeV4l2Kernel::~FakeV4l2Kernel() = default;

void FakeV4l2Kernel::addNode(FakeNodeSpec spec)
{
    auto n = std::make_unique<Node>();
    n->spec = std::move(spec);
    if (!n->spec.capture.empty()) {
        const FakeFormat &f = n->spec.capture.front();
        n->fourcc = f.fourcc;
        n->width = f.sizes.empty() ? 0 : f.sizes.front().first;
        n->height = f.sizes.empty() ? 0 : f.sizes.front().second;
        n->fps = f.fps.empty() ? 30.0 : f.fps.front();
    }
    nodes_.push_back(std::move(n));
}

std::uint16_t FakeV4l2Kernel::depthMm(int x, int y, std::uint32_t seq) noexcept
{
    if (x % 16 == 15 && y % 16 == 15)
        return 0;
    return static_cast<std::uint16_t>(400 +
                                      (x * 7 + y * 3 + static_cast<int>(seq % 1000) * 11) % 3000);
}

std::uint8_t FakeV4l2Kernel::greyValue(int x, int y, std::uint32_t seq) noexcept
{
    return static_cast<std::uint8_t>((x + 2 * y + static_cast<int>(seq % 256)) & 0xff);
}

std::uint8_t FakeV4l2Kernel::lumaValue(int x, int /*y*/, std::uint32_t seq) noexcept
{
    return static_cast<std::uint8_t>(16 + ((x / 8) * 16 + static_cast<int>(seq % 20) * 10) % 200);
}

void FakeV4l2Kernel::unplug() noexcept
{
    for (auto &n : nodes_) {
        n->present = false;
        ++n->generation;
        n->streaming = false;
    }
}

void FakeV4l2Kernel::replug() noexcept
{
    for (auto &n : nodes_)
        n->present = true;
}

void FakeV4l2Kernel::failIoctl(unsigned long request, int err, int count)
{
    for (int i = 0; i < count; ++i)
        ioctlFaults_[request].push_back(err);
}

void FakeV4l2Kernel::failPoll(int err, int count) noexcept
{
    pollFaultErr_ = err;
    pollFaults_ = count;
}

void FakeV4l2Kernel::damageFrames(const std::string &path, int count)
{
    nodeOf(path)->damage += count;
}
void FakeV4l2Kernel::shortenFrames(const std::string &path, int count)
{
    nodeOf(path)->shorten += count;
}
void FakeV4l2Kernel::garbleFrames(const std::string &path, int count)
{
    nodeOf(path)->garble += count;
}
void FakeV4l2Kernel::stall(const std::string &path, bool stalled)
{
    Node &n = *nodeOf(path);
    if (n.stalled && !stalled) {
        // Resume at the next period after now, as a sensor that was covered.
        const double period = 1.0 / n.fps;
        const double since = platform::toSeconds(clock_.now() - n.streamOn - n.spec.phase);
        n.nextFrame = std::max<std::uint64_t>(
            n.nextFrame, static_cast<std::uint64_t>(std::ceil(std::max(0.0, since) / period)));
    }
    n.stalled = stalled;
}

int FakeV4l2Kernel::ioctlCount(unsigned long request) const
{
    const auto it = ioctlCounts_.find(request);
    return it == ioctlCounts_.end() ? 0 : it->second;
}
bool FakeV4l2Kernel::streaming(const std::string &path) const
{
    return nodeOf(path)->streaming;
}
std::uint32_t FakeV4l2Kernel::currentFourcc(const std::string &path) const
{
    return nodeOf(path)->fourcc;
}
std::vector<std::uint32_t> FakeV4l2Kernel::queuedOrder(const std::string &path) const
{
    return nodeOf(path)->queuedOrder;
}
std::vector<std::uint32_t> FakeV4l2Kernel::dequeuedOrder(const std::string &path) const
{
    return nodeOf(path)->dequeuedOrder;
}
std::uint64_t FakeV4l2Kernel::framesLost(const std::string &path) const
{
    return nodeOf(path)->lost;
}

FakeV4l2Kernel::Node *FakeV4l2Kernel::nodeOf(const std::string &path) const
{
    for (const auto &n : nodes_)
        if (n->spec.path == path)
            return n.get();
    return nullptr;
}

FakeV4l2Kernel::Node *FakeV4l2Kernel::live(int fd) const noexcept
{
    const auto it = fds_.find(fd);
    if (it == fds_.end()) {
        errno = EBADF;
        return nullptr;
    }
    Node *n = nodes_[it->second.node].get();
    if (!n->present || n->generation != it->second.generation) {
        errno = ENODEV;
        return nullptr;
    }
    return n;
}

std::vector<std::string> FakeV4l2Kernel::listNodes()
{
    std::vector<std::string> out;
    for (const auto &n : nodes_)
        if (n->present)
            out.push_back(n->spec.path);
    return out;
}

int FakeV4l2Kernel::open(const char *path, int /*flags*/) noexcept
{
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        if (nodes_[i]->spec.path != path)
            continue;
        if (!nodes_[i]->present)
            break;
        const int fd = nextFd_++;
        fds_[fd] = {i, nodes_[i]->generation};
        return fd;
    }
    errno = ENOENT;
    return -1;
}

int FakeV4l2Kernel::close(int fd) noexcept
{
    const auto it = fds_.find(fd);
    if (it == fds_.end()) {
        errno = EBADF;
        return -1;
    }
    Node &n = *nodes_[it->second.node];
    if (n.owner == fd)
        releaseBuffers(n);
    fds_.erase(it);
    return 0;
}

void FakeV4l2Kernel::releaseBuffers(Node &n)
{
    n.streaming = false;
    n.incoming.clear();
    n.done.clear();
    n.buffers.clear(); // mappings keep their memory alive until munmap
    n.owner = -1;
}

int FakeV4l2Kernel::ioctl(int fd, unsigned long request, void *arg) noexcept
{
    ++ioctlCounts_[request];
    auto fault = ioctlFaults_.find(request);
    if (fault != ioctlFaults_.end() && !fault->second.empty()) {
        errno = fault->second.front();
        fault->second.pop_front();
        return -1;
    }
    Node *n = live(fd);
    if (n == nullptr)
        return -1;
    try {
        const int err = dispatch(fd, *n, request, arg);
        if (err != 0) {
            errno = err;
            return -1;
        }
        return 0;
    } catch (...) {
        errno = ENOMEM;
        return -1;
    }
}

int FakeV4l2Kernel::dispatch(int fd, Node &n, unsigned long request, void *arg)
{
    const bool canCapture = (n.spec.deviceCaps & V4L2_CAP_VIDEO_CAPTURE) != 0;
    const bool m2m = (n.spec.deviceCaps & (V4L2_CAP_VIDEO_M2M | V4L2_CAP_VIDEO_M2M_MPLANE)) != 0;
    const bool mplane = (n.spec.deviceCaps & V4L2_CAP_VIDEO_M2M_MPLANE) != 0;

    // Adjusts \a pix to the nearest supported format (S_FMT and TRY_FMT never refuse).
    const auto adjust = [&n](v4l2_pix_format &pix) {
        const FakeFormat *f = n.format(pix.pixelformat);
        if (f == nullptr)
            f = &n.spec.capture.front();
        pix.pixelformat = f->fourcc;
        const auto size = std::find(
            f->sizes.begin(), f->sizes.end(),
            std::pair<int, int>(static_cast<int>(pix.width), static_cast<int>(pix.height)));
        const auto chosen =
            (size == f->sizes.end() || n.spec.sfmtKeepsFirstSize) ? f->sizes.front() : *size;
        pix.width = static_cast<std::uint32_t>(chosen.first);
        pix.height = static_cast<std::uint32_t>(chosen.second);
        pix.field = V4L2_FIELD_NONE;
        const std::uint32_t bpp = bytesPerPixel(pix.pixelformat);
        pix.bytesperline = bpp == 0 ? 0 : pix.width * bpp + n.spec.linePadding;
        pix.sizeimage = bpp == 0 ? pix.width * pix.height * 2 : pix.bytesperline * pix.height;
        pix.colorspace =
            pix.pixelformat == V4L2_PIX_FMT_MJPEG ? V4L2_COLORSPACE_JPEG : V4L2_COLORSPACE_SRGB;
    };

    switch (request) {
    case VIDIOC_QUERYCAP: {
        auto *cap = static_cast<v4l2_capability *>(arg);
        std::memset(cap, 0, sizeof(*cap));
        copyName(cap->driver, sizeof(cap->driver), "fake");
        copyName(cap->card, sizeof(cap->card), n.spec.card);
        copyName(cap->bus_info, sizeof(cap->bus_info), "platform:" + n.spec.path);
        cap->version = 0x060100;
        cap->device_caps = n.spec.deviceCaps;
        cap->capabilities = n.spec.deviceCaps | V4L2_CAP_DEVICE_CAPS;
        return 0;
    }
    case VIDIOC_ENUM_FMT: {
        auto *d = static_cast<v4l2_fmtdesc *>(arg);
        std::uint32_t fourcc = 0;
        if (d->type == V4L2_BUF_TYPE_VIDEO_CAPTURE && canCapture) {
            if (d->index >= n.spec.capture.size())
                return EINVAL;
            fourcc = n.spec.capture[d->index].fourcc;
        } else if (m2m && d->type == (mplane ? V4L2_BUF_TYPE_VIDEO_OUTPUT_MPLANE
                                             : V4L2_BUF_TYPE_VIDEO_OUTPUT)) {
            if (d->index >= n.spec.output.size())
                return EINVAL;
            fourcc = n.spec.output[d->index];
        } else {
            return EINVAL;
        }
        d->pixelformat = fourcc;
        d->flags = fourcc == V4L2_PIX_FMT_MJPEG || fourcc == V4L2_PIX_FMT_H264
                       ? V4L2_FMT_FLAG_COMPRESSED
                       : 0;
        copyName(d->description, sizeof(d->description), "fake format");
        return 0;
    }
    case VIDIOC_G_FMT:
    case VIDIOC_S_FMT:
    case VIDIOC_TRY_FMT: {
        auto *f = static_cast<v4l2_format *>(arg);
        if (f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || !canCapture || n.spec.capture.empty())
            return EINVAL;
        if (request == VIDIOC_G_FMT) {
            v4l2_pix_format pix{};
            pix.pixelformat = n.fourcc;
            pix.width = static_cast<std::uint32_t>(n.width);
            pix.height = static_cast<std::uint32_t>(n.height);
            adjust(pix);
            f->fmt.pix = pix;
            return 0;
        }
        if (request == VIDIOC_S_FMT && (!n.buffers.empty() || n.streaming))
            return EBUSY;
        adjust(f->fmt.pix);
        if (request == VIDIOC_S_FMT) {
            n.fourcc = f->fmt.pix.pixelformat;
            n.width = static_cast<int>(f->fmt.pix.width);
            n.height = static_cast<int>(f->fmt.pix.height);
        }
        return 0;
    }
    case VIDIOC_ENUM_FRAMESIZES: {
        auto *s = static_cast<v4l2_frmsizeenum *>(arg);
        const FakeFormat *f = n.format(s->pixel_format);
        if (f == nullptr || s->index >= f->sizes.size())
            return EINVAL;
        s->type = V4L2_FRMSIZE_TYPE_DISCRETE;
        s->discrete.width = static_cast<std::uint32_t>(f->sizes[s->index].first);
        s->discrete.height = static_cast<std::uint32_t>(f->sizes[s->index].second);
        return 0;
    }
    case VIDIOC_ENUM_FRAMEINTERVALS: {
        auto *iv = static_cast<v4l2_frmivalenum *>(arg);
        const FakeFormat *f = n.format(iv->pixel_format);
        if (f == nullptr || iv->index >= f->fps.size() ||
            std::find(f->sizes.begin(), f->sizes.end(),
                      std::pair<int, int>(static_cast<int>(iv->width),
                                          static_cast<int>(iv->height))) == f->sizes.end())
            return EINVAL;
        iv->type = V4L2_FRMIVAL_TYPE_DISCRETE;
        iv->discrete.numerator = 1000;
        iv->discrete.denominator =
            static_cast<std::uint32_t>(std::lround(f->fps[iv->index] * 1000));
        return 0;
    }
    case VIDIOC_G_PARM:
    case VIDIOC_S_PARM: {
        auto *p = static_cast<v4l2_streamparm *>(arg);
        if (p->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || !canCapture)
            return EINVAL;
        if (request == VIDIOC_S_PARM) {
            if (n.streaming)
                return EBUSY;
            const v4l2_fract tpf = p->parm.capture.timeperframe;
            const FakeFormat *f = n.format(n.fourcc);
            if (tpf.numerator != 0 && tpf.denominator != 0 && f != nullptr && !f->fps.empty()) {
                const double want = static_cast<double>(tpf.denominator) / tpf.numerator;
                double best = f->fps.front();
                for (const double r : f->fps)
                    if (std::fabs(r - want) < std::fabs(best - want))
                        best = r;
                n.fps = best;
            }
        }
        std::memset(&p->parm, 0, sizeof(p->parm));
        p->parm.capture.capability = V4L2_CAP_TIMEPERFRAME;
        p->parm.capture.timeperframe.numerator = 1000;
        p->parm.capture.timeperframe.denominator =
            static_cast<std::uint32_t>(std::lround(n.fps * 1000));
        return 0;
    }
    case VIDIOC_REQBUFS: {
        auto *r = static_cast<v4l2_requestbuffers *>(arg);
        if (r->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || !canCapture || r->memory != V4L2_MEMORY_MMAP)
            return EINVAL;
        if (n.owner != -1 && n.owner != fd)
            return EBUSY;
        if (n.streaming)
            return EBUSY;
        for (const Mapping &m : maps_)
            for (const auto &b : n.buffers)
                if (m.buffer == b)
                    return EBUSY; // this fake is strict: unmap before freeing
        releaseBuffers(n);
        if (r->count == 0)
            return 0;
        const std::uint32_t count = std::min(r->count, n.spec.maxBuffers);
        for (std::uint32_t i = 0; i < count; ++i) {
            auto b = std::make_shared<Buffer>();
            b->mem.assign(n.sizeImage(), 0);
            n.buffers.push_back(std::move(b));
        }
        n.owner = fd;
        r->count = count;
        r->capabilities = V4L2_BUF_CAP_SUPPORTS_MMAP;
        return 0;
    }
    case VIDIOC_QUERYBUF:
    case VIDIOC_QBUF:
    case VIDIOC_DQBUF: {
        auto *b = static_cast<v4l2_buffer *>(arg);
        if (b->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || b->memory != V4L2_MEMORY_MMAP)
            return EINVAL;
        if (n.owner != fd)
            return n.owner == -1 ? EINVAL : EBUSY;
        if (request == VIDIOC_DQBUF) {
            produce(n);
            if (n.done.empty())
                return n.streaming ? EAGAIN : EINVAL;
            const std::uint32_t i = n.done.front();
            n.done.pop_front();
            Buffer &buf = *n.buffers[i];
            buf.queued = false;
            n.dequeuedOrder.push_back(i);
            b->index = i;
            b->bytesused = buf.bytesUsed;
            b->flags = buf.flags | V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_MAPPED;
            b->field = V4L2_FIELD_NONE;
            b->sequence = buf.sequence;
            const auto ns = buf.time.time_since_epoch().count();
            b->timestamp.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
            b->timestamp.tv_usec = static_cast<suseconds_t>((ns % 1'000'000'000) / 1000);
            b->length = static_cast<std::uint32_t>(buf.mem.size());
            b->m.offset = i * kOffsetStride;
            return 0;
        }
        if (b->index >= n.buffers.size())
            return EINVAL;
        Buffer &buf = *n.buffers[b->index];
        if (request == VIDIOC_QUERYBUF) {
            b->length = static_cast<std::uint32_t>(buf.mem.size());
            b->m.offset = b->index * kOffsetStride;
            b->flags = buf.queued ? V4L2_BUF_FLAG_QUEUED : 0;
            return 0;
        }
        if (buf.queued)
            return EINVAL;
        buf.queued = true;
        n.incoming.push_back(b->index);
        n.queuedOrder.push_back(b->index);
        return 0;
    }
    case VIDIOC_STREAMON:
    case VIDIOC_STREAMOFF: {
        const int type = *static_cast<int *>(arg);
        if (type != V4L2_BUF_TYPE_VIDEO_CAPTURE || n.owner != fd)
            return EINVAL;
        if (request == VIDIOC_STREAMOFF) {
            n.streaming = false;
            n.incoming.clear();
            n.done.clear();
            for (auto &buf : n.buffers)
                buf->queued = false;
            return 0;
        }
        if (n.buffers.empty())
            return EINVAL;
        if (!n.streaming) {
            n.streaming = true;
            n.streamOn = clock_.now();
            n.nextFrame = 0;
            n.lost = 0;
            n.queuedOrder.clear();
            n.dequeuedOrder.clear();
            for (const std::uint32_t i : n.incoming)
                n.queuedOrder.push_back(i);
        }
        return 0;
    }
    default:
        return ENOTTY;
    }
}

void FakeV4l2Kernel::produce(Node &n)
{
    if (!n.streaming || n.stalled || n.fps <= 0.0)
        return;
    const platform::TimePoint now = clock_.now();
    const double period = 1.0 / n.fps;
    for (;;) {
        const platform::TimePoint t =
            n.streamOn + n.spec.phase +
            platform::fromSeconds(static_cast<double>(n.nextFrame) * period);
        if (t > now)
            return;
        const auto seq = static_cast<std::uint32_t>(n.nextFrame++);
        if (n.incoming.empty()) {
            ++n.lost;
            continue;
        }
        const std::uint32_t i = n.incoming.front();
        n.incoming.pop_front();
        fill(n, *n.buffers[i], seq, t);
        n.done.push_back(i);
    }
}

void FakeV4l2Kernel::fill(Node &n, Buffer &b, std::uint32_t seq, platform::TimePoint t)
{
    b.sequence = seq;
    b.time = t;
    b.flags = 0;
    const std::size_t bpl = n.bytesPerLine();
    const auto w = static_cast<std::size_t>(n.width);
    const auto h = static_cast<std::size_t>(n.height);
    std::uint8_t *mem = b.mem.data();
    b.bytesUsed = n.sizeImage();
    const auto at = [](std::size_t v) { return static_cast<int>(v); };
    switch (n.fourcc) {
    case V4L2_PIX_FMT_Z16:
    case V4L2_PIX_FMT_Y16:
        for (std::size_t y = 0; y < h; ++y)
            for (std::size_t x = 0; x < w; ++x) {
                const std::uint16_t v = depthMm(at(x), at(y), seq);
                mem[y * bpl + 2 * x] = static_cast<std::uint8_t>(v & 0xff);
                mem[y * bpl + 2 * x + 1] = static_cast<std::uint8_t>(v >> 8);
            }
        break;
    case V4L2_PIX_FMT_GREY:
        for (std::size_t y = 0; y < h; ++y)
            for (std::size_t x = 0; x < w; ++x)
                mem[y * bpl + x] = greyValue(at(x), at(y), seq);
        break;
    case V4L2_PIX_FMT_YUYV:
    case V4L2_PIX_FMT_MJPEG: {
        const std::size_t stride = n.fourcc == V4L2_PIX_FMT_YUYV ? bpl : 2 * w;
        std::vector<std::uint8_t> yuyv(stride * h, 0);
        for (std::size_t y = 0; y < h; ++y)
            for (std::size_t x = 0; x < w; ++x) {
                yuyv[y * stride + 2 * x] = lumaValue(at(x), at(y), seq);
                yuyv[y * stride + 2 * x + 1] = 128;
            }
        if (n.fourcc == V4L2_PIX_FMT_YUYV) {
            std::memcpy(mem, yuyv.data(), yuyv.size());
        } else {
            const std::vector<std::uint8_t> jpeg = encodeFakeJpeg(yuyv.data(), n.width, n.height);
            const std::size_t size = std::min(jpeg.size(), b.mem.size());
            std::memcpy(mem, jpeg.data(), size);
            b.bytesUsed = static_cast<std::uint32_t>(size);
        }
        break;
    }
    default:
        break;
    }
    if (n.garble > 0) {
        --n.garble;
        for (std::size_t i = 0; i < b.bytesUsed; ++i)
            mem[i] = static_cast<std::uint8_t>((i * 37 + seq) & 0xff);
    }
    if (n.damage > 0) {
        --n.damage;
        b.flags |= V4L2_BUF_FLAG_ERROR;
    }
    if (n.shorten > 0) {
        --n.shorten;
        b.bytesUsed /= 2;
    }
}

void *FakeV4l2Kernel::mmap(std::size_t length, int /*prot*/, int flags, int fd,
                           std::uint32_t offset) noexcept
{
    Node *n = live(fd);
    if (n == nullptr)
        return MAP_FAILED;
    const std::uint32_t i = offset / kOffsetStride;
    if ((flags & MAP_SHARED) == 0 || n->owner != fd || offset % kOffsetStride != 0 ||
        i >= n->buffers.size() || length > n->buffers[i]->mem.size() || length == 0) {
        errno = EINVAL;
        return MAP_FAILED;
    }
    try {
        maps_.push_back({n->buffers[i]->mem.data(), length, n->buffers[i]});
    } catch (...) {
        errno = ENOMEM;
        return MAP_FAILED;
    }
    return n->buffers[i]->mem.data();
}

int FakeV4l2Kernel::munmap(void *addr, std::size_t length) noexcept
{
    const auto it = std::find_if(maps_.begin(), maps_.end(), [&](const Mapping &m) {
        return m.addr == addr && m.length == length;
    });
    if (it == maps_.end()) {
        errno = EINVAL;
        return -1;
    }
    maps_.erase(it);
    return 0;
}

int FakeV4l2Kernel::poll(pollfd *fds, std::size_t count, platform::Duration timeout) noexcept
{
    if (pollFaults_ > 0) {
        --pollFaults_;
        errno = pollFaultErr_;
        return -1;
    }
    const bool infinite = timeout < platform::Duration::zero();
    const platform::TimePoint deadline =
        infinite ? platform::TimePoint::max() : clock_.now() + timeout;
    for (;;) {
        int ready = 0;
        platform::TimePoint next = platform::TimePoint::max();
        for (std::size_t k = 0; k < count; ++k) {
            pollfd &p = fds[k];
            p.revents = 0;
            const auto it = fds_.find(p.fd);
            if (it == fds_.end()) {
                p.revents = POLLNVAL;
            } else if (Node *n = live(p.fd); n == nullptr) {
                p.revents = POLLERR | POLLHUP;
            } else {
                produce(*n);
                if (!n->done.empty())
                    p.revents = static_cast<short>(POLLIN | POLLRDNORM);
                else if (!n->streaming)
                    p.revents = POLLERR;
                else if (!n->incoming.empty() && !n->stalled)
                    next = std::min(next, n->streamOn + n->spec.phase +
                                              platform::fromSeconds(
                                                  static_cast<double>(n->nextFrame) / n->fps));
            }
            if (p.revents != 0)
                ++ready;
        }
        if (ready > 0)
            return ready;
        if (timeout == platform::Duration::zero())
            return 0;
        if (next == platform::TimePoint::max() || next > deadline) {
            // Nothing will come before the deadline (or ever, for an infinite wait: return rather
            // than hang the test).
            if (!infinite)
                clock_.sleepUntil(deadline);
            return 0;
        }
        clock_.sleepUntil(next);
    }
}

} // namespace depthtouch::drivers::fake
