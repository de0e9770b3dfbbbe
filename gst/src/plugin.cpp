/// \file
/// \brief The GStreamer plugin `depthtouch` (libgstdepthtouch.so): registers its elements,
/// hapticsink (haptic_sink.h) today; depthtouchsink (colour + depth, the stereo view) is to come,
/// one more gst_element_register() here. GST_PLUGIN_DEFINE expands to C casts and to the exported
/// gst_plugin_depthtouch_get_desc(), hence the narrow warning region around it (gst_casts.h).

#include <gst/gst.h>

#include "haptic_sink.h"

#ifndef DT_GST_VERSION
#define DT_GST_VERSION "0.1.0"
#endif
#define PACKAGE "depthtouch"

namespace {

gboolean pluginInit(GstPlugin *plugin)
{
    return gst_element_register(plugin, depthtouch::gst::kHapticSinkName, GST_RANK_NONE,
                                depthtouch::gst::hapticSinkGetType());
}

} // namespace

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
GST_PLUGIN_DEFINE(GST_VERSION_MAJOR, GST_VERSION_MINOR, depthtouch,
                  "DepthTouch: touchable 3D video (the haptic task on a depth video)", pluginInit,
                  DT_GST_VERSION, "Proprietary", "DepthTouch", "Unknown package origin")
#pragma GCC diagnostic pop
