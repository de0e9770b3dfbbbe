#pragma once
/// \file
/// \brief depthtouchsink's instance and its state (depthtouch_sink.cpp: pads and states;
/// depthtouch_sink_properties.cpp: properties). Internal to the plugin.
/// Thread-safety: every SinkState field under its mutex.

#include <array>
#include <condition_variable>
#include <memory>
#include <mutex>

#include <gst/gst.h>
#include <gst/video/video.h>

#include "depthtouch/hal/media_source.h"
#include "feed_player.h"
#include "pad_feed.h"

namespace depthtouch::gst {

/// One sink pad's negotiated format and segment. Under SinkState::mutex.
struct PadState {
    GstPad *pad = nullptr; ///< Owned by the element.
    GstVideoInfo info{};
    bool configured = false;
    hal::PixelFormat format = hal::PixelFormat::Unknown;
    GstSegment segment{};
};

/// The element's own state (C++), owned by the instance; every field under mutex.
struct SinkState {
    std::mutex mutex;
    PlayerSettings settings;
    hal::DepthMetadata tags; ///< The depth stream's tags so far.
    std::array<PadState, 2> pads;
    std::shared_ptr<PadFeed> feed;      ///< Between READY to PAUSED and PAUSED to READY.
    std::unique_ptr<FeedPlayer> player; ///< Likewise.
    bool started = false;               ///< The player's loop runs (first PLAYING).
    bool async = true;                  ///< Preroll: READY to PAUSED completes on the frames.
    bool prerollPending = false;        ///< READY to PAUSED returned ASYNC, not committed yet.
    std::array<bool, 2> prerolled{};    ///< Each pad had its first frame or its EOS.
    /// A streaming thread is committing the preroll (commitPreroll()): PAUSED to PLAYING waits
    /// for it (committed), so that the pipeline's PLAYING is posted after its PAUSED.
    bool committing = false;
    std::condition_variable committed;
    guint32 eosSeqnum = 0;
};

/// The GObject instance: the GstElement and its C++ state (made in instance init, freed in
/// finalize).
struct DepthTouchSink {
    GstElement parent;
    SinkState *state;
};

struct DepthTouchSinkClass {
    GstElementClass parentClass;
};

/// The property ids: the four haptic settings first, in element_common.h's order; the read-only
/// readouts last, kPropFramesPaired to kPropHaptics.
enum Property : guint {
    kPropZero,
    kPropDevice, // the four HapticProperty in order
    kPropDeviceOptions,
    kPropStiffness,
    kPropMethod,
    kPropDisplay,
    kPropDisplayOptions,
    kPropControl,
    kPropAsync,
    kPropFramesPaired,
    kPropFramesPresented,
    kPropDepthUnpaired,
    kPropDepthMissing,
    kPropUpdates,
    kPropServoRate,
    kPropContactForce,
    kPropContactForceZ,
    kPropPosition,
    kPropSafetyTrips,
    kPropWatchdogTrips,
    kPropHaptics,
};

/// \return the state of the depthtouchsink instance \a self.
inline SinkState &stateOf(gpointer self)
{
    return *static_cast<DepthTouchSink *>(self)->state;
}

/// \name Properties (depthtouch_sink_properties.cpp)
///@{
void installSinkProperties(GObjectClass *oc);
void setSinkProperty(GObject *object, guint id, const GValue *value, GParamSpec *spec);
void getSinkProperty(GObject *object, guint id, GValue *value, GParamSpec *spec);
///@}

} // namespace depthtouch::gst
