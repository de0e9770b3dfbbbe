/// \file
/// \brief depthtouchsink, colour + depth into play's player: see depthtouch_sink.h.

#include "depthtouch_sink.h"

#include <array>
#include <chrono>
#include <memory>
#include <mutex>
#include <source_location>
#include <string>
#include <vector>

#include "depthtouch/options/option_range.h"
#include "depthtouch_sink_state.h"
#include "element_common.h"
#include "feed_player.h"
#include "gst_casts.h"
#include "pad_feed.h"

namespace depthtouch::gst {

namespace {

GstElementClass *parentClass = nullptr;
/// "depthtouchsink" (GST_DEBUG=depthtouchsink:4: the start, the caps, the tags, the run's counts).
GstDebugCategory *category = nullptr;

/// \brief Posts \a text as the element's error (prefixed with its name).
void fail(gpointer self, GQuark domain, gint code, const std::string &text,
          const std::source_location where = std::source_location::current())
{
    const std::string line = std::string(kDepthTouchSinkName) + ": " + text;
    postError(self, domain, code, line.c_str(), nullptr, where);
}

/// \return which stream \a pad carries.
FeedStream streamOf(SinkState &s, GstPad *pad)
{
    return pad == s.pads[1].pad ? FeedStream::Depth : FeedStream::Color;
}

PadState &padOf(SinkState &s, FeedStream f)
{
    return s.pads[static_cast<std::size_t>(f)];
}

// ---- the pads ---------------------------------------------------------------------------------

/// \return the format of the player's stream for caps \a info on \a f, Unknown when refused.
hal::PixelFormat formatOf(FeedStream f, const GstVideoInfo &info)
{
    const GstVideoFormat v = GST_VIDEO_INFO_FORMAT(&info);
    if (f == FeedStream::Color)
        return v == GST_VIDEO_FORMAT_I420 ? hal::PixelFormat::Yuv420p : hal::PixelFormat::Unknown;
    // An H.264 depth stream decodes to I420 (avdec_h264): its luma is the depth, as play reads it.
    if (v == GST_VIDEO_FORMAT_GRAY8 || v == GST_VIDEO_FORMAT_I420)
        return hal::PixelFormat::Gray8;
    if (v == GST_VIDEO_FORMAT_GRAY16_LE && G_BYTE_ORDER == G_LITTLE_ENDIAN)
        return hal::PixelFormat::Gray16;
    return hal::PixelFormat::Unknown;
}

/// \brief The stream of \a f as the feed describes it to the player. \pre s.mutex held.
void describeStream(SinkState &s, FeedStream f)
{
    const PadState &p = padOf(s, f);
    if (!p.configured || !s.feed)
        return;
    hal::StreamInfo si;
    si.format = p.format;
    si.width = GST_VIDEO_INFO_WIDTH(&p.info);
    si.height = GST_VIDEO_INFO_HEIGHT(&p.info);
    si.frameRate = hal::Rational{GST_VIDEO_INFO_FPS_N(&p.info), GST_VIDEO_INFO_FPS_D(&p.info)};
    if (f == FeedStream::Depth)
        si.depth = s.tags;
    s.feed->setStream(f, si);
}

gboolean setCaps(GstElement *self, SinkState &s, FeedStream f, GstCaps *caps)
{
    GstVideoInfo info;
    if (gst_video_info_from_caps(&info, caps) == FALSE) {
        fail(self, GST_STREAM_ERROR, GST_STREAM_ERROR_FORMAT, "caps are not raw video");
        return FALSE;
    }
    const hal::PixelFormat format = formatOf(f, info);
    if (format == hal::PixelFormat::Unknown) {
        fail(self, GST_STREAM_ERROR, GST_STREAM_ERROR_FORMAT,
             f == FeedStream::Color ? "color must be I420"
                                    : "depth must be GRAY8, GRAY16_LE or I420 (its luma)");
        return FALSE;
    }
    PadState &p = padOf(s, f);
    p.info = info;
    p.format = format;
    p.configured = true;
    describeStream(s, f);
    return TRUE;
}

void commitPreroll(GstElement *self, SinkState &s);

/// \brief Notes that the pad of \a f had its first frame or its EOS. \return whether the preroll
/// is now complete (both pads) and is to be committed (commitPreroll()). \pre s.mutex held.
bool prerolledNow(SinkState &s, FeedStream f)
{
    s.prerolled[static_cast<std::size_t>(f)] = true;
    if (!s.prerollPending || !s.prerolled[0] || !s.prerolled[1])
        return false;
    s.prerollPending = false;
    s.committing = true;
    return true;
}

gboolean padEvent(GstPad *pad, GstObject *parent, GstEvent *event)
{
    SinkState &s = stateOf(parent);
    gboolean result = TRUE;
    bool commit = false;
    {
        const std::lock_guard lock(s.mutex);
        const FeedStream f = streamOf(s, pad);
        PadState &p = padOf(s, f);
        switch (eventType(event)) {
        case GST_EVENT_CAPS: {
            GstCaps *caps = nullptr;
            gst_event_parse_caps(event, &caps);
            result = setCaps(asElement(parent), s, f, caps);
            break;
        }
        case GST_EVENT_SEGMENT:
            gst_event_copy_segment(event, &p.segment);
            break;
        case GST_EVENT_TAG:
            if (f == FeedStream::Depth && readDepthTagEvent(event, s.tags)) {
                logInfo(category, parent, describeDepthTags(s.tags).c_str());
                describeStream(s, f);
            }
            break;
        case GST_EVENT_FLUSH_START:
            // A flushing seek: the player seeks once for both pads (pad_feed.h).
            if (s.feed && s.feed->flushStart(f, s.player != nullptr) && s.player)
                s.player->seekForFlush();
            break;
        case GST_EVENT_FLUSH_STOP:
            gst_segment_init(&p.segment, GST_FORMAT_TIME);
            if (s.feed)
                s.feed->flushStop(f);
            break;
        case GST_EVENT_EOS:
            s.eosSeqnum = gst_event_get_seqnum(event);
            if (s.feed)
                s.feed->endOfStream(f);
            commit = prerolledNow(s, f);
            break;
        default:
            break;
        }
    }
    gst_event_unref(event);
    if (commit)
        commitPreroll(asElement(parent), s);
    return result;
}

GstFlowReturn chain(GstPad *pad, GstObject *parent, GstBuffer *buffer)
{
    SinkState &s = stateOf(parent);
    std::shared_ptr<PadFeed> feed;
    FeedStream f = FeedStream::Color;
    std::vector<std::uint8_t> bytes;
    GstClockTime running = 0;
    {
        const std::lock_guard lock(s.mutex);
        f = streamOf(s, pad);
        const PadState &p = padOf(s, f);
        feed = s.feed;
        if (!p.configured || !feed) {
            gst_buffer_unref(buffer);
            return GST_FLOW_NOT_NEGOTIATED;
        }
        if (const GstClockTime pts = bufferPts(buffer); isTime(pts)) {
            const GstClockTime rt = gst_segment_to_running_time(&p.segment, GST_FORMAT_TIME, pts);
            if (isTime(rt))
                running = rt;
        }
        bytes = packVideoFrame(p.info, p.format, buffer);
    }
    gst_buffer_unref(buffer);
    if (bytes.empty()) {
        fail(parent, GST_STREAM_ERROR, GST_STREAM_ERROR_FAILED, "cannot map a buffer");
        return GST_FLOW_ERROR;
    }
    // Outside the lock: waits while the player's queue is full.
    const PushResult r =
        feed->push(f, std::move(bytes), hal::Pts(static_cast<std::int64_t>(running)));
    if (r != PushResult::Ok)
        return GST_FLOW_FLUSHING;
    bool commit = false;
    {
        const std::lock_guard lock(s.mutex);
        commit = prerolledNow(s, f);
    }
    if (commit)
        commitPreroll(asElement(parent), s);
    return GST_FLOW_OK;
}

// ---- states -----------------------------------------------------------------------------------

/// \return the pipeline's clock as the player's master clock: while \a self plays, the running time
/// now, which the pads stamp their frames with (chain()), so the picture and the haptic task's
/// time follow the pipeline (a pipeline clock that is an audio sink's drifts from the steady one).
std::function<playback::MasterClock()> pipelineClock(GstElement *self)
{
    return [self]() {
        playback::MasterClock c;
        GST_OBJECT_LOCK(self);
        const bool playing = GST_STATE(self) == GST_STATE_PLAYING;
        GST_OBJECT_UNLOCK(self);
        GstClockTime running = 0;
        if (playing && runningTimeNow(self, c.at, running)) {
            c.running = true;
            c.mediaTime = static_cast<double>(running) * 1e-9;
        }
        return c;
    };
}

/// READY to PAUSED: the feed and the player (display, device, Playback). \return FALSE on failure
/// (posted).
gboolean openPlayer(GstElement *self, SinkState &s)
{
    const std::lock_guard lock(s.mutex);
    s.feed = std::make_shared<PadFeed>();
    s.tags = {};
    for (PadState &p : s.pads) {
        p.configured = false;
        gst_segment_init(&p.segment, GST_FORMAT_TIME);
    }
    std::string why;
    s.player = FeedPlayer::open(s.settings, s.feed, pipelineClock(self), why);
    if (!s.player) {
        s.feed.reset();
        fail(self, GST_RESOURCE_ERROR, GST_RESOURCE_ERROR_SETTINGS, why);
        return FALSE;
    }
    s.started = false;
    s.prerolled = {};
    s.prerollPending = s.async;
    logInfo(category, self,
            ("haptic device '" + s.player->deviceName() + "', display '" + s.player->displayName() +
             "', method " + s.settings.haptic.method + ", stiffness " +
             options::OptionRange::number(s.settings.haptic.stiffness) + " N/m")
                .c_str());
    return TRUE;
}

/// Called on the player's thread when it stopped by itself: EOS (the stream shown) or an error.
void playerEnded(GstElement *self, const std::string &failure)
{
    if (!failure.empty()) {
        fail(self, GST_STREAM_ERROR, GST_STREAM_ERROR_FAILED, "the player failed: " + failure);
        return;
    }
    SinkState &s = stateOf(self);
    guint32 seqnum = 0;
    {
        const std::lock_guard lock(s.mutex);
        seqnum = s.eosSeqnum;
    }
    GstMessage *eos = gst_message_new_eos(asGstObject(self));
    if (seqnum != 0)
        gst_message_set_seqnum(eos, seqnum);
    gst_element_post_message(self, eos);
}

/// PAUSED to PLAYING: the player's loop the first time, else it resumes.
gboolean play(GstElement *self, SinkState &s)
{
    const std::lock_guard lock(s.mutex);
    if (!s.player)
        return TRUE;
    s.player->setPaused(false);
    if (s.started)
        return TRUE;
    const std::string bad =
        s.player->start([self](const std::string &failure) { playerEnded(self, failure); });
    if (!bad.empty()) {
        fail(self, GST_RESOURCE_ERROR, GST_RESOURCE_ERROR_OPEN_READ_WRITE, bad);
        return FALSE;
    }
    s.started = true;
    return TRUE;
}

/// \brief commitPreroll()'s messages: the state changes (and PLAYING's start), ASYNC_DONE.
void postCommitted(GstElement *self, SinkState &s, GstState before, GstState committed)
{
    if (before == GST_STATE_READY)
        gst_element_post_message(
            self, gst_message_new_state_changed(
                      asGstObject(self), GST_STATE_READY, GST_STATE_PAUSED,
                      committed == GST_STATE_PLAYING ? GST_STATE_PLAYING : GST_STATE_VOID_PENDING));
    if (committed == GST_STATE_PLAYING) {
        if (play(self, s) == FALSE)
            return;
        gst_element_post_message(
            self, gst_message_new_state_changed(asGstObject(self), GST_STATE_PAUSED,
                                                GST_STATE_PLAYING, GST_STATE_VOID_PENDING));
    }
    gst_element_post_message(self,
                             gst_message_new_async_done(asGstObject(self), GST_CLOCK_TIME_NONE));
    broadcastState(self);
}

/// \brief The preroll is complete (both pads have a frame or ended): commits the asynchronous
/// READY to PAUSED, and goes on to PLAYING when that is pending (the player starts), posting the
/// state changes and ASYNC_DONE as GstBaseSink does. Called without s.mutex.
void commitPreroll(GstElement *self, SinkState &s)
{
    GstState before = GST_STATE_VOID_PENDING;
    GstState committed = GST_STATE_VOID_PENDING;
    commitAsyncState(self, before, committed);
    if (committed != GST_STATE_VOID_PENDING)
        postCommitted(self, s, before, committed);
    {
        const std::lock_guard lock(s.mutex);
        s.committing = false;
    }
    s.committed.notify_all();
}

/// PAUSED to READY: the player stopped and closed, with its counts logged.
void closePlayer(GstElement *self, SinkState &s)
{
    std::unique_ptr<FeedPlayer> player;
    {
        const std::lock_guard lock(s.mutex);
        player = std::move(s.player);
        s.feed.reset();
        s.started = false;
    }
    if (!player)
        return;
    const PlayerReadout r = player->readout();
    player.reset(); // joins its thread (which may post): outside the lock
    const std::string line =
        "stopped: " + std::to_string(r.framesPaired) + " pairs, " +
        std::to_string(r.framesPresented) + " presented, " + std::to_string(r.depthUnpaired) +
        " depth unpaired; " + std::to_string(r.hapticUpdates) + " haptic updates, max force " +
        options::OptionRange::number(r.maxForce) + " N, " + std::to_string(r.safetyTrips) +
        " safety trips (" + std::to_string(r.watchdogTrips) + " by the watchdog), " +
        std::to_string(r.pageFaults) + " page faults after warm-up";
    logInfo(category, self, line.c_str());
}

/// \brief Waits (at most a second) until a streaming thread committing the preroll has posted
/// its messages: the pipeline's PAUSED (that thread's) then comes before its PLAYING (the
/// caller's), which it needs to forward the EOS at the end.
void waitForCommit(SinkState &s)
{
    std::unique_lock lock(s.mutex);
    s.committed.wait_for(lock, std::chrono::seconds(1), [&s] { return !s.committing; });
}

bool async(SinkState &s)
{
    const std::lock_guard lock(s.mutex);
    return s.async;
}

bool prerollPending(SinkState &s)
{
    const std::lock_guard lock(s.mutex);
    return s.prerollPending;
}

GstStateChangeReturn changeState(GstElement *element, GstStateChange transition)
{
    SinkState &s = stateOf(element);
    switch (transition) {
    case GST_STATE_CHANGE_READY_TO_PAUSED:
        if (openPlayer(element, s) == FALSE)
            return GST_STATE_CHANGE_FAILURE;
        if (async(s))
            gst_element_post_message(element, gst_message_new_async_start(asGstObject(element)));
        break;
    case GST_STATE_CHANGE_PAUSED_TO_PLAYING:
        waitForCommit(s);
        if (play(element, s) == FALSE)
            return GST_STATE_CHANGE_FAILURE;
        break;
    case GST_STATE_CHANGE_PLAYING_TO_PAUSED: {
        const std::lock_guard lock(s.mutex);
        if (s.player)
            s.player->setPaused(true);
        break;
    }
    case GST_STATE_CHANGE_PAUSED_TO_READY: {
        // Unblock the pads before their deactivation takes their stream locks.
        const std::lock_guard lock(s.mutex);
        s.prerollPending = false;
        if (s.feed)
            s.feed->shutdown();
        break;
    }
    default:
        break;
    }
    const GstStateChangeReturn r = parentClass->change_state(element, transition);
    if (transition == GST_STATE_CHANGE_PAUSED_TO_READY)
        closePlayer(element, s);
    // Prerolling: PAUSED comes with the first frames (commitPreroll()), unless it came already.
    if (transition == GST_STATE_CHANGE_READY_TO_PAUSED && r == GST_STATE_CHANGE_SUCCESS &&
        async(s) && prerollPending(s))
        return GST_STATE_CHANGE_ASYNC;
    return r;
}

// ---- the type ---------------------------------------------------------------------------------

void finalize(GObject *object)
{
    auto *self = reinterpret_cast<DepthTouchSink *>(object);
    delete self->state;
    self->state = nullptr;
    asObjectClass(parentClass)->finalize(object);
}

void instanceInit(GTypeInstance *instance, gpointer klass)
{
    auto *self = reinterpret_cast<DepthTouchSink *>(instance);
    self->state = new SinkState();
    GstElement *element = asElement(instance);
    GstElementClass *ec = asElementClass(klass);
    const std::array<const char *, 2> names{"color", "depth"};
    for (std::size_t i = 0; i < names.size(); ++i) {
        GstPad *pad =
            gst_pad_new_from_template(gst_element_class_get_pad_template(ec, names[i]), names[i]);
        gst_pad_set_chain_function(pad, chain);
        gst_pad_set_event_function(pad, padEvent);
        self->state->pads[i].pad = pad;
        gst_element_add_pad(element, pad);
    }
    setSinkFlag(element);
}

/// Adds the always sink pad template \a name with \a caps.
void addTemplate(GstElementClass *ec, const char *name, const char *caps)
{
    GstCaps *c = gst_caps_from_string(caps);
    gst_element_class_add_pad_template(ec,
                                       gst_pad_template_new(name, GST_PAD_SINK, GST_PAD_ALWAYS, c));
    gst_caps_unref(c);
}

void classInit(gpointer klass, gpointer)
{
    parentClass = parentElementClass(klass);
    category = _gst_debug_category_new(kDepthTouchSinkName, 0, "DepthTouch colour + depth sink");
    GObjectClass *oc = asObjectClass(klass);
    oc->set_property = setSinkProperty;
    oc->get_property = getSinkProperty;
    oc->finalize = finalize;
    installSinkProperties(oc);

    GstElementClass *ec = asElementClass(klass);
    gst_element_class_set_static_metadata(
        ec, "DepthTouch sink", "Sink/Video/Haptic",
        "Plays a colour + depth video as depthtouch play does: pairs colour and depth by running "
        "time, draws the stereo view and runs the 1 kHz haptic task on the depth",
        "DepthTouch");
    addTemplate(ec, "color",
                "video/x-raw, format=(string)I420, width=(int)[ 2, 8192 ], "
                "height=(int)[ 2, 8192 ], framerate=(fraction)[ 0/1, 2147483647/1 ]");
    addTemplate(ec, "depth",
                "video/x-raw, format=(string){ GRAY8, GRAY16_LE, I420 }, width=(int)[ 2, 8192 ], "
                "height=(int)[ 2, 8192 ], framerate=(fraction)[ 0/1, 2147483647/1 ]");
    ec->change_state = changeState;
}

} // namespace

GType depthTouchSinkGetType()
{
    static const GType type = g_type_register_static_simple(
        GST_TYPE_ELEMENT, "GstDepthTouchSink", sizeof(DepthTouchSinkClass), classInit,
        sizeof(DepthTouchSink), instanceInit, static_cast<GTypeFlags>(0));
    return type;
}

} // namespace depthtouch::gst
