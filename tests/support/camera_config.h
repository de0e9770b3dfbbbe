#pragma once
/// \file
/// \brief configOf(): the hal::CameraConfig that runs one of a depth camera's modes (test
/// support). Header-only.

#include "depthtouch/hal/depth_camera.h"

namespace depthtouch::testing {

/// \return the configuration of camera mode \a m: its size, rate and formats, the color stream on
/// when the mode has one; the other fields keep their defaults.
inline hal::CameraConfig configOf(const hal::CameraMode &m)
{
    hal::CameraConfig cfg;
    cfg.width = m.width;
    cfg.height = m.height;
    cfg.fps = m.fps;
    cfg.depthFormat = m.depthFormat;
    cfg.color = m.colorFormat != hal::PixelFormat::Unknown;
    cfg.colorFormat = m.colorFormat;
    return cfg;
}

} // namespace depthtouch::testing
