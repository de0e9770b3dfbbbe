#pragma once
/// \file
/// \brief The inside of V4l2DepthCamera, private to drivers/v4l2: the node and buffer records,
/// the Impl that holds the camera's state, and the helpers its files share. The Impl's members
/// live in three files: v4l2_camera_modes.cpp (settings, modes, formats, configuration),
/// v4l2_camera_stream.cpp (buffers, dequeue, pairing, conversion into pool frames) and
/// v4l2_depth_camera.cpp (the hal::DepthCamera calls).
/// Thread-safety: thread-bound, as V4l2DepthCamera. Not real-time safe.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "color_converter.h"
#include "depthtouch/drivers/common/frame_pool.h"
#include "depthtouch/drivers/v4l2/v4l2_depth_camera.h"
#include "depthtouch/drivers/v4l2/v4l2_probe.h"

namespace depthtouch::drivers {

namespace v4l2 {

/// \return whether frame rates \a a and \a b are the same (within 0.1 %).
bool sameFps(double a, double b) noexcept;

} // namespace v4l2

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

/// \brief The state of one V4l2DepthCamera: its device, nodes, modes, pools and counters.
struct V4l2DepthCamera::Impl {
    Impl(std::unique_ptr<V4l2Device> d, platform::Clock &c, V4l2CameraSettings s)
        : dev(std::move(d)), clock(c), settings(std::move(s))
    {
    }

    /// Turns a failed ioctl into an error; ENODEV and friends mark the camera unplugged.
    Unexpected fail(const Node &n, int err, const char *what) noexcept;

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

} // namespace depthtouch::drivers
