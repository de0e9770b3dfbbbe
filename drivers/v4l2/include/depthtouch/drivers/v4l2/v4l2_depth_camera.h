#pragma once
/// \file
/// \brief V4l2DepthCamera: hal::DepthCamera on V4L2 nodes with streaming I/O on mmap buffers.
/// Backend name `v4l2`.
///
/// Nodes: a depth node (single-planar VIDEO_CAPTURE offering Z16, Y16 or GREY) and an optional
/// color node (YUYV or MJPEG), as RealSense-style cameras expose depth and color as separate
/// /dev/video nodes. Options (hal::OptionList): `device=/dev/videoN` depth node (or
/// BackendConfig::device; autoprobed when neither is given: the node with the most preferred depth
/// format), `color=/dev/videoM` color node (none by default), `pool=N` frames lent per stream
/// (1..32, default 4), `buffers=N` mmap buffers per node (2..32, default 4), `hfov=DEG`
/// horizontal field of view for intrinsics() (1..179, default 87, the RealSense D4xx depth
/// imager).
///
/// Formats: the depth node's format is chosen per mode in the order Z16, Y16, GREY. Z16 and Y16
/// are read as 16-bit little-endian millimetres and delivered as hal Z16, or as Gray16 nearness
/// through CameraConfig near/far (docs/architecture.md §3: v = 65535·(1/Z − 1/far)/(1/near −
/// 1/far), 0 stays 0 = no measurement); GREY is 8-bit nearness delivered as Gray16 (v·257). Color:
/// YUYV is delivered as Yuyv or converted to Rgb24 with libswscale; MJPEG is decoded to Rgb24 with
/// libavcodec. Both conversions need the FFmpeg feature: without it, only Yuyv is offered and an
/// MJPEG-only color node is refused with a clear error. Modes are the depth node's sizes and rates;
/// a mode carries a color format when the color node offers the same size and rate.
///
/// Streaming: start() applies the format (VIDIOC_S_FMT, S_PARM), requests and maps the buffers
/// (REQBUFS with V4L2_MEMORY_MMAP, QUERYBUF, mmap), queues them and starts the streams. capture()
/// polls the nodes until the deadline, dequeues the newest good depth buffer (older ones are
/// dropped, buffers flagged V4L2_BUF_FLAG_ERROR or shorter than the format are counted damaged
/// and skipped), pairs it with the color buffer whose timestamp is within half a frame period,
/// copies or converts both into pool frames and requeues the buffers at once, so a held Capture
/// never starves the driver. Time: Frame::time is the depth buffer's timestamp (CLOCK_MONOTONIC,
/// the SteadyClock epoch; the dequeue time when the driver gives none), on both frames of a
/// capture; Frame::pts = time − start(); Frame::sequence is the depth buffer's sequence (a gap
/// means frames the driver dropped). EINTR is retried; ENODEV (unplug) makes capture() and
/// start() return NoDevice; stop() still works and a later start() reopens the nodes.
///
/// A configure() refused by the driver after the camera was Configured (S_FMT answering another
/// format) leaves it Unconfigured, so no pool is left that does not match the nodes.
///
/// Thread-safety: thread-bound, as hal::DepthCamera. Not real-time safe.

#include <cstdint>
#include <memory>
#include <string>

#include "depthtouch/drivers/v4l2/v4l2_device.h"
#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/depth_camera_base.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {

/// \brief Settings of V4l2DepthCamera (from the backend options).
struct V4l2CameraSettings {
    std::string depthNode; ///< Empty: autoprobe.
    std::string colorNode; ///< Empty: no color stream.
    int poolFrames = 4;
    int buffers = 4;
    double hfovDegrees = 87.0;

    /// \return the settings of \a cfg (options and device). Errors: InvalidArgument (unknown key,
    /// value out of range, `device` option and BackendConfig::device disagree).
    static Result<V4l2CameraSettings> parse(const hal::BackendConfig &cfg);
};

/// \brief Counters of one streaming session (reset by start()).
struct V4l2CameraStats {
    std::uint64_t captures = 0;       ///< Captures lent.
    std::uint64_t framesDamaged = 0;  ///< Buffers flagged as errors, short or undecodable.
    std::uint64_t framesDropped = 0;  ///< Good buffers skipped (late consumer, every frame lent).
    std::uint64_t framesUnpaired = 0; ///< Depth buffers without a color partner.
};

class V4l2DepthCamera final : public hal::DepthCameraBase {
public:
    /// Backend factory: settings from cfg, kernel side from makeV4l2Device(), time from cfg.clock.
    /// Errors: InvalidArgument (options), NoDevice (no depth node), NotSupported (the node offers
    /// no depth format, or the color node no color format).
    static Result<std::unique_ptr<hal::DepthCamera>> create(const hal::BackendConfig &cfg);

    /// \brief Opens the camera on the kernel side \a device (tests pass a fake kernel).
    /// \return the camera (Unconfigured). Errors: as create().
    static Result<std::unique_ptr<V4l2DepthCamera>> open(std::unique_ptr<V4l2Device> device,
                                                         platform::Clock &clock,
                                                         const V4l2CameraSettings &settings);

    ~V4l2DepthCamera() override;

    /// \return the counters since the last start().
    [[nodiscard]] V4l2CameraStats stats() const noexcept;
    /// \return the V4L2 pixel format of the depth node (0 before configure()).
    [[nodiscard]] std::uint32_t depthFourcc() const noexcept;
    /// \return the V4L2 pixel format of the color node (0 without color).
    [[nodiscard]] std::uint32_t colorFourcc() const noexcept;
    /// \return the kernel side (tests reach their fake through it).
    [[nodiscard]] V4l2Device &device() noexcept;

    struct Impl;

protected:
    // hal::DepthCameraBase's hooks (the state checks are the base's).
    [[nodiscard]] Result<void> configureDevice(const hal::CameraConfig &cfg) override;
    [[nodiscard]] hal::CameraIntrinsics intrinsicsDevice() const noexcept override;
    [[nodiscard]] Result<void> startDevice() override;
    [[nodiscard]] Result<hal::Capture> captureDevice(hal::Deadline until) override;
    void stopDevice() noexcept override;

private:
    explicit V4l2DepthCamera(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

} // namespace depthtouch::drivers
