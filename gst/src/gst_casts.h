#pragma once
/// \file
/// \brief The GObject and GStreamer C macros the plugin uses, each behind a small typed function.
/// GLib's type-check and cast macros (G_OBJECT, GST_ELEMENT_CAST, GST_VIDEO_FRAME_PLANE_DATA, ...)
/// expand to C casts, which the project's -Wold-style-cast refuses; they are confined here, in
/// one region where that warning is off (-Wuseless-cast too: some expand to casts to the same
/// type), so that the elements' own code keeps the full warning set.
///
/// Thread-safety: what the GStreamer call each wraps says.

#include <cstddef>
#include <cstdint>
#include <source_location>

#include <gst/base/gstbasesink.h>
#include <gst/gst.h>
#include <gst/video/video.h>

namespace depthtouch::gst {

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wuseless-cast"
#pragma GCC diagnostic ignored "-Wsign-conversion"

/// \return \a p as a GObject.
inline GObject *asObject(gpointer p) noexcept
{
    return G_OBJECT(p);
}
/// \return \a p as a GstElement.
inline GstElement *asElement(gpointer p) noexcept
{
    return GST_ELEMENT_CAST(p);
}
/// \return \a p as a GstObject.
inline GstObject *asGstObject(gpointer p) noexcept
{
    return GST_OBJECT_CAST(p);
}
/// \return \a p as a GstBaseSink.
inline GstBaseSink *asBaseSink(gpointer p) noexcept
{
    return GST_BASE_SINK_CAST(p);
}
/// \return the element class of \a klass.
inline GstElementClass *asElementClass(gpointer klass) noexcept
{
    return GST_ELEMENT_CLASS(klass);
}
/// \return the base sink class of \a klass.
inline GstBaseSinkClass *asBaseSinkClass(gpointer klass) noexcept
{
    return GST_BASE_SINK_CLASS(klass);
}
/// \return the object class of \a klass.
inline GObjectClass *asObjectClass(gpointer klass) noexcept
{
    return G_OBJECT_CLASS(klass);
}

/// \return plane 0 of a mapped video frame.
inline const std::uint8_t *planeData(const GstVideoFrame &frame) noexcept
{
    return static_cast<const std::uint8_t *>(GST_VIDEO_FRAME_PLANE_DATA(&frame, 0));
}
/// \return the bytes from one row of plane 0 to the next.
inline int planeStride(const GstVideoFrame &frame) noexcept
{
    return GST_VIDEO_FRAME_PLANE_STRIDE(&frame, 0);
}
/// \return plane \a i of a mapped video frame.
inline const std::uint8_t *planeDataAt(const GstVideoFrame &frame, guint i) noexcept
{
    return static_cast<const std::uint8_t *>(GST_VIDEO_FRAME_PLANE_DATA(&frame, i));
}
/// \return the bytes from one row of plane \a i to the next.
inline int planeStrideAt(const GstVideoFrame &frame, guint i) noexcept
{
    return GST_VIDEO_FRAME_PLANE_STRIDE(&frame, i);
}
/// \brief Marks \a element as a sink (GST_ELEMENT_FLAG_SINK: the bin waits for its EOS).
inline void setSinkFlag(GstElement *element) noexcept
{
    GST_OBJECT_FLAG_SET(element, GST_ELEMENT_FLAG_SINK);
}
/// \return the parent class of \a klass as an element class.
inline GstElementClass *parentElementClass(gpointer klass) noexcept
{
    return GST_ELEMENT_CLASS(g_type_class_peek_parent(klass));
}
/// \return the buffer's presentation time (GST_CLOCK_TIME_NONE when it has none).
inline GstClockTime bufferPts(GstBuffer *buffer) noexcept
{
    return GST_BUFFER_PTS(buffer);
}
/// \brief Sets the buffer's presentation time and duration, ns.
inline void setBufferTimes(GstBuffer *buffer, GstClockTime pts, GstClockTime duration) noexcept
{
    GST_BUFFER_PTS(buffer) = pts;
    GST_BUFFER_DURATION(buffer) = duration;
}
/// \return whether \a t is a time (not GST_CLOCK_TIME_NONE).
inline bool isTime(GstClockTime t) noexcept
{
    return GST_CLOCK_TIME_IS_VALID(t);
}
/// \return the event's type.
inline GstEventType eventType(GstEvent *event) noexcept
{
    return GST_EVENT_TYPE(event);
}

/// \brief Commits an element's asynchronous state change (its READY to PAUSED, and on to PLAYING
/// when that is pending), as GstBaseSink commits its preroll: the state fields set under the
/// object lock; the caller then posts the state-changed messages and ASYNC_DONE.
/// \return the state before, the state committed and the pending one it was going to (PAUSED or
/// PLAYING); VOID_PENDING as \a committed when nothing was pending (a stop came first).
inline void commitAsyncState(GstElement *element, GstState &before, GstState &committed) noexcept
{
    GST_OBJECT_LOCK(element);
    before = GST_STATE(element);
    const GstState pending = GST_STATE_PENDING(element);
    committed = pending == GST_STATE_PAUSED || pending == GST_STATE_PLAYING
                    ? pending
                    : GST_STATE_VOID_PENDING;
    if (committed != GST_STATE_VOID_PENDING) {
        GST_STATE(element) = committed;
        GST_STATE_NEXT(element) = GST_STATE_VOID_PENDING;
        GST_STATE_PENDING(element) = GST_STATE_VOID_PENDING;
        GST_STATE_RETURN(element) = GST_STATE_CHANGE_SUCCESS;
    }
    GST_OBJECT_UNLOCK(element);
}
/// \brief Wakes the threads waiting in gst_element_get_state() on \a element.
inline void broadcastState(GstElement *element) noexcept
{
    GST_STATE_BROADCAST(element);
}

/// \brief Logs \a text at INFO in \a category for \a object (GST_INFO_OBJECT; shown with
/// GST_DEBUG=CATEGORY:4).
inline void logInfo(GstDebugCategory *category, gpointer object, const char *text,
                    const std::source_location &where = std::source_location::current()) noexcept
{
    gst_debug_log(category, GST_LEVEL_INFO, where.file_name(), where.function_name(),
                  static_cast<gint>(where.line()), G_OBJECT(object), "%s", text);
}

/// \brief Warns of a property id the class does not have (G_OBJECT_WARN_INVALID_PROPERTY_ID).
inline void warnInvalidProperty(GObject *object, guint id, GParamSpec *spec) noexcept
{
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, spec);
}

/// \brief Posts an error message of \a element on the bus (GST_ELEMENT_ERROR) with \a text and
/// \a debug (plain text, not formats; may be null), from the source line \a where.
/// \a domain: GST_CORE_ERROR, GST_RESOURCE_ERROR, ...
inline void postError(gpointer element, GQuark domain, gint code, const char *text,
                      const char *debug, const std::source_location &where) noexcept
{
    gst_element_message_full(GST_ELEMENT_CAST(element), GST_MESSAGE_ERROR, domain, code,
                             g_strdup(text), g_strdup(debug), where.file_name(),
                             where.function_name(), static_cast<gint>(where.line()));
}

#pragma GCC diagnostic pop

} // namespace depthtouch::gst
