#pragma once
/// \file
/// \brief `v4l2:DEVICE` frame sources (the grammar: app/cli/source_providers.h): one
/// hal::DepthCamera shared by the color and the depth source of a spec. The camera backend is
/// handed in (CameraOpener): dt_media is written against the HAL, the executable picks the driver.
///
/// Thread-safety: CameraSourceFactory may be called from any thread; the two sources of one camera
/// must be used from one thread, as hal::DepthCamera is.

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>

#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/depth_camera.h"
#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/source_spec.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::media {

/// \brief A parsed `v4l2:` target (grammar in app/cli/source_providers.h).
struct CameraSpec {
    std::string device;         ///< Depth node, e.g. "/dev/video0".
    std::string backendOptions; ///< Options passed on to the backend, e.g. "color=/dev/video2".
    int width = 0;              ///< Pixels; 0 = SourceOptions::videoSize or the camera's choice.
    int height = 0;             ///< Pixels.
    double fps = 0.0;           ///< Frames/s asked with `fps=`; 0 = SourceOptions::fps if offered.
    double preferredFps = 30.0; ///< SourceOptions::fps: used when the camera offers it.
    bool depth = false;         ///< The depth stream, else color.
};

/// \brief Parses \a target (after `v4l2:`). \return the spec. Errors: InvalidArgument (empty
/// device, bad size/fps/stream, demuxer or pixel-format options).
Result<CameraSpec> parseCameraSpec(std::string_view target, const SourceOptions &options);

class CameraShare;

/// \brief Puts \a camera (Unconfigured) to work for sources: picks the mode (size and rate of
/// \a spec, else the camera's first; Z16 depth preferred, with the color stream when the mode
/// has one) and configures it. Streaming starts at the first frame asked.
/// \return the share. Errors: NotSupported (no mode of that size and rate), the camera's errors.
Result<std::shared_ptr<CameraShare>> shareCamera(std::unique_ptr<hal::DepthCamera> camera,
                                                 const CameraSpec &spec);

/// \brief A source of the color or the depth stream of \a share.
/// \return the source. Errors: NotSupported (color asked of a camera without a color stream).
Result<std::unique_ptr<FrameSource>> openCameraSource(std::shared_ptr<CameraShare> share,
                                                      bool depth);

/// \brief Opens the depth camera backend for \a config (BackendConfig::device: the depth node;
/// options: what the spec passes on, e.g. `color=`), not configured yet. The executable hands in
/// the `v4l2` backend. Errors: the backend's (NoDevice: no such node; NotSupported: not a depth
/// camera).
using CameraOpener =
    std::function<Result<std::unique_ptr<hal::DepthCamera>>(const hal::BackendConfig &config)>;

/// \brief Opens `v4l2:` sources; sources of one spec (without `stream=`) share one camera while
/// any of them lives. Thread-safe.
class CameraSourceFactory {
public:
    /// \a openCamera: see CameraOpener.
    explicit CameraSourceFactory(CameraOpener openCamera) : openCamera_(std::move(openCamera)) {}

    /// \brief Opens the source of \a target (after `v4l2:`) on the camera that \a openCamera gives.
    /// \return the source. Errors: those of parseCameraSpec(), shareCamera(), openCameraSource()
    /// and the backend (NoDevice: no such node; NotSupported: not a depth camera).
    Result<std::unique_ptr<FrameSource>> open(std::string_view target,
                                              const SourceOptions &options);

private:
    const CameraOpener openCamera_;
    std::mutex mutex_;
    SharedCache<CameraShare> cameras_;
};

} // namespace depthtouch::media
