#pragma once
/// \file
/// \brief DepthCamera: an RGB-D camera (V4L2 Z16/Y16 in real backends) delivering depth and color
/// images.
///
/// State machine:
/// \verbatim
///   Unconfigured --configure()--> Configured --start()--> Streaming
///                                   ^   |                     |
///                                   |   +--configure()        |
///                                   +---------stop()----------+
/// \endverbatim
/// A call that is not allowed in the current state returns Errc::InvalidState and has no effect. If
/// the camera is unplugged, capture() and start() return Errc::NoDevice; stop() is still allowed.
///
/// Images: depth is Z16 (millimetres along the optical axis, 0 = no measurement) or Gray16 nearness
/// (docs/architecture.md §3 mapping with CameraConfig near/far); color is Rgb24, Yuyv or Mjpeg as
/// the mode says. Ownership: a Capture lends pool frames (FrameRef); destroying it returns them.
/// The camera must outlive every Capture; configure() needs every frame back (Busy otherwise). When
/// the caller holds every pool frame, the camera drops new frames and capture() returns Busy. Time:
/// Frame::time is the capture time on the backend clock; Frame::pts the time since start();
/// Frame::sequence counts frames since start(), so a gap means dropped frames.
/// Thread-safety: thread-bound (the capture thread), except FrameRef release (any thread).
/// Not real-time safe.

#include <cstdint>
#include <string>
#include <vector>

#include "depthtouch/hal/types.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::hal {

/// \brief One mode the camera offers: a size, a rate and the formats of each stream.
struct CameraMode {
    int width = 0;                                  ///< Pixels (depth and color share the size).
    int height = 0;                                 ///< Pixels.
    double fps = 0.0;                               ///< Frames per second.
    PixelFormat depthFormat = PixelFormat::Unknown; ///< Unknown when the mode has no depth stream.
    PixelFormat colorFormat = PixelFormat::Unknown; ///< Unknown when the mode has no color stream.
};

/// \brief What configure() should set up.
struct CameraConfig {
    int width = 0;                              ///< Pixels.
    int height = 0;                             ///< Pixels.
    double fps = 0.0;                           ///< Frames per second.
    bool depth = true;                          ///< Deliver the depth stream.
    bool color = true;                          ///< Deliver the color stream.
    PixelFormat depthFormat = PixelFormat::Z16; ///< Z16 or Gray16 (nearness).
    PixelFormat colorFormat = PixelFormat::Rgb24;
    double nearMetres = 0.3; ///< Gray16 nearness only: distance of the maximum value.
    double farMetres = 3.0;  ///< Gray16 nearness only: distance of value 0.
};

/// \brief Pinhole intrinsics of the depth image (pixels).
struct CameraIntrinsics {
    double fx = 0.0; ///< Focal length along x, pixels.
    double fy = 0.0; ///< Focal length along y, pixels.
    double cx = 0.0; ///< Principal point x, pixels from the left edge.
    double cy = 0.0; ///< Principal point y, pixels from the top edge.
};

/// \brief What a camera can do. Constant for the camera's lifetime.
struct DepthCameraCapabilities {
    std::string name;              ///< Model, e.g. "Intel RealSense D435".
    std::vector<CameraMode> modes; ///< Every supported mode; configure() accepts these only.
    int poolFrames = 0; ///< Frames per stream in the pool: the most Captures held at once.
};

/// \brief The images of one capture instant; RAII: destroying it returns its frames. Move-only.
struct Capture {
    FrameRef depth; ///< Empty when the depth stream is off.
    FrameRef color; ///< Empty when the color stream is off.
};

/// \brief An RGB-D camera.
class DepthCamera {
public:
    enum class State : std::uint8_t { Unconfigured, Configured, Streaming };

    virtual ~DepthCamera() = default;

    /// \return what the camera can do; constant for its whole lifetime.
    [[nodiscard]] virtual const DepthCameraCapabilities &capabilities() const noexcept = 0;

    /// \return the current state.
    [[nodiscard]] virtual State state() const noexcept = 0;

    /// \brief Selects a mode and the streams to deliver; allocates the pools.
    /// \pre Unconfigured or Configured, and no frame lent.
    /// \param[in] cfg Size, rate and formats: must match one of capabilities().modes, with at least
    /// one stream on. \return nothing on success (state Configured). Errors: InvalidState
    /// (Streaming), Busy (a frame is lent), NotSupported (no such mode or format), InvalidArgument
    /// (no stream, bad near/far), NoDevice (unplugged).
    [[nodiscard]] virtual Result<void> configure(const CameraConfig &cfg) = 0;

    /// \return the intrinsics of the configured depth image ({} when Unconfigured).
    [[nodiscard]] virtual CameraIntrinsics intrinsics() const noexcept = 0;

    /// \brief Starts streaming; frame 0 is exposed at the time of the call.
    /// \pre Configured.
    /// \return nothing on success (state Streaming). Errors: InvalidState, NoDevice (unplugged).
    [[nodiscard]] virtual Result<void> start() = 0;

    /// \brief Lends the next frame set, waiting on the backend clock until \a until at most. If the
    /// caller is late, the newest frame is returned and the older ones are dropped (sequence gap).
    /// \pre Streaming.
    /// \param[in] until Absolute deadline; a deadline in the past polls without waiting.
    /// \return the capture. Errors: InvalidState (not Streaming), Timeout (no frame by the
    /// deadline), Busy (every pool frame is lent), NoDevice (unplugged), Io (the frame was
    /// damaged).
    [[nodiscard]] virtual Result<Capture> capture(Deadline until) = 0;

    /// \brief Stops streaming. Lent frames stay valid until returned.
    /// \pre Streaming.
    /// \return nothing on success (state Configured). Errors: InvalidState (not Streaming).
    [[nodiscard]] virtual Result<void> stop() = 0;

protected:
    DepthCamera() = default;
    DT_DISABLE_COPY_AND_MOVE(DepthCamera)
};

/// \return the name of \a s: "Unconfigured", "Configured" or "Streaming" (a static string; "?" for
/// another value), for messages. Thread-safe.
[[nodiscard]] const char *toString(DepthCamera::State s) noexcept;

} // namespace depthtouch::hal
