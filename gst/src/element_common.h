#pragma once
/// \file
/// \brief What DepthTouch's two GStreamer elements (hapticsink, depthtouchsink) share on the
/// GStreamer side: the four properties of the haptic settings (haptic-device,
/// haptic-device-options, stiffness, method: play's options, play's defaults and ranges) and the
/// reading of the demuxer's depth tags from a GST_EVENT_TAG (depth_tags.h).
/// Thread-safety: the installers at class init; the rest on the caller's data (the elements lock).

#include <string>

#include <gst/gst.h>

#include "depthtouch/hal/media_source.h"
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

/// \brief Reads the depth tags of a tag event (extended comments "KEY=value", matroskademux's
/// form) into \a md. \return true when \a md changed.
bool readDepthTagEvent(GstEvent *event, hal::DepthMetadata &md);
/// \return "depth tags: near N m, far N m, mapping 'M', bits B, occupancy O" (the log line).
std::string describeDepthTags(const hal::DepthMetadata &md);

} // namespace depthtouch::gst
