#pragma once
/// \file
/// \brief FakeV4l2Kernel: the kernel side of V4L2 (drivers::V4l2Device) simulated in memory, so the
/// V4L2 backends are tested without /dev/video*.
///
/// Semantics follow the V4L2 API for single-planar capture with MMAP streaming: QUERYCAP,
/// ENUM_FMT (CAPTURE, and OUTPUT/OUTPUT_MPLANE of M2M nodes), G/S/TRY_FMT (S_FMT adjusts to a
/// supported format and size, EBUSY while buffers exist), ENUM_FRAMESIZES/INTERVALS (discrete),
/// G/S_PARM, REQBUFS (MMAP only; the owning descriptor; count 0 frees, EBUSY while mapped or
/// streaming), QUERYBUF, mmap/munmap, QBUF/DQBUF (every descriptor is non-blocking: DQBUF with
/// nothing done is EAGAIN), STREAMON/OFF (sequence restarts at 0), poll. Frames are exposed on the
/// injected clock at STREAMON + phase + k / fps; frame k fills the oldest queued buffer with the
/// known pattern (depthMm(), greyValue(), lumaValue(); MJPEG is a real JPEG of the YUYV pattern
/// made by libavcodec when the tests have FFmpeg), timestamp = exposure time
/// (TIMESTAMP_MONOTONIC), sequence = k; with no buffer queued the frame is lost (sequence gap).
/// poll() sleeps on the clock until the next exposure or the timeout.
///
/// Faults: unplug() (open → ENOENT, every call on an earlier descriptor → ENODEV, poll → POLLERR |
/// POLLHUP; replug() makes the nodes openable again, old descriptors stay dead), failIoctl()
/// (EINTR, EAGAIN, EIO... on the next calls of one request), failPoll(), damageFrames()
/// (V4L2_BUF_FLAG_ERROR), shortenFrames() (bytesused half the image), garbleFrames() (payload is
/// noise: an MJPEG that does not decode), stall() (no more exposures: timeouts).
///
/// Thread-safety: thread-bound (one test thread).

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "depthtouch/drivers/v4l2/v4l2_device.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers::fake {

/// One capture format of a fake node: its discrete sizes, each at every rate.
struct FakeFormat {
    std::uint32_t fourcc = 0;
    std::vector<std::pair<int, int>> sizes;
    std::vector<double> fps;
};

/// What a fake node is.
struct FakeNodeSpec {
    std::string path;
    std::string card = "Fake V4L2 camera";
    std::uint32_t deviceCaps = 0;      ///< V4L2_CAP_* of the node.
    std::vector<FakeFormat> capture;   ///< VIDEO_CAPTURE formats.
    std::vector<std::uint32_t> output; ///< OUTPUT (OUTPUT_MPLANE) formats of an M2M node.
    platform::Duration phase{};        ///< Exposure offset after STREAMON.
    std::uint32_t maxBuffers = 8;      ///< REQBUFS gives at most this many.
    std::uint32_t linePadding = 0;     ///< Extra bytes per row (bytesperline > width × bpp).
    bool sfmtKeepsFirstSize = false;   ///< A driver whose S_FMT ignores the requested size.
};

/// \return a depth camera node offering \a fourccs at \a sizes and \a fps.
FakeNodeSpec fakeCameraNode(std::string path, std::vector<std::uint32_t> fourccs,
                            std::vector<std::pair<int, int>> sizes = {{64, 48}, {32, 24}},
                            std::vector<double> fps = {30.0, 15.0});
/// \return a stateful M2M decoder node taking \a bitstreams on its OUTPUT queue.
FakeNodeSpec fakeM2mNode(std::string path, std::vector<std::uint32_t> bitstreams, bool mplane);

/// \return whether this test build can make MJPEG frames (libavcodec's mjpeg encoder).
bool fakeJpegAvailable() noexcept;
/// \return a JPEG of the packed YUYV image \a yuyv (\a width × \a height, rows of 2·width bytes),
/// empty when unavailable.
std::vector<std::uint8_t> encodeFakeJpeg(const std::uint8_t *yuyv, int width, int height);

class FakeV4l2Kernel final : public V4l2Device {
public:
    explicit FakeV4l2Kernel(platform::Clock &clock);
    ~FakeV4l2Kernel() override;

    void addNode(FakeNodeSpec spec);

    /// \name The pattern of frame \a seq at pixel (x, y)
    ///@{
    /// Millimetres (Z16, Y16): 400..3399, 0 (no measurement) where x % 16 == 15 and y % 16 == 15.
    static std::uint16_t depthMm(int x, int y, std::uint32_t seq) noexcept;
    /// GREY nearness.
    static std::uint8_t greyValue(int x, int y, std::uint32_t seq) noexcept;
    /// YUYV luma (16..215, flat over 8-pixel columns; chroma is neutral 128).
    static std::uint8_t lumaValue(int x, int y, std::uint32_t seq) noexcept;
    ///@}

    /// \name Fault injection
    ///@{
    void unplug() noexcept;
    void replug() noexcept;
    /// The next \a count ioctls with \a request fail with \a err, without effect.
    void failIoctl(unsigned long request, int err, int count = 1);
    /// The next \a count poll() calls fail with \a err (EINTR).
    void failPoll(int err, int count = 1) noexcept;
    void damageFrames(const std::string &path, int count);
    void shortenFrames(const std::string &path, int count);
    void garbleFrames(const std::string &path, int count);
    void stall(const std::string &path, bool stalled);
    ///@}

    /// \name Observation
    ///@{
    [[nodiscard]] int openDescriptors() const noexcept { return static_cast<int>(fds_.size()); }
    [[nodiscard]] int mappings() const noexcept { return static_cast<int>(maps_.size()); }
    [[nodiscard]] int ioctlCount(unsigned long request) const;
    [[nodiscard]] bool streaming(const std::string &path) const;
    [[nodiscard]] std::uint32_t currentFourcc(const std::string &path) const;
    /// Buffer indices in the order QBUF and DQBUF saw them since the last STREAMON.
    [[nodiscard]] std::vector<std::uint32_t> queuedOrder(const std::string &path) const;
    [[nodiscard]] std::vector<std::uint32_t> dequeuedOrder(const std::string &path) const;
    /// Frames exposed with no queued buffer since the last STREAMON.
    [[nodiscard]] std::uint64_t framesLost(const std::string &path) const;
    ///@}

    [[nodiscard]] std::vector<std::string> listNodes() override;
    int open(const char *path, int flags) noexcept override;
    int close(int fd) noexcept override;
    int ioctl(int fd, unsigned long request, void *arg) noexcept override;
    void *mmap(std::size_t length, int prot, int flags, int fd,
               std::uint32_t offset) noexcept override;
    int munmap(void *addr, std::size_t length) noexcept override;
    int poll(pollfd *fds, std::size_t count, platform::Duration timeout) noexcept override;

    struct Node;
    struct Buffer;

private:
    struct Descriptor {
        std::size_t node = 0;
        std::uint64_t generation = 0;
    };
    struct Mapping {
        void *addr = nullptr;
        std::size_t length = 0;
        std::shared_ptr<Buffer> buffer;
    };

    Node *nodeOf(const std::string &path) const;
    /// \return the node of \a fd, nullptr with errno set (EBADF, ENODEV) otherwise.
    Node *live(int fd) const noexcept;
    int dispatch(int fd, Node &n, unsigned long request, void *arg);
    void produce(Node &n);
    void fill(Node &n, Buffer &b, std::uint32_t seq, platform::TimePoint t);
    void releaseBuffers(Node &n);

    platform::Clock &clock_;
    std::vector<std::unique_ptr<Node>> nodes_;
    std::map<int, Descriptor> fds_;
    std::vector<Mapping> maps_;
    int nextFd_ = 100;
    std::map<unsigned long, std::deque<int>> ioctlFaults_;
    std::map<unsigned long, int> ioctlCounts_;
    int pollFaultErr_ = 0;
    int pollFaults_ = 0;
};

} // namespace depthtouch::drivers::fake
