/// \file
/// \brief depthtouchsink (gst/, issue 62) through GStreamer's check library: the element loaded
/// from libgstdepthtouch.so (GST_PLUGIN_PATH, set by CTest), its two pads fed by two GstHarness
/// (the aggregator pattern: one per sink pad), on the headless display with the simulated hand.
/// A solid colour and a flat depth plane, frame after frame with the same running times: every
/// frame is paired (no depth unpaired or missing), presented, the haptic task runs and the hand
/// pressing the plane feels a force out of it (+z); EOS on both pads ends in EOS on the bus. The
/// picture follows the pipeline's clock (a GstTestClock held, then moved on). Bad
/// caps are refused; a bad method fails the start with play's message. And the pads' feed alone
/// (pad_feed.h): streams read in PTS order once each has a frame, the end, a flush.
///
/// Real time: the player presents at its frame clock and the haptic task runs at 1 kHz, so the
/// tests wait for what they check (the CTest time limit ends a wait that never comes); no
/// assertion is made on timing.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <unistd.h>

#include <gst/check/gstharness.h>
#include <gst/check/gsttestclock.h>
#include <gst/gst.h>
#include <gtest/gtest.h>

#include "gst_casts.h"
#include "pad_feed.h"

namespace depthtouch::gst {
namespace {

using namespace std::chrono_literals;

constexpr int kW = 64;                       ///< Frame width, pixels.
constexpr int kH = 48;                       ///< Frame height, pixels.
constexpr GstClockTime kPeriod = 33'333'333; ///< 30 fps, ns.
const char *kColorCaps = "video/x-raw, format=I420, width=64, height=48, framerate=30/1";
const char *kDepthCaps = "video/x-raw, format=GRAY16_LE, width=64, height=48, framerate=30/1";

class DepthTouchSinkTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        static const bool ready = [] {
            gst_init(nullptr, nullptr);
            return true;
        }();
        ASSERT_TRUE(ready);
        GstElementFactory *f = gst_element_factory_find("depthtouchsink");
        if (f == nullptr)
            GTEST_SKIP() << "depthtouchsink not found: run through ctest (GST_PLUGIN_PATH)";
        gst_object_unref(f);
    }
};

/// \return a buffer of \a bytes at \a pts.
GstBuffer *bufferOf(const std::vector<std::uint8_t> &bytes, GstClockTime pts)
{
    GstBuffer *b = gst_buffer_new_allocate(nullptr, bytes.size(), nullptr);
    gst_buffer_fill(b, 0, bytes.data(), bytes.size());
    setBufferTimes(b, pts, kPeriod);
    return b;
}

/// A solid I420 colour (Y 180, neutral chroma).
std::vector<std::uint8_t> solidColour()
{
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(kW * kH * 3 / 2), 128);
    std::fill_n(bytes.begin(), kW * kH, std::uint8_t{180});
    return bytes;
}

/// A flat GRAY16_LE plane at a quarter of the nearness range.
std::vector<std::uint8_t> flatDepth()
{
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(kW * kH * 2));
    for (std::size_t i = 0; i < bytes.size(); i += 2) {
        bytes[i] = 0x00; // 16384, little-endian
        bytes[i + 1] = 0x40;
    }
    return bytes;
}

double doubleProperty(GstElement *e, const char *name)
{
    double v = 0.0;
    g_object_get(asObject(e), name, &v, nullptr);
    return v;
}

std::uint64_t countProperty(GstElement *e, const char *name)
{
    guint64 v = 0;
    g_object_get(asObject(e), name, &v, nullptr);
    return v;
}

/// \return the text of \a m's error, or "".
std::string errorText(GstMessage *m)
{
    if (m == nullptr || GST_MESSAGE_TYPE(m) != GST_MESSAGE_ERROR)
        return "";
    GError *error = nullptr;
    gst_message_parse_error(m, &error, nullptr);
    std::string text = error != nullptr ? error->message : "";
    g_clear_error(&error);
    return text;
}

/// \return a new depthtouchsink on the headless display with the haptic device \a device
/// ("sim", "none"), or null when the plugin is not found.
GstElement *headlessSink(const char *device)
{
    GstElement *sink = gst_element_factory_make("depthtouchsink", nullptr);
    if (sink != nullptr)
        g_object_set(asObject(sink), "haptic-device", device, "display", "headless", nullptr);
    return sink;
}

/// \brief Runs the element of \a h (\a sink) on the system clock, its running time 0 now, as a
/// pipeline going to PLAYING does (a harness gives it a GstTestClock standing at 0: the player,
/// following the pipeline's clock, would wait at running time 0).
void runOnTheSystemClockFromNow(GstHarness *h, GstElement *sink)
{
    gst_harness_use_systemclock(h);
    GstClock *system = gst_system_clock_obtain();
    gst_element_set_base_time(sink, gst_clock_get_time(system));
    gst_object_unref(system);
}

/// \return why the headless display does not open here (an element alone to PAUSED), or "".
std::string displayMissing()
{
    GstElement *probe = gst_element_factory_make("depthtouchsink", nullptr);
    g_object_set(asObject(probe), "haptic-device", "none", "display", "headless", nullptr);
    GstBus *bus = gst_bus_new();
    gst_element_set_bus(probe, bus);
    std::string why;
    if (gst_element_set_state(probe, GST_STATE_PAUSED) == GST_STATE_CHANGE_FAILURE) {
        GstMessage *m = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR);
        why = m != nullptr ? errorText(m) : "the start failed";
        if (m != nullptr)
            gst_message_unref(m);
    }
    gst_element_set_state(probe, GST_STATE_NULL);
    gst_element_set_bus(probe, nullptr);
    gst_object_unref(bus);
    gst_object_unref(probe);
    return why;
}

TEST_F(DepthTouchSinkTest, pairsColourAndDepthByRunningTimeAndTheHandFeelsThePlane)
{
    const std::string socket = (std::filesystem::temp_directory_path() /
                                ("dt-gst-" + std::to_string(::getpid()) + ".sock"))
                                   .string();
    GstElement *sink = gst_element_factory_make("depthtouchsink", nullptr);
    ASSERT_NE(sink, nullptr);
    g_object_set(asObject(sink), "haptic-device", "sim", "haptic-device-options",
                 "intent=press,force=2,x=0.005,y=-0.004,z=0.02", "display", "headless", "control",
                 socket.c_str(), nullptr);
    if (const std::string why = displayMissing(); !why.empty()) {
        gst_object_unref(sink);
        GTEST_SKIP() << "no headless display here: " << why;
    }
    GstBus *bus = gst_bus_new();
    gst_element_set_bus(sink, bus);
    // GIVEN the two pads fed by a harness each (the element goes to PLAYING with the first)
    GstHarness *color = gst_harness_new_with_element(sink, "color", nullptr);
    GstHarness *depth = gst_harness_new_with_element(sink, "depth", nullptr);
    runOnTheSystemClockFromNow(color, sink);
    gst_harness_set_src_caps_str(color, kColorCaps);
    gst_harness_set_src_caps_str(depth, kDepthCaps);
    EXPECT_TRUE(std::filesystem::exists(socket)) << "play's control socket is up";
    // WHEN frames with the same running times go to both pads until the hand rests on the plane
    const std::vector<std::uint8_t> c = solidColour();
    const std::vector<std::uint8_t> d = flatDepth();
    std::uint64_t frames = 0; // pushed to each pad
    while (frames < 3000) {   // the pads wait for the player: ~30 frames a second
        const GstClockTime pts = frames * kPeriod;
        ASSERT_EQ(gst_harness_push(color, bufferOf(c, pts)), GST_FLOW_OK);
        ASSERT_EQ(gst_harness_push(depth, bufferOf(d, pts)), GST_FLOW_OK);
        ++frames;
        if (frames >= 30 && doubleProperty(sink, "contact-force-z") > 1.0)
            break;
    }
    const double fz = doubleProperty(sink, "contact-force-z");
    const double force = doubleProperty(sink, "contact-force");
    EXPECT_GT(fz, 1.0) << "the hand presses the plane: the force pushes it out (+z)";
    EXPECT_NEAR(force, fz, 0.1) << "a flat plane pushes straight up";
    EXPECT_TRUE(gst_harness_push_event(color, gst_event_new_eos()));
    EXPECT_TRUE(gst_harness_push_event(depth, gst_event_new_eos()));
    // THEN the player shows the last frame and the element posts EOS
    GstMessage *end = gst_bus_timed_pop_filtered(
        bus, GST_CLOCK_TIME_NONE, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
    ASSERT_NE(end, nullptr);
    EXPECT_EQ(GST_MESSAGE_TYPE(end), GST_MESSAGE_EOS) << errorText(end);
    gst_message_unref(end);
    // every colour frame was paired with the depth frame of its running time
    EXPECT_EQ(countProperty(sink, "frames-paired"), frames);
    EXPECT_EQ(countProperty(sink, "depth-unpaired"), 0u);
    EXPECT_EQ(countProperty(sink, "depth-missing"), 0u);
    EXPECT_GT(countProperty(sink, "frames-presented"), 0u);
    EXPECT_LE(countProperty(sink, "frames-presented"), frames);
    EXPECT_GT(countProperty(sink, "updates"), 0u);
    EXPECT_GT(doubleProperty(sink, "servo-rate"), 0.0);
    gboolean haptics = FALSE;
    g_object_get(asObject(sink), "haptics", &haptics, nullptr);
    EXPECT_TRUE(haptics);
    gst_harness_teardown(depth);
    gst_harness_teardown(color);
    EXPECT_FALSE(std::filesystem::exists(socket)) << "the socket goes with the player";
    gst_element_set_bus(sink, nullptr);
    gst_object_unref(bus);
    gst_object_unref(sink);
}

/// \return the "position" property (s) once \a done(position) holds, polled every 10 ms (the
/// readout is a tenth of a second old at most); the CTest time limit ends a wait that never comes.
template <class Done> double positionWhen(GstElement *sink, Done done)
{
    for (;;) {
        const double p = doubleProperty(sink, "position");
        if (done(p))
            return p;
        std::this_thread::sleep_for(10ms);
    }
}

/// Waits until the haptic task has run \a n more updates (the player's own time going on at its
/// 1 kHz servo rate, however busy the machine), polled every 10 ms.
void waitForUpdates(GstElement *sink, std::uint64_t n)
{
    const std::uint64_t from = countProperty(sink, "updates");
    while (countProperty(sink, "updates") < from + n)
        std::this_thread::sleep_for(10ms);
}

/// \return the "position" property (s) once it lies within \a lo..\a hi, or after \a updates
/// more haptic updates (the player's own time, at its 1 kHz servo rate however busy the machine)
/// if it never does: the caller's assertion then fails instead of hanging.
double positionWithin(GstElement *sink, double lo, double hi, std::uint64_t updates)
{
    const std::uint64_t until = countProperty(sink, "updates") + updates;
    for (;;) {
        const double p = doubleProperty(sink, "position");
        if ((p >= lo && p <= hi) || countProperty(sink, "updates") >= until)
            return p;
        std::this_thread::sleep_for(10ms);
    }
}

/// \brief depthtouchsink with the simulated hand on the headless display, a GstHarness on each
/// pad, on a GstTestClock (it moves only when told) standing at running time 1 s, I420 colour and
/// GRAY16_LE depth caps set; torn down by the destructor. Frames: solidColour(), flatDepth().
struct ClockedSink {
    GstElement *sink = headlessSink("sim");
    GstBus *bus = gst_bus_new();
    GstHarness *color = nullptr;
    GstHarness *depth = nullptr;
    GstTestClock *clock = nullptr;
    GstClockTime base = 0;
    const std::vector<std::uint8_t> c = solidColour();
    const std::vector<std::uint8_t> d = flatDepth();

    ClockedSink()
    {
        if (sink == nullptr) // the plugin is not found (SetUp() skips then)
            return;
        gst_element_set_bus(sink, bus);
        color = gst_harness_new_with_element(sink, "color", nullptr);
        depth = gst_harness_new_with_element(sink, "depth", nullptr);
        gst_harness_use_testclock(color);
        clock = gst_harness_get_testclock(color);
        base = gst_element_get_base_time(sink);
        setRunningTime(GST_SECOND);
        gst_harness_set_src_caps_str(color, kColorCaps);
        gst_harness_set_src_caps_str(depth, kDepthCaps);
    }
    ~ClockedSink()
    {
        if (clock != nullptr)
            gst_object_unref(clock);
        if (sink != nullptr) {
            gst_harness_teardown(depth);
            gst_harness_teardown(color);
            gst_element_set_bus(sink, nullptr);
            gst_object_unref(sink);
        }
        gst_object_unref(bus);
    }
    DT_DISABLE_COPY_AND_MOVE(ClockedSink)

    /// Moves the pipeline clock to running time \a t (ns) from the element's base time.
    void setRunningTime(GstClockTime t) { gst_test_clock_set_time(clock, base + t); }
    /// Pushes \a n frames to both pads from PTS \a first (ns), as the pads take them, until a
    /// push is refused or \a stop is set; then EOS on both when \a eos. \return whether all went.
    bool push(GstClockTime first, int n, bool eos, const std::atomic<bool> *stop = nullptr)
    {
        for (int i = 0; i < n && (stop == nullptr || !stop->load()); ++i) {
            const GstClockTime pts = first + static_cast<GstClockTime>(i) * kPeriod;
            if (gst_harness_push(color, bufferOf(c, pts)) != GST_FLOW_OK ||
                gst_harness_push(depth, bufferOf(d, pts)) != GST_FLOW_OK)
                return false;
        }
        if (eos) {
            gst_harness_push_event(color, gst_event_new_eos());
            gst_harness_push_event(depth, gst_event_new_eos());
        }
        return true;
    }
    /// Waits for the end on the bus: EXPECTs EOS, not an error.
    void expectEos()
    {
        GstMessage *end = gst_bus_timed_pop_filtered(
            bus, GST_CLOCK_TIME_NONE,
            static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
        ASSERT_NE(end, nullptr);
        EXPECT_EQ(GST_MESSAGE_TYPE(end), GST_MESSAGE_EOS) << errorText(end);
        gst_message_unref(end);
    }
};

TEST_F(DepthTouchSinkTest, thePictureFollowsThePipelineClockNotThePlayersOwn)
{
    if (const std::string why = displayMissing(); !why.empty())
        GTEST_SKIP() << "no headless display here: " << why;
    // GIVEN a pipeline clock that stands at running time 1 s, and 3 s of frames pushed as the pads
    // take them
    ClockedSink e;
    ASSERT_NE(e.sink, nullptr);
    ASSERT_NE(e.clock, nullptr);
    std::thread pusher([&] { (void)e.push(0, 90, true); });
    // WHEN the player has caught up with the clock and half a second of its own time passes (500
    // haptic updates)
    (void)positionWhen(e.sink, [](double p) { return p >= 0.9; });
    waitForUpdates(e.sink, 500);
    // THEN the frame on screen is the clock's: on its own clock the player would be 0.5 s on
    const double held = doubleProperty(e.sink, "position");
    EXPECT_NEAR(held, 1.0, 0.1) << "the picture waits for the pipeline's running time";
    // WHEN the pipeline clock jumps to 2.5 s THEN the picture goes there, not frame by frame
    e.setRunningTime(5 * GST_SECOND / 2);
    const double moved = positionWhen(e.sink, [](double p) { return p >= 2.4; });
    waitForUpdates(e.sink, 300);
    const double after = doubleProperty(e.sink, "position");
    std::printf("pipeline clock at 1 s: position %.3f s; moved to 2.5 s: %.3f s, 300 updates "
                "later %.3f s\n",
                held, moved, after);
    EXPECT_NEAR(after, 2.5, 0.1);
    // the rest plays out once the clock is past the end: EOS
    e.setRunningTime(10 * GST_SECOND);
    pusher.join();
    e.expectEos();
    EXPECT_EQ(countProperty(e.sink, "depth-unpaired"), 0u);
}

TEST_F(DepthTouchSinkTest, aFlushingSeekPlaysOnFromTheTargetOnTheNewRunningTime)
{
    if (const std::string why = displayMissing(); !why.empty())
        GTEST_SKIP() << "no headless display here: " << why;
    // GIVEN the first 2 s of a stream, played to running time 1 s
    ClockedSink e;
    ASSERT_NE(e.sink, nullptr);
    ASSERT_NE(e.clock, nullptr);
    std::atomic<bool> seeking{false};
    std::thread before([&] { (void)e.push(0, 60, false, &seeking); });
    (void)positionWhen(e.sink, [](double p) { return p >= 0.9; });
    waitForUpdates(e.sink, 100);
    const std::uint64_t presented = countProperty(e.sink, "frames-presented");
    // The renderer's releases (the watchdog's trips are missed deadlines: the machine's load)
    const auto releases = [&e] {
        return countProperty(e.sink, "safety-trips") - countProperty(e.sink, "watchdog-trips");
    };
    const std::uint64_t trips = releases();
    // WHEN the pipeline seeks to 10 s, flushing (GstBaseSink's order), with the clock at 1 s:
    // FLUSH_START and FLUSH_STOP(reset_time) on both pads, the base time moved so that the running
    // time starts again from 0, a SEGMENT from the target
    seeking.store(true);
    for (GstHarness *h : {e.color, e.depth})
        EXPECT_TRUE(gst_harness_push_event(h, gst_event_new_flush_start()));
    before.join(); // a push waiting on a full pad returns, flushing
    for (GstHarness *h : {e.color, e.depth})
        EXPECT_TRUE(gst_harness_push_event(h, gst_event_new_flush_stop(TRUE)));
    e.base += GST_SECOND;
    gst_element_set_base_time(e.sink, e.base);
    GstSegment segment;
    gst_segment_init(&segment, GST_FORMAT_TIME);
    segment.start = 10 * GST_SECOND;
    segment.time = 10 * GST_SECOND;
    segment.position = 10 * GST_SECOND;
    for (GstHarness *h : {e.color, e.depth})
        EXPECT_TRUE(gst_harness_push_event(h, gst_event_new_segment(&segment)));
    // and frames from the target come, the clock moving on to running time 0.5 s
    std::thread after([&] { (void)e.push(10 * GST_SECOND, 60, true); });
    e.setRunningTime(GST_SECOND / 2);
    // (5 s of the player's own time at most: before the fix the picture stood at 1.0 s for good)
    const double position = positionWithin(e.sink, 0.4, 0.6, 5000);
    const std::uint64_t presentedAfter = countProperty(e.sink, "frames-presented");
    std::printf("before the seek: position >= 0.9 s, %llu presented; after: position %.3f s, %llu "
                "presented, renderer releases %llu -> %llu\n",
                static_cast<unsigned long long>(presented), position,
                static_cast<unsigned long long>(presentedAfter),
                static_cast<unsigned long long>(trips),
                static_cast<unsigned long long>(releases()));
    // THEN the picture is the target's frame of running time 0.5 s, and it moves on
    EXPECT_NEAR(position, 0.5, 0.1);
    EXPECT_GT(presentedAfter, presented);
    if (HasFailure()) {
        // A player stuck before the seek takes no more frames: stopping the element ends the
        // pushes waiting on its full pads (a failure, not a hang).
        gst_element_set_state(e.sink, GST_STATE_NULL);
        after.join();
        return;
    }
    e.setRunningTime(10 * GST_SECOND);
    after.join();
    e.expectEos();
    EXPECT_EQ(countProperty(e.sink, "depth-unpaired"), 0u);
    EXPECT_EQ(releases(), trips) << "a seek re-seats, it does not trip";
}

TEST_F(DepthTouchSinkTest, aFlushEndsAPushWaitingOnAFullPad)
{
    if (const std::string why = displayMissing(); !why.empty())
        GTEST_SKIP() << "no headless display here: " << why;
    GstElement *sink = headlessSink("none");
    ASSERT_NE(sink, nullptr);
    GstHarness *color = gst_harness_new_with_element(sink, "color", nullptr);
    GstHarness *depth = gst_harness_new_with_element(sink, "depth", nullptr);
    gst_harness_set_src_caps_str(color, kColorCaps);
    gst_harness_set_src_caps_str(depth, kDepthCaps);
    // GIVEN colour frames and no depth: the player waits for depth, the colour pad's queue fills
    const std::vector<std::uint8_t> c = solidColour();
    std::atomic<int> pushed{0};
    std::atomic<bool> done{false};
    GstFlowReturn last = GST_FLOW_OK;
    std::thread pusher([&] {
        for (int i = 0; i < 100; ++i) {
            last = gst_harness_push(color, bufferOf(c, static_cast<GstClockTime>(i) * kPeriod));
            if (last != GST_FLOW_OK)
                break;
            pushed.fetch_add(1);
        }
        done.store(true);
    });
    // The queue's 4 frames; the 5th push waits. A poll, not a deadline: however slow the machine,
    // the loop ends once 4 are in or the pusher stopped (a push refused early fails below, no
    // hang).
    while (pushed.load() < 4 && !done.load())
        std::this_thread::sleep_for(10ms);
    // WHEN the pad is flushed THEN the waiting push returns, flushing
    EXPECT_TRUE(gst_harness_push_event(color, gst_event_new_flush_start()));
    pusher.join();
    EXPECT_EQ(last, GST_FLOW_FLUSHING);
    EXPECT_EQ(pushed.load(), 4);
    EXPECT_TRUE(gst_harness_push_event(color, gst_event_new_flush_stop(TRUE)));
    gst_harness_teardown(depth);
    gst_harness_teardown(color);
    gst_object_unref(sink);
}

TEST_F(DepthTouchSinkTest, capsOtherThanI420ColourAndGrayDepthAreRefused)
{
    GstElement *sink = gst_element_factory_make("depthtouchsink", nullptr);
    ASSERT_NE(sink, nullptr);
    GstPad *color = gst_element_get_static_pad(sink, "color");
    GstPad *depth = gst_element_get_static_pad(sink, "depth");
    GstCaps *rgb =
        gst_caps_from_string("video/x-raw, format=RGB, width=64, height=48, framerate=30/1");
    GstCaps *i420 = gst_caps_from_string(kColorCaps);
    GstCaps *gray16 = gst_caps_from_string(kDepthCaps);
    EXPECT_FALSE(gst_pad_query_accept_caps(color, rgb));
    EXPECT_FALSE(gst_pad_query_accept_caps(depth, rgb));
    EXPECT_FALSE(gst_pad_query_accept_caps(color, gray16)) << "colour is I420";
    EXPECT_TRUE(gst_pad_query_accept_caps(color, i420));
    EXPECT_TRUE(gst_pad_query_accept_caps(depth, gray16));
    EXPECT_TRUE(gst_pad_query_accept_caps(depth, i420)) << "an H.264 depth stream: its luma";
    for (GstCaps *caps : {rgb, i420, gray16})
        gst_caps_unref(caps);
    gst_object_unref(color);
    gst_object_unref(depth);
    gst_object_unref(sink);
}

TEST_F(DepthTouchSinkTest, aBadMethodFailsTheStartWithPlaysMessage)
{
    GstElement *sink = gst_element_factory_make("depthtouchsink", nullptr);
    ASSERT_NE(sink, nullptr);
    g_object_set(asObject(sink), "haptic-device", "sim", "display", "headless", "method", "bogus",
                 nullptr);
    GstElement *pipeline = gst_pipeline_new(nullptr);
    gst_bin_add(GST_BIN_CAST(pipeline), sink);
    EXPECT_EQ(gst_element_set_state(pipeline, GST_STATE_PAUSED), GST_STATE_CHANGE_FAILURE);
    GstBus *bus = gst_element_get_bus(pipeline);
    GstMessage *m = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR);
    EXPECT_EQ(errorText(m),
              "depthtouchsink: method must be finger, ball, modified, proxy-graph or mesh-bvh");
    if (m != nullptr)
        gst_message_unref(m);
    gst_object_unref(bus);
    gst_element_set_state(pipeline, GST_STATE_NULL);
    gst_object_unref(pipeline);
}

// ---- the feed alone ---------------------------------------------------------------------------

hal::StreamInfo streamOf(hal::PixelFormat format)
{
    hal::StreamInfo si;
    si.format = format;
    si.width = 4;
    si.height = 2;
    return si;
}

TEST(PadFeedTest, theSourceReadsBothStreamsInPtsOrderThenEnds)
{
    auto feed = std::make_shared<PadFeed>(4);
    feed->setStream(FeedStream::Color, streamOf(hal::PixelFormat::Yuv420p));
    hal::StreamInfo depth = streamOf(hal::PixelFormat::Gray8);
    depth.depth.nearMetres = 0.5;
    feed->setStream(FeedStream::Depth, depth);
    using hal::Pts;
    ASSERT_EQ(feed->push(FeedStream::Depth, {1, 2, 3, 4, 5, 6, 7, 8}, Pts(0)), PushResult::Ok);
    ASSERT_EQ(feed->push(FeedStream::Depth, {1, 2, 3, 4, 5, 6, 7, 8}, Pts(10)), PushResult::Ok);
    for (const Pts pts : {Pts(0), Pts(20)})
        ASSERT_EQ(feed->push(FeedStream::Color, std::vector<std::uint8_t>(12, 9), pts),
                  PushResult::Ok);
    PadMediaSource source(feed);
    ASSERT_TRUE(source.open("depthtouchsink:pads"));
    const hal::MediaInfo &info = source.info();
    ASSERT_EQ(info.streams.size(), 2u);
    EXPECT_EQ(info.streams[0].title, "color");
    EXPECT_EQ(info.streams[1].kind, hal::StreamKind::Depth);
    EXPECT_EQ(info.streams[1].codec, hal::CodecId::RawVideo);
    EXPECT_DOUBLE_EQ(info.streams[1].depth.nearMetres, 0.5);
    EXPECT_TRUE(info.seekable); // as the pipeline seeks (aFlushingSeekHoldsTheReader...)
    // the earliest first (colour before depth at a tie), once every stream has a frame or ended
    std::vector<std::pair<int, Pts>> read;
    for (int i = 0; i < 3; ++i) {
        auto p = source.readPacket();
        ASSERT_TRUE(p);
        read.emplace_back(p->streamIndex, p->pts);
    }
    EXPECT_EQ(read, (std::vector<std::pair<int, Pts>>{{0, Pts(0)}, {1, Pts(0)}, {1, Pts(10)}}));
    feed->endOfStream(FeedStream::Depth); // colour 20 waited for the depth stream until now
    auto last = source.readPacket();
    ASSERT_TRUE(last);
    EXPECT_EQ(last->streamIndex, 0);
    EXPECT_EQ(last->size, 12u);
    EXPECT_EQ(last->pts, Pts(20));
    feed->endOfStream(FeedStream::Color);
    auto end = source.readPacket();
    ASSERT_FALSE(end);
    EXPECT_EQ(end.error().code, Errc::EndOfStream);
}

TEST(PadFeedTest, aFlushDropsTheFramesAndUnblocksAFullPad)
{
    auto feed = std::make_shared<PadFeed>(1);
    feed->setStream(FeedStream::Depth, streamOf(hal::PixelFormat::Gray8));
    ASSERT_EQ(feed->push(FeedStream::Depth, std::vector<std::uint8_t>(8), hal::Pts(0)),
              PushResult::Ok);
    std::thread pusher([&] { // waits: the stream is full
        EXPECT_EQ(feed->push(FeedStream::Depth, std::vector<std::uint8_t>(8), hal::Pts(1)),
                  PushResult::Flushing);
    });
    EXPECT_TRUE(feed->flushStart(FeedStream::Depth, false));
    pusher.join();
    feed->flushStop(FeedStream::Depth);
    EXPECT_EQ(feed->push(FeedStream::Depth, std::vector<std::uint8_t>(8), hal::Pts(2)),
              PushResult::Ok);
    feed->shutdown();
    EXPECT_EQ(feed->push(FeedStream::Depth, std::vector<std::uint8_t>(8), hal::Pts(3)),
              PushResult::Closed);
    EXPECT_TRUE(feed->ended());
}

TEST(PadFeedTest, aFlushingSeekHoldsTheReaderUntilThePlayersSeekThenReadsTheNewTimeline)
{
    auto feed = std::make_shared<PadFeed>(4);
    feed->setStream(FeedStream::Depth, streamOf(hal::PixelFormat::Gray8));
    using hal::Pts;
    ASSERT_EQ(feed->push(FeedStream::Depth, std::vector<std::uint8_t>(8), Pts(5'000)),
              PushResult::Ok);
    feed->endOfStream(FeedStream::Color); // a depth-only input
    PadMediaSource source(feed);
    ASSERT_TRUE(source.open("depthtouchsink:pads"));
    ASSERT_TRUE(source.readPacket());
    // A seek the pipeline did not make (the control socket's): the decode thread cancels the read
    // waiting for the next frame (cancelRead(), before its seek), then the seek fails at the
    // source. The read goes on waiting and the frames go on: the input did not end.
    source.cancelRead();
    std::thread pusher([&] {
        EXPECT_EQ(feed->push(FeedStream::Depth, std::vector<std::uint8_t>(8), Pts(5'033)),
                  PushResult::Ok);
    });
    auto next = source.readPacket();
    pusher.join();
    ASSERT_TRUE(next) << "a cancelled read without a flush goes on waiting: " << next.error().what;
    EXPECT_EQ(next->pts, Pts(5'033));
    EXPECT_EQ(source.seek(Pts(0)).error().code, Errc::NotSupported);
    // GIVEN a flushing seek that the player will follow, and the new timeline's first frame
    EXPECT_TRUE(feed->flushStart(FeedStream::Depth, true));
    EXPECT_FALSE(feed->flushStart(FeedStream::Color, true)) << "one seek for both pads' flushes";
    feed->flushStop(FeedStream::Depth);
    feed->flushStop(FeedStream::Color);
    ASSERT_EQ(feed->push(FeedStream::Depth, std::vector<std::uint8_t>(8), Pts(0)), PushResult::Ok);
    // WHEN the player reads before its seek reached the source THEN the frame there is not read:
    // the read waits, and the seek's cancelRead() ends it (Timeout, as a read of a stalled input)
    source.cancelRead();
    auto early = source.readPacket();
    ASSERT_FALSE(early) << "no frame of the new timeline before the seek";
    EXPECT_EQ(early.error().code, Errc::Timeout);
    // AND after the player's seek the new timeline's frame is read, from its start
    ASSERT_TRUE(source.seek(Pts(0)));
    auto p = source.readPacket();
    ASSERT_TRUE(p);
    EXPECT_EQ(p->pts, Pts(0));
    source.close();
}

TEST(PadFeedTest, anInterruptedOpenSaysTimeout)
{
    auto feed = std::make_shared<PadFeed>();
    PadMediaSource source(feed);
    source.interrupt();
    auto r = source.open("depthtouchsink:pads");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, Errc::Timeout);
}

} // namespace
} // namespace depthtouch::gst
