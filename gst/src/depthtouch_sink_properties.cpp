/// \file
/// \brief depthtouchsink's properties: see depthtouch_sink.h.

#include <string>

#include "depthtouch_sink_state.h"
#include "element_common.h"
#include "gst_casts.h"

namespace depthtouch::gst {

namespace {

std::string textOf(const GValue *value)
{
    const gchar *text = g_value_get_string(value);
    return text != nullptr ? text : "";
}

/// Sets \a value from the readout \a r (a read-only property \a id).
void getReadout(guint id, const PlayerReadout &r, GValue *value)
{
    switch (id) {
    case kPropFramesPaired:
        g_value_set_uint64(value, r.framesPaired);
        break;
    case kPropFramesPresented:
        g_value_set_uint64(value, r.framesPresented);
        break;
    case kPropDepthUnpaired:
        g_value_set_uint64(value, r.depthUnpaired);
        break;
    case kPropDepthMissing:
        g_value_set_uint64(value, r.depthMissing);
        break;
    case kPropUpdates:
        g_value_set_uint64(value, r.hapticUpdates);
        break;
    case kPropServoRate:
        g_value_set_double(value, r.servoRateHz);
        break;
    case kPropContactForce:
        g_value_set_double(value, r.force);
        break;
    case kPropContactForceZ:
        g_value_set_double(value, r.forceZ);
        break;
    case kPropPosition:
        g_value_set_double(value, r.position);
        break;
    case kPropSafetyTrips:
        g_value_set_uint64(value, r.safetyTrips);
        break;
    case kPropWatchdogTrips:
        g_value_set_uint64(value, r.watchdogTrips);
        break;
    case kPropHaptics:
        g_value_set_boolean(value, r.haptics ? TRUE : FALSE);
        break;
    default:
        break;
    }
}

} // namespace

void setSinkProperty(GObject *object, guint id, const GValue *value, GParamSpec *spec)
{
    SinkState &s = stateOf(object);
    const std::lock_guard lock(s.mutex);
    switch (id) {
    case kPropDevice:
    case kPropDeviceOptions:
    case kPropStiffness:
    case kPropMethod:
        setHapticProperty(s.settings.haptic, static_cast<HapticProperty>(id - kPropDevice), value);
        if (id == kPropStiffness && s.player)
            s.player->setStiffness(s.settings.haptic.stiffness);
        break;
    case kPropDisplay:
        s.settings.display = textOf(value);
        break;
    case kPropDisplayOptions:
        s.settings.displayOptions = textOf(value);
        break;
    case kPropControl:
        s.settings.control = textOf(value);
        break;
    case kPropAsync:
        s.async = g_value_get_boolean(value) != FALSE;
        break;
    default:
        warnInvalidProperty(object, id, spec);
        break;
    }
}

void getSinkProperty(GObject *object, guint id, GValue *value, GParamSpec *spec)
{
    SinkState &s = stateOf(object);
    const std::lock_guard lock(s.mutex);
    switch (id) {
    case kPropDevice:
    case kPropDeviceOptions:
    case kPropStiffness:
    case kPropMethod:
        getHapticProperty(s.settings.haptic, static_cast<HapticProperty>(id - kPropDevice), value);
        break;
    case kPropDisplay:
        g_value_set_string(value, s.settings.display.c_str());
        break;
    case kPropDisplayOptions:
        g_value_set_string(value, s.settings.displayOptions.c_str());
        break;
    case kPropControl:
        g_value_set_string(value, s.settings.control.c_str());
        break;
    case kPropAsync:
        g_value_set_boolean(value, s.async ? TRUE : FALSE);
        break;
    default:
        if (id >= kPropFramesPaired && id <= kPropHaptics)
            getReadout(id, s.player ? s.player->readout() : PlayerReadout{}, value);
        else
            warnInvalidProperty(object, id, spec);
        break;
    }
}

void installSinkProperties(GObjectClass *oc)
{
    installHapticProperties(oc, kPropDevice);
    g_object_class_install_property(
        oc, kPropDisplay,
        g_param_spec_string("display", "Display",
                            "Display backend(s), comma-separated, tried in order, as play "
                            "--display (x11, kms, offscreen, ...); empty: autoprobe, as play",
                            "", kReadWrite));
    g_object_class_install_property(
        oc, kPropDisplayOptions,
        g_param_spec_string("display-options", "Display options",
                            "The display backend's key=value options, as play --display-options",
                            "", kReadWrite));
    g_object_class_install_property(
        oc, kPropControl,
        g_param_spec_string("control", "Control socket",
                            "Path of the control socket (mpv's JSON IPC), as play --control; "
                            "empty: none",
                            "", kReadWrite));
    g_object_class_install_property(
        oc, kPropAsync,
        g_param_spec_boolean("async", "Async",
                             "Go to PAUSED asynchronously: once each pad has its first frame (or "
                             "its EOS), as GstBaseSink's async",
                             TRUE, kReadWrite));
    installCounter(oc, kPropFramesPaired, "frames-paired",
                   "Colour + depth pairs the player's receiver made by PTS (running time)");
    installCounter(oc, kPropFramesPresented, "frames-presented", "Pairs the player presented");
    installCounter(oc, kPropDepthUnpaired, "depth-unpaired",
                   "Depth frames no colour frame was paired with");
    installCounter(oc, kPropDepthMissing, "depth-missing", "Pairs made without a depth frame");
    installCounter(oc, kPropUpdates, "updates", "Cycles of the haptic loop so far");
    installMeasure(oc, kPropServoRate, "servo-rate",
                   "Haptic updates per second measured over the run, Hz", 0.0);
    installMeasure(oc, kPropContactForce, "contact-force",
                   "Magnitude of the last force commanded to the device, N", 0.0);
    installMeasure(oc, kPropContactForceZ, "contact-force-z",
                   "z of the last force, N, scene box (positive: toward the viewer)", -G_MAXDOUBLE);
    installMeasure(oc, kPropPosition, "position",
                   "Running time of the frame on screen, s: the player follows the pipeline's "
                   "clock",
                   0.0);
    installCounter(oc, kPropSafetyTrips, "safety-trips",
                   "Force-jump releases of the renderer and watchdog trips so far");
    installCounter(oc, kPropWatchdogTrips, "watchdog-trips",
                   "Of safety-trips, the watchdog's zero-force trips (a missed deadline, a device "
                   "time-out): the machine's load where the haptic thread is not SCHED_FIFO");
    g_object_class_install_property(
        oc, kPropHaptics,
        g_param_spec_boolean("haptics", "Haptics",
                             "A haptic task runs (a depth stream and a haptic device)", FALSE,
                             kReadOnly));
}

} // namespace depthtouch::gst
