#pragma once
/// \file
/// \brief The `kms` display backend (GBM/KMS, the set-top-box target): finds a DRM card and a
/// connected connector and chooses its mode (kms_output.h; DisplayConfig::mode "HDMI-A-1",
/// "1920x1080@60" or "HDMI-A-1:1280x720@50").
///
/// \todo #5 Scan-out: GBM surface, EGL on the GBM platform, page flips on vblank
/// (drmModePageFlip + event handling) and restoring the previous CRTC on close. Until then the
/// factory reports NotSupported on a machine that has a DRM card, so autoprobe moves on.
/// Errors: the factory returns NoDevice when there is no DRM card (/dev/dri/card*), or no
/// connected display.
/// Thread-safety: reentrant.

#include <memory>

#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/display.h"

namespace depthtouch::drivers {

class EglGbmDisplay {
public:
    /// Backend factory (see the file comment). cfg.device: a card path to use instead of
    /// discovery (e.g. "/dev/dri/card1").
    static Result<std::unique_ptr<hal::Display>> create(const hal::BackendConfig &cfg);
};

} // namespace depthtouch::drivers
