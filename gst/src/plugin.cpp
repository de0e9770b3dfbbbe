/// \file
/// \brief The GStreamer plugin `depthtouch` (libgstdepthtouch.so): registers its elements,
/// hapticsink (haptic_sink.h, depth only) and depthtouchsink (depthtouch_sink.h: colour + depth
/// into play's player, the stereo view and the haptic task). GST_PLUGIN_DEFINE expands to C casts
/// and to the exported gst_plugin_depthtouch_get_desc(), hence the narrow warning region around it
/// (gst_casts.h).

#include <gst/gst.h>

#include "depthtouch_sink.h"
#include "haptic_sink.h"

#ifndef DT_GST_VERSION
#define DT_GST_VERSION "0.1.0"
#endif
#define PACKAGE "depthtouch"

namespace {

gboolean pluginInit(GstPlugin *plugin)
{
    return gst_element_register(plugin, depthtouch::gst::kHapticSinkName, GST_RANK_NONE,
                                depthtouch::gst::hapticSinkGetType()) != FALSE &&
                   gst_element_register(plugin, depthtouch::gst::kDepthTouchSinkName, GST_RANK_NONE,
                                        depthtouch::gst::depthTouchSinkGetType()) != FALSE
               ? TRUE
               : FALSE;
}

} // namespace

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
GST_PLUGIN_DEFINE(GST_VERSION_MAJOR, GST_VERSION_MINOR, depthtouch,
                  "DepthTouch: touchable 3D video (the stereo view and the haptic task of a colour "
                  "+ depth video)",
                  pluginInit, DT_GST_VERSION, "Proprietary", "DepthTouch", "Unknown package origin")
#pragma GCC diagnostic pop
