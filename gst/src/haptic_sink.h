#pragma once
/// \file
/// \brief `hapticsink`: DepthTouch's haptic task as a GStreamer sink (issue 62; docs/embedding.md
/// "GStreamer"). Depth only, for boxes whose video plane belongs to the platform's own sink: the
/// colour goes to that sink, the depth video to this one, which hands each depth frame to the
/// 1 kHz haptic task (a GstBaseSink subclass; render() publishes, nothing is drawn).
///
/// Pad `sink` (always): `video/x-raw, format={GRAY8, GRAY16_LE}`, any size from 2×2 to
/// 16384×16384, any frame rate. The samples are nearness (0 far, the maximum near), the depth
/// video of a DepthTouch file as `play` decodes it (decodebin ! videoconvert gives GRAY8 of an
/// H.264 4:0:0 depth stream).
///
/// Timing: each buffer is published when the base sink renders it (sync=true: at its running
/// time on the pipeline clock), as the newest pair (previous frame, this frame) of the depth
/// hand-off, with the buffer's running time as its PTS; the haptic time is the pipeline clock's
/// running time, carried over to the haptic task's steady clock at each buffer. A flush restarts
/// the pairs and the haptic time, the end of the stream holds the last frame.
///
/// Depth mapping: holes (docs/architecture.md §3 "Holes") come from the stream's depth tags
/// (depth_occupancy with depth_bits) in the GST_EVENT_TAG events the demuxer sends (matroskademux:
/// extended comments "DEPTH_OCCUPANCY=...", depth_tags.h); a stream without them has no holes. The
/// planes depth_near and depth_far (metres) come from the same tags when present, else from the
/// properties depth-near / depth-far (the project's default planes, depth::DepthRange). The haptic
/// surface is the nearness image in the scene box (§3 "Vertices"), as `play` touches it: the
/// planes do not change the force; they are kept as the stream's description for the
/// application (and for depthtouchsink's drawing, to come).
///
/// Properties: haptic-device, haptic-device-options, stiffness, method (play's options, its
/// option table's checks: a bad value fails the start with an error message on the bus),
/// depth-near, depth-far; read-only contact-force, contact-force-z, hip-z, servo-rate, updates,
/// safety-trips, watchdog-trips. Thread-safety: GStreamer's: properties from any thread (an
/// internal mutex), the base sink's virtual methods from its streaming and state-change threads.

#include <gst/gst.h>

namespace depthtouch::gst {

/// The element's name in pipelines.
inline constexpr const char *kHapticSinkName = "hapticsink";

/// \return the GType of hapticsink (registered on the first call).
GType hapticSinkGetType();

} // namespace depthtouch::gst
