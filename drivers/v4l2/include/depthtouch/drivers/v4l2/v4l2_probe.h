#pragma once
/// \file
/// \brief What a V4L2 node offers (VIDIOC_QUERYCAP, ENUM_FMT, ENUM_FRAMESIZES,
/// ENUM_FRAMEINTERVALS) and the probes built on it: find the depth camera node, find an M2M H.264
/// decoder. Every function works on a V4l2Device, so tests run them against a fake kernel.
///
/// Thread-safety: reentrant. Not real-time safe (allocates, performs ioctls).

#include <cstdint>
#include <string>
#include <vector>

#include "depthtouch/drivers/v4l2/v4l2_device.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers {

/// One frame size of a format, with its frame rates.
struct V4l2FrameSize {
    int width = 0;           ///< Pixels.
    int height = 0;          ///< Pixels.
    std::vector<double> fps; ///< Frames per second, as VIDIOC_ENUM_FRAMEINTERVALS lists them.
};

/// One pixel format of the capture queue with its sizes.
struct V4l2FormatDesc {
    std::uint32_t fourcc = 0; ///< V4L2_PIX_FMT_*.
    std::vector<V4l2FrameSize> sizes;
};

/// What one node is and offers.
struct V4l2NodeInfo {
    std::string path;
    std::string card; ///< v4l2_capability::card, e.g. "Intel(R) RealSense(TM) Depth Ca".
    std::uint32_t deviceCaps = 0;        ///< device_caps (capabilities when the driver has none).
    std::vector<V4l2FormatDesc> capture; ///< Single-planar VIDEO_CAPTURE formats (empty if none).

    /// \return the capture format \a fourcc, or nullptr.
    [[nodiscard]] const V4l2FormatDesc *find(std::uint32_t fourcc) const noexcept;
};

/// \brief The depth formats in order of preference: Z16, Y16, GREY.
inline constexpr std::uint32_t kV4l2DepthFourccs[] = {
    0x2036315a, // V4L2_PIX_FMT_Z16  'Z16 '
    0x20363159, // V4L2_PIX_FMT_Y16  'Y16 '
    0x59455247, // V4L2_PIX_FMT_GREY 'GREY'
};

/// \brief Queries node \a path: capabilities and, when it can capture single-planar video, its
/// formats, sizes and rates (stepwise and continuous ranges are sampled: their limits and the
/// usual sizes 320×240, 640×480, 1280×720 and rates 15, 30, 60 fps inside them).
/// \return the node. Errors: NoDevice (no such node, unplugged), PermissionDenied, Io.
Result<V4l2NodeInfo> queryV4l2Node(V4l2Device &dev, const std::string &path);

/// \return the most preferred depth format of \a node's capture queue (kV4l2DepthFourccs order),
/// 0 when it has none or cannot capture video.
std::uint32_t bestDepthFourcc(const V4l2NodeInfo &node) noexcept;

/// \brief Autoprobe of the depth camera: the node with VIDEO_CAPTURE and the most preferred depth
/// format (Z16 before Y16 before GREY; lower /dev/videoN first on a tie).
/// \return its path. Errors: NoDevice (no such node).
Result<std::string> findDepthCameraNode(V4l2Device &dev);

/// \brief Finds a stateful V4L2 memory-to-memory H.264 decoder: a node whose capabilities include
/// V4L2_CAP_VIDEO_M2M or V4L2_CAP_VIDEO_M2M_MPLANE and whose OUTPUT queue (the bitstream side;
/// OUTPUT_MPLANE for multi-planar devices) lists V4L2_PIX_FMT_H264. An encoder (H.264 on its
/// CAPTURE queue) or a camera does not qualify.
/// \return the node's path. Errors: NoDevice (none found).
Result<std::string> findM2mH264Decoder(V4l2Device &dev);

} // namespace depthtouch::drivers
