#pragma once
/// \file
/// \brief What DepthTouch's two GStreamer elements (hapticsink, depthtouchsink) share on the
/// GStreamer side: the four properties of the haptic settings (haptic-device,
/// haptic-device-options, stiffness, method: play's options, play's defaults and ranges) and the
/// reading of the demuxer's depth tags from a GST_EVENT_TAG (depth_tags.h).
/// Thread-safety: the installers at class init; the rest on the caller's data (the elements lock).

#include <cstdint>
#include <string>
#include <vector>

#include <gst/gst.h>
#include <gst/video/video.h>

#include "depthtouch/hal/media_source.h"
#include "depthtouch/platform/clock.h"
#include "haptic_session.h"

namespace depthtouch::gst {

/// The haptic settings' properties, in HapticSettings' order.
enum class HapticProperty : guint { Device, DeviceOptions, Stiffness, Method };

/// Flags of the elements' properties.
inline constexpr GParamFlags kReadWrite =
    static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
inline constexpr GParamFlags kReadOnly =
    static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS);
inline constexpr GParamFlags kReadWriteLive = static_cast<GParamFlags>(
    G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS | GST_PARAM_MUTABLE_PLAYING);

/// \brief Installs the four haptic settings' properties on \a oc with ids \a firstId + the
/// HapticProperty (play's defaults, the stiffness's range, the method's names).
void installHapticProperties(GObjectClass *oc, guint firstId);
/// \brief Sets the setting \a p of \a s from \a value.
void setHapticProperty(HapticSettings &s, HapticProperty p, const GValue *value);
/// \brief Reads the setting \a p of \a s into \a value.
void getHapticProperty(const HapticSettings &s, HapticProperty p, GValue *value);

/// \brief Installs a read-only uint64 counter \a name (from 0).
void installCounter(GObjectClass *oc, guint id, const char *name, const char *blurb);
/// \brief Installs a read-only double \a name from \a min (default 0).
void installMeasure(GObjectClass *oc, guint id, const char *name, const char *blurb, double min);

/// \return the frame of \a buffer (caps \a info) tightly packed in \a format
/// (hal::planeLayout(): \a format's planes from the frame's first ones, so an I420 frame read as
/// Gray8 gives its luma), or empty when it cannot be mapped.
std::vector<std::uint8_t> packVideoFrame(const GstVideoInfo &info, hal::PixelFormat format,
                                         GstBuffer *buffer);

/// \brief Reads the depth tags of a tag event (extended comments "KEY=value", matroskademux's
/// form) into \a md. \return true when \a md changed.
bool readDepthTagEvent(GstEvent *event, hal::DepthMetadata &md);
/// \return "depth tags: near N m, far N m, mapping 'M', bits B, occupancy O" (the log line).
std::string describeDepthTags(const hal::DepthMetadata &md);

/// \brief Reads \a element's pipeline clock: its running time now (clock time − base time, ns: the
/// time its pads' buffers carry once through their segment) into \a running, and the steady
/// clock's time of that reading (platform::SteadyClock, the player's and the haptic task's clock)
/// into \a at. \return false without a clock (the element is not in a pipeline's PAUSED or
/// PLAYING) or before the base time. Thread-safe (a GstClock is read under its own seqlock).
bool runningTimeNow(GstElement *element, platform::TimePoint &at, GstClockTime &running);

} // namespace depthtouch::gst
