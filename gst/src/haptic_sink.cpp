/// \file
/// \brief hapticsink, the depth-only GStreamer sink of the haptic task: see haptic_sink.h.

#include "haptic_sink.h"

#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <source_location>
#include <string>

#include <glm/geometric.hpp>

#include "depth_tags.h"
#include "element_common.h"
#include "depthtouch/depth/conversion.h"
#include "depthtouch/options/option_range.h"
#include "depthtouch/platform/clock.h"
#include "gst_casts.h"
#include "haptic_session.h"

namespace depthtouch::gst {

namespace {

/// The element's own state (C++), owned by the instance; every field under mutex.
struct SinkState {
    std::mutex mutex;
    HapticSettings settings;
    const depth::DepthRange defaultPlanes{};
    double nearProperty = defaultPlanes.nearM; ///< depth-near as set, m.
    double farProperty = defaultPlanes.farM;   ///< depth-far as set, m.
    hal::DepthMetadata tags;                   ///< The stream's depth tags so far.
    std::unique_ptr<HapticSession> session;    ///< Between start() and stop().
    GstVideoInfo info{};
    bool configured = false;
    scene::SampleFormat format = scene::SampleFormat::Gray8;
    std::uint32_t holeBelow = 0;
    /// Without a pipeline clock: the steady time at running time 0, from the first buffer.
    bool haveOrigin = false;
    platform::TimePoint origin{};
};

struct HapticSink {
    GstBaseSink parent;
    SinkState *state;
};

struct HapticSinkClass {
    GstBaseSinkClass parentClass;
};

GstBaseSinkClass *parentClass = nullptr;
/// The element's debug category, "hapticsink" (GST_DEBUG=hapticsink:4 shows the start, the caps,
/// the depth tags and the run's counters at stop).
GstDebugCategory *category = nullptr;

enum Property : guint {
    kPropZero,
    kPropDevice,
    kPropDeviceOptions,
    kPropStiffness,
    kPropMethod,
    kPropDepthNear,
    kPropDepthFar,
    kPropContactForce,
    kPropContactForceZ,
    kPropHipZ,
    kPropServoRate,
    kPropUpdates,
    kPropSafetyTrips,
    kPropWatchdogTrips,
};

SinkState &stateOf(gpointer self)
{
    return *static_cast<HapticSink *>(self)->state;
}

/// \brief Posts \a text as the element's error (prefixed with its name) and returns FALSE.
gboolean fail(gpointer self, GQuark domain, gint code, const std::string &text,
              const std::source_location where = std::source_location::current())
{
    const std::string line = std::string(kHapticSinkName) + ": " + text;
    postError(self, domain, code, line.c_str(), nullptr, where);
    return FALSE;
}

// ---- properties -------------------------------------------------------------------------------

void setProperty(GObject *object, guint id, const GValue *value, GParamSpec *spec)
{
    SinkState &s = stateOf(object);
    const std::lock_guard lock(s.mutex);
    switch (id) {
    case kPropDevice:
    case kPropDeviceOptions:
    case kPropStiffness:
    case kPropMethod:
        setHapticProperty(s.settings, static_cast<HapticProperty>(id - kPropDevice), value);
        if (id == kPropStiffness && s.session)
            s.session->setStiffness(s.settings.stiffness);
        break;
    case kPropDepthNear:
        s.nearProperty = g_value_get_double(value);
        break;
    case kPropDepthFar:
        s.farProperty = g_value_get_double(value);
        break;
    default:
        warnInvalidProperty(object, id, spec);
        break;
    }
}

void getProperty(GObject *object, guint id, GValue *value, GParamSpec *spec)
{
    SinkState &s = stateOf(object);
    const std::lock_guard lock(s.mutex);
    // The task's measurements are read for the read-only properties only (stats() drains).
    const bool measured = id >= kPropContactForce && id <= kPropWatchdogTrips;
    const HapticReadout r = measured && s.session ? s.session->readout() : HapticReadout{};
    switch (id) {
    case kPropDevice:
    case kPropDeviceOptions:
    case kPropStiffness:
    case kPropMethod:
        getHapticProperty(s.settings, static_cast<HapticProperty>(id - kPropDevice), value);
        break;
    case kPropDepthNear:
        g_value_set_double(value, s.tags.nearMetres > 0.0 ? s.tags.nearMetres : s.nearProperty);
        break;
    case kPropDepthFar:
        g_value_set_double(value, s.tags.farMetres > 0.0 ? s.tags.farMetres : s.farProperty);
        break;
    case kPropContactForce:
        g_value_set_double(value, glm::length(r.force));
        break;
    case kPropContactForceZ:
        g_value_set_double(value, r.force.z);
        break;
    case kPropHipZ:
        g_value_set_double(value, r.posed ? r.hip.z : 0.0);
        break;
    case kPropServoRate:
        g_value_set_double(value, r.servoRateHz);
        break;
    case kPropUpdates:
        g_value_set_uint64(value, r.updates);
        break;
    case kPropSafetyTrips:
        g_value_set_uint64(value, r.safetyTrips);
        break;
    case kPropWatchdogTrips:
        g_value_set_uint64(value, r.watchdogTrips);
        break;
    default:
        warnInvalidProperty(object, id, spec);
        break;
    }
}

constexpr double kMaxPlane = 1e6; ///< Largest plane distance accepted, m.

void installProperties(GObjectClass *oc)
{
    const depth::DepthRange planes{};
    installHapticProperties(oc, kPropDevice);
    g_object_class_install_property(
        oc, kPropDepthNear,
        g_param_spec_double("depth-near", "Near plane",
                            "Distance of the largest nearness, m, when the stream's depth_near "
                            "tag gives none (reads the one in use)",
                            1e-6, kMaxPlane, planes.nearM, kReadWrite));
    g_object_class_install_property(
        oc, kPropDepthFar,
        g_param_spec_double("depth-far", "Far plane",
                            "Distance of nearness 0, m, when the stream's depth_far tag gives "
                            "none (reads the one in use)",
                            1e-6, kMaxPlane, planes.farM, kReadWrite));
    g_object_class_install_property(
        oc, kPropContactForce,
        g_param_spec_double("contact-force", "Contact force",
                            "Magnitude of the last force commanded to the device, N", 0.0,
                            G_MAXDOUBLE, 0.0, kReadOnly));
    g_object_class_install_property(
        oc, kPropContactForceZ,
        g_param_spec_double("contact-force-z", "Contact force along z",
                            "z of the last force, N, scene box (positive: toward the viewer)",
                            -G_MAXDOUBLE, G_MAXDOUBLE, 0.0, kReadOnly));
    g_object_class_install_property(
        oc, kPropHipZ,
        g_param_spec_double("hip-z", "HIP height",
                            "z of the haptic interface point at the last update, m, scene box",
                            -G_MAXDOUBLE, G_MAXDOUBLE, 0.0, kReadOnly));
    g_object_class_install_property(
        oc, kPropServoRate,
        g_param_spec_double("servo-rate", "Servo rate",
                            "Haptic updates per second measured over the run, Hz", 0.0, G_MAXDOUBLE,
                            0.0, kReadOnly));
    g_object_class_install_property(oc, kPropUpdates,
                                    g_param_spec_uint64("updates", "Updates",
                                                        "Cycles of the haptic loop so far", 0,
                                                        G_MAXUINT64, 0, kReadOnly));
    g_object_class_install_property(
        oc, kPropSafetyTrips,
        g_param_spec_uint64("safety-trips", "Safety trips",
                            "Force-jump releases of the renderer and watchdog trips so far", 0,
                            G_MAXUINT64, 0, kReadOnly));
    g_object_class_install_property(
        oc, kPropWatchdogTrips,
        g_param_spec_uint64(
            "watchdog-trips", "Watchdog trips",
            "Of safety-trips, the watchdog's zero-force trips (a missed deadline, a device "
            "time-out): the machine's load where the haptic thread is not SCHED_FIFO",
            0, G_MAXUINT64, 0, kReadOnly));
}

// ---- the base sink's methods ------------------------------------------------------------------

gboolean start(GstBaseSink *sink)
{
    SinkState &s = stateOf(sink);
    const std::lock_guard lock(s.mutex);
    const std::string bad = checkHapticSettings(s.settings);
    if (!bad.empty())
        return fail(sink, GST_RESOURCE_ERROR, GST_RESOURCE_ERROR_SETTINGS, bad);
    std::string why;
    s.session = HapticSession::open(s.settings, platform::SteadyClock::instance(), why);
    if (!s.session)
        return fail(sink, GST_RESOURCE_ERROR, GST_RESOURCE_ERROR_OPEN_READ_WRITE,
                    "cannot open the haptic device '" + s.settings.device + "': " + why);
    s.configured = false;
    s.haveOrigin = false;
    s.tags = {};
    logInfo(category, sink,
            ("haptic device '" + s.session->deviceName() + "', method " + s.settings.method +
             ", stiffness " + options::OptionRange::number(s.settings.stiffness) + " N/m")
                .c_str());
    return TRUE;
}

gboolean stop(GstBaseSink *sink)
{
    SinkState &s = stateOf(sink);
    const std::lock_guard lock(s.mutex);
    if (s.session) {
        const HapticReadout r = s.session->readout();
        const std::string line =
            "stopped: " + std::to_string(r.updates) + " updates, " +
            std::to_string(r.contactUpdates) + " in contact, max force " +
            options::OptionRange::number(r.maxForce) + " N, " + std::to_string(r.safetyTrips) +
            " safety trips (" + std::to_string(r.watchdogTrips) +
            " by the watchdog); depth planes " +
            options::OptionRange::number(s.tags.nearMetres > 0.0 ? s.tags.nearMetres
                                                                 : s.nearProperty) +
            ".." +
            options::OptionRange::number(s.tags.farMetres > 0.0 ? s.tags.farMetres
                                                                : s.farProperty) +
            " m (" + (s.tags.nearMetres > 0.0 ? "tags" : "properties") + ")";
        logInfo(category, sink, line.c_str());
    }
    s.session.reset(); // zero force, the task stopped, the device closed
    s.configured = false;
    return TRUE;
}

gboolean setCaps(GstBaseSink *sink, GstCaps *caps)
{
    SinkState &s = stateOf(sink);
    const std::lock_guard lock(s.mutex);
    GstVideoInfo info;
    if (gst_video_info_from_caps(&info, caps) == FALSE)
        return fail(sink, GST_STREAM_ERROR, GST_STREAM_ERROR_FORMAT,
                    "the caps are not raw video with a size");
    const GstVideoFormat f = GST_VIDEO_INFO_FORMAT(&info);
    if (f != GST_VIDEO_FORMAT_GRAY8 && f != GST_VIDEO_FORMAT_GRAY16_LE)
        return fail(sink, GST_STREAM_ERROR, GST_STREAM_ERROR_FORMAT,
                    "depth must be GRAY8 or GRAY16_LE nearness");
    if (f == GST_VIDEO_FORMAT_GRAY16_LE && G_BYTE_ORDER != G_LITTLE_ENDIAN)
        return fail(sink, GST_STREAM_ERROR, GST_STREAM_ERROR_FORMAT,
                    "GRAY16_LE on a big-endian host is not supported");
    const int w = GST_VIDEO_INFO_WIDTH(&info);
    const int h = GST_VIDEO_INFO_HEIGHT(&info);
    if (w < 2 || h < 2 || w > 16384 || h > 16384)
        return fail(sink, GST_STREAM_ERROR, GST_STREAM_ERROR_FORMAT,
                    "depth frames of " + std::to_string(w) + "x" + std::to_string(h) +
                        ": 2 to 16384 pixels each way");
    s.info = info;
    s.format =
        f == GST_VIDEO_FORMAT_GRAY8 ? scene::SampleFormat::Gray8 : scene::SampleFormat::Gray16;
    s.holeBelow = holeBelowFor(s.tags, s.format);
    if (s.session) {
        if (auto r = s.session->configure(w, h, s.format); !r) {
            char buf[256];
            return fail(sink, GST_RESOURCE_ERROR, GST_RESOURCE_ERROR_FAILED,
                        std::string("cannot start the haptic task: ") +
                            r.error().format(buf, sizeof buf));
        }
    }
    s.configured = true;
    return TRUE;
}

/// Reads the stream's depth tags from a tag event (extended comments "KEY=value") of \a sink.
void readTags(GstBaseSink *sink, SinkState &s, GstEvent *event)
{
    if (!readDepthTagEvent(event, s.tags))
        return;
    if (s.configured)
        s.holeBelow = holeBelowFor(s.tags, s.format);
    logInfo(category, sink, describeDepthTags(s.tags).c_str());
}

gboolean event(GstBaseSink *sink, GstEvent *ev)
{
    SinkState &s = stateOf(sink);
    {
        const std::lock_guard lock(s.mutex);
        switch (eventType(ev)) {
        case GST_EVENT_TAG:
            readTags(sink, s, ev);
            break;
        case GST_EVENT_FLUSH_STOP:
            s.haveOrigin = false;
            if (s.session)
                s.session->restart();
            break;
        case GST_EVENT_EOS:
            if (s.session)
                s.session->finish();
            break;
        default:
            break;
        }
    }
    return parentClass->event(sink, ev);
}

/// \return the steady clock's time at running time 0: from the pipeline clock when the element
/// has one (its running time now), else fixed by the first buffer since the start or a flush.
platform::TimePoint mediaOrigin(GstBaseSink *sink, SinkState &s, GstClockTime running)
{
    platform::TimePoint at{};
    GstClockTime now = 0;
    if (runningTimeNow(asElement(sink), at, now))
        return at - std::chrono::nanoseconds(static_cast<std::int64_t>(now));
    if (!s.haveOrigin) {
        s.origin = platform::SteadyClock::instance().now() -
                   std::chrono::nanoseconds(static_cast<std::int64_t>(running));
        s.haveOrigin = true;
    }
    return s.origin;
}

GstFlowReturn render(GstBaseSink *sink, GstBuffer *buffer)
{
    SinkState &s = stateOf(sink);
    const std::lock_guard lock(s.mutex);
    if (!s.configured || !s.session || s.session->noDevice())
        return GST_FLOW_OK;
    GstClockTime running = 0;
    if (const GstClockTime pts = bufferPts(buffer); isTime(pts)) {
        const GstClockTime rt = gst_segment_to_running_time(&sink->segment, GST_FORMAT_TIME, pts);
        if (isTime(rt))
            running = rt;
    }
    GstVideoFrame frame;
    if (gst_video_frame_map(&frame, &s.info, buffer, GST_MAP_READ) == FALSE) {
        fail(sink, GST_STREAM_ERROR, GST_STREAM_ERROR_FAILED, "cannot map a depth buffer");
        return GST_FLOW_ERROR;
    }
    scene::DepthFrameView view;
    view.data = planeData(frame);
    view.width = GST_VIDEO_INFO_WIDTH(&s.info);
    view.height = GST_VIDEO_INFO_HEIGHT(&s.info);
    view.strideBytes = static_cast<std::size_t>(planeStride(frame));
    view.format = s.format;
    view.pts = static_cast<double>(running) * 1e-9;
    view.holeBelow = s.holeBelow;
    const auto pushed = s.session->push(view, mediaOrigin(sink, s, running));
    gst_video_frame_unmap(&frame);
    if (!pushed) {
        char buf[256];
        fail(sink, GST_STREAM_ERROR, GST_STREAM_ERROR_FORMAT,
             std::string("a depth frame was refused: ") + pushed.error().format(buf, sizeof buf));
        return GST_FLOW_ERROR;
    }
    return GST_FLOW_OK;
}

// ---- the type ---------------------------------------------------------------------------------

void finalize(GObject *object)
{
    auto *self = reinterpret_cast<HapticSink *>(object);
    delete self->state;
    self->state = nullptr;
    asObjectClass(parentClass)->finalize(object);
}

void instanceInit(GTypeInstance *instance, gpointer)
{
    auto *self = reinterpret_cast<HapticSink *>(instance);
    self->state = new SinkState();
    gst_base_sink_set_sync(asBaseSink(instance), TRUE);
}

void classInit(gpointer klass, gpointer)
{
    parentClass = static_cast<GstBaseSinkClass *>(g_type_class_peek_parent(klass));
    category = _gst_debug_category_new(kHapticSinkName, 0, "DepthTouch haptic sink");
    GObjectClass *oc = asObjectClass(klass);
    oc->set_property = setProperty;
    oc->get_property = getProperty;
    oc->finalize = finalize;
    installProperties(oc);

    GstElementClass *ec = asElementClass(klass);
    gst_element_class_set_static_metadata(
        ec, "DepthTouch haptic sink", "Sink/Video/Haptic",
        "Runs DepthTouch's 1 kHz haptic task on a depth video (GRAY8/GRAY16_LE nearness): the "
        "viewer feels the moving surface through a haptic device",
        "DepthTouch");
    GstCaps *caps = gst_caps_from_string("video/x-raw, format=(string){ GRAY8, GRAY16_LE }, "
                                         "width=(int)[ 2, 16384 ], height=(int)[ 2, 16384 ], "
                                         "framerate=(fraction)[ 0/1, 2147483647/1 ]");
    gst_element_class_add_pad_template(
        ec, gst_pad_template_new("sink", GST_PAD_SINK, GST_PAD_ALWAYS, caps));
    gst_caps_unref(caps);

    GstBaseSinkClass *bc = asBaseSinkClass(klass);
    bc->start = start;
    bc->stop = stop;
    bc->set_caps = setCaps;
    bc->event = event;
    bc->render = render;
}

} // namespace

GType hapticSinkGetType()
{
    static const GType type = g_type_register_static_simple(
        GST_TYPE_BASE_SINK, "GstHapticSink", sizeof(HapticSinkClass), classInit, sizeof(HapticSink),
        instanceInit, static_cast<GTypeFlags>(0));
    return type;
}

} // namespace depthtouch::gst
