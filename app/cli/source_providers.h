#pragma once
/// \file
/// \brief The `v4l2:` and `synthetic:` frame sources of the `depthtouch` executable: the
/// media::SourceProviders that media::openFrameSource() needs for those specs (dt_media cannot
/// open them itself: a camera needs a driver, a scene needs a GL context).
///
/// Which stream a source delivers: SourceOptions::streamTitle "depth" gives the depth stream,
/// anything else the color stream (`depthtouch encode` sets the title to "color" or "depth"),
/// unless the spec says `stream=color|depth`. Options go after the name, comma-separated
/// `key=value` (commas need no quoting in a shell):
///
/// `synthetic:NAME[,size=WxH][,fps=F][,frames=N][,stream=color|depth]`: a built-in CG scene
/// (synthetic::listScenes(): head, spheres, cut) rendered with OpenGL ES 3 on a headless EGL
/// display of its own. Defaults: 720×486 (or SourceOptions::videoSize), SourceOptions::fps (30),
/// 4 s of frames (round(4·fps): 120 at 30 fps); `frames=0` or SourceOptions::loop: endless.
/// The color stream is Rgb24; the depth stream is nearness (nativeFormat Gray8; next(Gray16) gives
/// the 16-bit nearness the scene computes), inverse-Z mapped (docs/architecture.md §3) between the
/// scene's near and far planes, which the source's tags carry (depth_near, depth_far, depth_mapping
/// inverse_z) so the encoder writes them to the file. Frame i shows time i / fps and has PTS
/// i / fps. The color and depth sources of one scene, size and rate opened through the same
/// SourceProviders share one renderer: each frame is drawn once for both streams.
///
/// `v4l2:DEVICE[,color=/dev/videoM][,size=WxH][,fps=F][,stream=color|depth][,OPTION=V...]`: the
/// `v4l2` depth-camera backend (drivers/v4l2) on depth node DEVICE; `color=` names its color node
/// (needed for the color stream); other options go to the backend (pool, buffers, hfov). Mode:
/// the first the camera offers with the size (or SourceOptions::videoSize) and rate asked, or
/// else its first mode; the rate SourceOptions::fps is used only when the camera offers it. Depth
/// is Z16 millimetres (nativeFormat Gray16: metric, encode converts it with --depth-scale 0.001)
/// or, from an 8-bit GREY node, nearness (Gray8). The color and depth sources of one DEVICE spec
/// opened through the same SourceProviders share the camera (give both the same spec); each
/// capture gives both frames, with the same PTS.
///
/// Errors of opening: InvalidArgument (unknown scene, with the list of scenes; bad option; unknown
/// key), NotSupported (no OpenGL ES display; a camera without a color node asked for color),
/// NoDevice (no such camera), and the errors of the backend.
///
/// Thread-safety: the factories may be called from any thread. A synthetic source may be used
/// from any one thread (it renders on its own thread and never touches the caller's GL context).
/// The two sources of one camera must be used from one thread, as hal::DepthCamera is.

#include "depthtouch/media/frame_source.h"

namespace depthtouch::cli {

/// \brief The `v4l2:` and `synthetic:` factories (empty `synthetic` when the build has no OpenGL
/// ES). The returned object keeps the shared renderers and cameras of the sources it opened; it
/// may be destroyed before them.
media::SourceProviders makeSourceProviders();

} // namespace depthtouch::cli
