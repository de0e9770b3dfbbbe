#pragma once
/// \file
/// \brief `depthtouchsink`: DepthTouch's player as a GStreamer sink (issue 62; docs/embedding.md
/// "GStreamer"). Two always sink pads, `color` (I420) and `depth` (GRAY8 / GRAY16_LE nearness),
/// whose decoded frames feed `play`'s own player (feed_player.h): the receiver pairs colour and
/// depth by PTS (the buffers' running times), the stereo renderer draws them on the player's
/// display (the `display` property: x11, kms, offscreen, ...; empty autoprobes as `play`), and the
/// 1 kHz haptic task touches the same depth frames; its control socket (`control`) answers as
/// `play --control`'s does.
///
/// Time: each buffer's running time (its segment's) is its PTS; the player presents frame i at
/// its own clock's origin + PTS_i (its frame clock, as `play`), and the pads wait while the
/// player's queue (pad_feed.h) is full, so the pipeline runs at the player's pace. A flush drops
/// the frames queued and unblocks the pads; EOS on both pads ends the stream: once the player has
/// shown the last frame it posts EOS on the bus. PLAYING to PAUSED pauses the player (the surface
/// holds still and stays touchable).
///
/// Depth mapping: the depth pad's tag events (matroskademux's extended comments
/// "DEPTH_NEAR=...", read by depth_tags.h as the FFmpeg source reads them) give the depth stream's
/// hal::DepthMetadata, as `play` reads it from the file.
///
/// Preroll: READY to PAUSED is asynchronous (the `async` property, as GstBaseSink's): PAUSED is
/// committed once each pad has its first frame or its EOS.
///
/// Properties: haptic-device, haptic-device-options, stiffness (live), method, display,
/// display-options, control (play's options, checked by play's option table: a bad value fails
/// READY to PAUSED with an error on the bus), async; read-only frames-paired, frames-presented,
/// depth-unpaired, depth-missing, updates, servo-rate, contact-force, contact-force-z,
/// safety-trips, watchdog-trips, haptics. Thread-safety: GStreamer's (an internal mutex for the
/// properties).

#include <gst/gst.h>

namespace depthtouch::gst {

/// The element's name in pipelines.
inline constexpr const char *kDepthTouchSinkName = "depthtouchsink";

/// \return the GType of depthtouchsink (registered on the first call).
GType depthTouchSinkGetType();

} // namespace depthtouch::gst
