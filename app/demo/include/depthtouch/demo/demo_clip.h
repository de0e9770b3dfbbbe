#pragma once
/// \file
/// \brief The demo's clip (`depthtouch demo`): a built-in `synthetic:` scene rendered and encoded
/// into a DepthTouch file with its color, depth and material streams (x264 veryfast, depth CRF
/// 12), the rendering progress on stderr. The `synthetic:` frame source comes from the caller's
/// providers (the executable hands in the display it renders on).
/// Thread-safety: call from the main thread: it catches the stop signals while it encodes
/// (platform/stop_signals.h; one StopSignals at a time).

#include <string>

#include "depthtouch/media/frame_source.h"

namespace depthtouch::demo {

/// \brief Renders scene \a scene (`synthetic:` name) at \a size ("WxH", pixels) for \a frames
/// frames and encodes it into \a clip, with the scene's soundtrack (synthetic/soundtrack.h: a click
/// at the start, the head's turning) as its sound. A stop signal during it sets \a interrupted: the
/// clip is then removed (a short clip would be reused by the next demo). \return an error line,
/// empty on success or interruption.
std::string encodeScene(const std::string &scene, const std::string &size, int frames,
                        const std::string &clip, const media::SourceProviders &providers,
                        bool &interrupted);

} // namespace depthtouch::demo
