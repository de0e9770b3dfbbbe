/// \file
/// \brief The elements' shared properties and tag reading: see element_common.h.

#include "element_common.h"

#include <cstring>

#include "depth_tags.h"
#include "gst_casts.h"
#include "depthtouch/haptics/renderer_table.h"
#include "depthtouch/options/option_range.h"

namespace depthtouch::gst {

namespace {

/// \return the string of \a value, "" for null.
std::string textOf(const GValue *value)
{
    const gchar *text = g_value_get_string(value);
    return text != nullptr ? text : "";
}

guint idOf(guint first, HapticProperty p)
{
    return first + static_cast<guint>(p);
}

} // namespace

void installHapticProperties(GObjectClass *oc, guint firstId)
{
    const HapticSettings play; // play's defaults
    g_object_class_install_property(
        oc, idOf(firstId, HapticProperty::Device),
        g_param_spec_string("haptic-device", "Haptic device",
                            "Haptic device backend(s), comma-separated, tried in order, as play "
                            "--haptic: falcon, sim (the simulated hand), mock, none",
                            play.device.c_str(), kReadWrite));
    g_object_class_install_property(
        oc, idOf(firstId, HapticProperty::DeviceOptions),
        g_param_spec_string("haptic-device-options", "Haptic device options",
                            "The backend's key=value options, comma-separated, as play "
                            "--haptic-options (sim: intent=press,force=2)",
                            play.deviceOptions.c_str(), kReadWrite));
    g_object_class_install_property(
        oc, idOf(firstId, HapticProperty::Stiffness),
        g_param_spec_double("stiffness", "Stiffness", "Surface stiffness k, N/m (live)",
                            options::kStiffness.min, options::kStiffness.max, play.stiffness,
                            kReadWriteLive));
    // GLib keeps the blurb's pointer: a string that lives as long as the program.
    static const std::string methodBlurb =
        "Haptic renderer, as play --method: " + haptics::rendererNames(", ", " or ") +
        " (the renderer table)";
    g_object_class_install_property(oc, idOf(firstId, HapticProperty::Method),
                                    g_param_spec_string("method", "Method", methodBlurb.c_str(),
                                                        play.method.c_str(), kReadWrite));
}

void setHapticProperty(HapticSettings &s, HapticProperty p, const GValue *value)
{
    switch (p) {
    case HapticProperty::Device:
        s.device = textOf(value);
        break;
    case HapticProperty::DeviceOptions:
        s.deviceOptions = textOf(value);
        break;
    case HapticProperty::Stiffness:
        s.stiffness = g_value_get_double(value);
        break;
    case HapticProperty::Method:
        s.method = textOf(value);
        break;
    }
}

void getHapticProperty(const HapticSettings &s, HapticProperty p, GValue *value)
{
    switch (p) {
    case HapticProperty::Device:
        g_value_set_string(value, s.device.c_str());
        break;
    case HapticProperty::DeviceOptions:
        g_value_set_string(value, s.deviceOptions.c_str());
        break;
    case HapticProperty::Stiffness:
        g_value_set_double(value, s.stiffness);
        break;
    case HapticProperty::Method:
        g_value_set_string(value, s.method.c_str());
        break;
    }
}

void installCounter(GObjectClass *oc, guint id, const char *name, const char *blurb)
{
    g_object_class_install_property(
        oc, id, g_param_spec_uint64(name, name, blurb, 0, G_MAXUINT64, 0, kReadOnly));
}

void installMeasure(GObjectClass *oc, guint id, const char *name, const char *blurb, double min)
{
    g_object_class_install_property(
        oc, id, g_param_spec_double(name, name, blurb, min, G_MAXDOUBLE, 0.0, kReadOnly));
}

std::vector<std::uint8_t> packVideoFrame(const GstVideoInfo &info, hal::PixelFormat format,
                                         GstBuffer *buffer)
{
    GstVideoInfo mapped = info;
    GstVideoFrame frame;
    if (gst_video_frame_map(&frame, &mapped, buffer, GST_MAP_READ) == FALSE)
        return {};
    const int w = GST_VIDEO_INFO_WIDTH(&mapped);
    const int h = GST_VIDEO_INFO_HEIGHT(&mapped);
    std::vector<std::uint8_t> bytes(hal::imageBytes(format, w, h));
    std::uint8_t *out = bytes.data();
    for (int plane = 0; plane < hal::planeCount(format); ++plane) {
        const hal::PlaneLayout l = hal::planeLayout(format, w, h, plane);
        const std::uint8_t *in = planeDataAt(frame, static_cast<guint>(plane));
        const auto stride =
            static_cast<std::size_t>(planeStrideAt(frame, static_cast<guint>(plane)));
        const auto row = static_cast<std::size_t>(l.rowBytes);
        for (int y = 0; y < l.rows; ++y, out += row)
            std::memcpy(out, in + static_cast<std::size_t>(y) * stride, row);
    }
    gst_video_frame_unmap(&frame);
    return bytes;
}

bool readDepthTagEvent(GstEvent *event, hal::DepthMetadata &md)
{
    GstTagList *list = nullptr;
    gst_event_parse_tag(event, &list);
    if (list == nullptr)
        return false;
    const guint n = gst_tag_list_get_tag_size(list, GST_TAG_EXTENDED_COMMENT);
    const hal::DepthMetadata a = md;
    for (guint i = 0; i < n; ++i) {
        const gchar *text = nullptr;
        if (gst_tag_list_peek_string_index(list, GST_TAG_EXTENDED_COMMENT, i, &text) != FALSE &&
            text != nullptr)
            applyDepthTag(text, md);
    }
    return a.nearMetres != md.nearMetres || a.farMetres != md.farMetres ||
           a.mapping != md.mapping || a.bits != md.bits || a.occupancy != md.occupancy;
}

std::string describeDepthTags(const hal::DepthMetadata &t)
{
    return "depth tags: near " + options::OptionRange::number(t.nearMetres) + " m, far " +
           options::OptionRange::number(t.farMetres) + " m, mapping '" + t.mapping + "', bits " +
           std::to_string(t.bits) + ", occupancy " + std::to_string(t.occupancy);
}

bool runningTimeNow(GstElement *element, platform::TimePoint &at, GstClockTime &running)
{
    GstClock *clock = gst_element_get_clock(element);
    if (clock == nullptr)
        return false;
    at = platform::SteadyClock::instance().now();
    const GstClockTime t = gst_clock_get_time(clock);
    const GstClockTime base = gst_element_get_base_time(element);
    gst_object_unref(clock);
    if (!isTime(t) || !isTime(base) || t < base)
        return false;
    running = t - base;
    return true;
}

} // namespace depthtouch::gst
