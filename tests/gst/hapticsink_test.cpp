/// \file
/// \brief hapticsink (gst/, issue 62) through GStreamer's check library: the element loaded from
/// libgstdepthtouch.so (GST_PLUGIN_PATH, set by CTest), fed by a GstHarness. The simulated hand
/// presses into a flat depth plane and the element's contact force is k·penetration pointing out
/// of the surface; bad caps are refused; a bad method fails the start with a clear error; the
/// depth tags of a tag event are read; and the tag parser on its own.
///
/// Real time: the haptic task runs on its steady clock at 1 kHz, so the force is waited for (the
/// test's CTest time limit ends a wait that never comes); no assertion is made on timing.

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include <gst/check/gstharness.h>
#include <gst/gst.h>
#include <gtest/gtest.h>

#include "depth_tags.h"
#include "depthtouch/scene/depth_frame.h"
#include "gst_casts.h"
#include "haptic_session.h"

namespace depthtouch::gst {
namespace {

using namespace std::chrono_literals;

constexpr int kW = 32; ///< Depth frame width, pixels.
constexpr int kH = 24; ///< Depth frame height, pixels.

/// gst_init once; skips when the plugin is not found (GST_PLUGIN_PATH unset: not run by CTest).
class HapticSinkTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        static const bool ready = [] {
            gst_init(nullptr, nullptr);
            return true;
        }();
        ASSERT_TRUE(ready);
        GstElementFactory *f = gst_element_factory_find("hapticsink");
        if (f == nullptr)
            GTEST_SKIP() << "hapticsink not found: run through ctest (GST_PLUGIN_PATH)";
        gst_object_unref(f);
    }
};

/// \return a new hapticsink with sync off (the harness has no running clock to wait on).
GstElement *makeSink(const char *device, const char *options = "")
{
    GstElement *e = gst_element_factory_make("hapticsink", nullptr);
    EXPECT_NE(e, nullptr);
    g_object_set(asObject(e), "haptic-device", device, "haptic-device-options", options, "sync",
                 FALSE, nullptr);
    return e;
}

/// \return a GRAY16_LE buffer of kW×kH samples all \a nearness, at \a pts (ns).
GstBuffer *flatFrame(std::uint16_t nearness, GstClockTime pts)
{
    std::vector<std::uint16_t> samples(static_cast<std::size_t>(kW) * kH, nearness);
    const std::size_t bytes = samples.size() * sizeof(std::uint16_t);
    GstBuffer *b = gst_buffer_new_allocate(nullptr, bytes, nullptr);
    gst_buffer_fill(b, 0, samples.data(), bytes);
    setBufferTimes(b, pts, 33'333'333);
    return b;
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

const char *kGray16 = "video/x-raw, format=GRAY16_LE, width=32, height=24, framerate=30/1";

/// \return the z of a flat GRAY16_LE plane of nearness \a v in the default scene box, m:
/// −d/2 + (v/v_max)·d (docs/architecture.md §3 "Vertices").
double planeZ(std::uint16_t v)
{
    const scene::SceneBox box{};
    return -box.depth / 2.0 + (v / 65535.0) * box.depth;
}

/// Pushes \a n frames of the plane of nearness \a v from PTS \a first (ns), a frame period apart.
void pushPlane(GstHarness *h, std::uint16_t v, GstClockTime first, int n)
{
    for (int i = 0; i < n; ++i)
        ASSERT_EQ(
            gst_harness_push(h, flatFrame(v, first + static_cast<GstClockTime>(i) * 33'333'333)),
            GST_FLOW_OK);
}

/// What the element reads out once the simulated hand rests.
struct Rest {
    double fz = 0.0;    ///< contact-force-z, N.
    double hip = 0.0;   ///< hip-z, m (scene box).
    double force = 0.0; ///< contact-force, N.
};

/// Polls until the simulated hand rests on the plane at \a surface (m, scene box z) with its own
/// 2 N at stiffness \a k (N/m): F = k·(surface − HIP) within 0.05 N; \return the readout then
/// (the last one if it never rests: CTest's time limit ends a hang).
Rest restOn(GstElement *sink, double surface, double k)
{
    Rest r;
    for (int tries = 0; tries < 3000; ++tries) {
        std::this_thread::sleep_for(10ms);
        r = {doubleProperty(sink, "contact-force-z"), doubleProperty(sink, "hip-z"),
             doubleProperty(sink, "contact-force")};
        if (r.fz > 1.0 && std::abs(r.fz - k * (surface - r.hip)) < 0.05 &&
            std::abs(r.fz - 2.0) < 0.1)
            break;
    }
    return r;
}

TEST_F(HapticSinkTest, simulatedHandPressingAFlatPlaneFeelsKTimesPenetrationOutOfTheSurface)
{
    // GIVEN the simulated hand pressing with 2 N at a point of the plane, stiffness 1200 N/m
    const double k = 1200.0;
    GstElement *sink = makeSink("sim", "intent=press,force=2,x=0.005,y=-0.004,z=0.02");
    g_object_set(asObject(sink), "stiffness", k, nullptr);
    GstHarness *h = gst_harness_new_with_element(sink, "sink", nullptr);
    gst_harness_set_src_caps_str(h, kGray16);
    // WHEN a flat GRAY16_LE plane at a quarter of the nearness range is pushed, frame after frame
    const std::uint16_t v = 16384;
    pushPlane(h, v, 0, 5);
    // THEN once the hand rests on it, F = k·penetration along +z (out of the surface, toward the
    // viewer)
    const double surface = planeZ(v);
    const Rest r = restOn(sink, surface, k);
    const double penetration = surface - r.hip;
    EXPECT_GT(penetration, 0.0);
    EXPECT_GT(r.fz, 0.0) << "the force pushes the finger out of the surface";
    EXPECT_NEAR(r.fz, k * penetration, 0.05);
    EXPECT_NEAR(r.fz, 2.0, 0.1) << "at rest the hand is held with its own force";
    EXPECT_NEAR(r.force, r.fz, 0.05) << "the magnitude is the force along z on a flat plane";
    EXPECT_LE(r.force, 8.5) << "clamped to the device's maximum";
    EXPECT_GT(countProperty(sink, "updates"), 0u);
    EXPECT_GT(doubleProperty(sink, "servo-rate"), 0.0);
    // The trips' counts depend on the machine's timing (the watchdog's are missed deadlines), but
    // the watchdog's are some of them, and a hand resting on a still plane is never released by
    // the renderer.
    const std::uint64_t watchdog = countProperty(sink, "watchdog-trips");
    const std::uint64_t trips = countProperty(sink, "safety-trips");
    EXPECT_GE(trips, watchdog);
    EXPECT_EQ(trips - std::min(trips, watchdog), 0u) << "the renderer released a resting hand";
    gst_harness_teardown(h);
    gst_object_unref(sink);
}

TEST_F(HapticSinkTest, aFlushingSeekGoesOnWithTheNewSegmentsSurface)
{
    // GIVEN the simulated hand resting with 2 N on a plane at a quarter of the nearness range
    const double k = 1200.0;
    GstElement *sink = makeSink("sim", "intent=press,force=2,x=0.005,y=-0.004,z=0.02");
    g_object_set(asObject(sink), "stiffness", k, nullptr);
    GstHarness *h = gst_harness_new_with_element(sink, "sink", nullptr);
    gst_harness_set_src_caps_str(h, kGray16);
    pushPlane(h, 16384, 0, 5);
    const Rest before = restOn(sink, planeZ(16384), k);
    EXPECT_NEAR(before.fz, k * (planeZ(16384) - before.hip), 0.05);
    // WHEN the pipeline seeks to 10 s, flushing (the running time starts from 0 again), and the
    // new segment shows a plane 5 mm nearer
    EXPECT_TRUE(gst_harness_push_event(h, gst_event_new_flush_start()));
    EXPECT_TRUE(gst_harness_push_event(h, gst_event_new_flush_stop(TRUE)));
    GstSegment segment;
    gst_segment_init(&segment, GST_FORMAT_TIME);
    segment.start = 10 * GST_SECOND;
    segment.time = 10 * GST_SECOND;
    EXPECT_TRUE(gst_harness_push_event(h, gst_event_new_segment(&segment)));
    pushPlane(h, 24576, 10 * GST_SECOND, 5);
    // THEN the hand rests on the new plane: the new segment's frames reach the haptic task
    const double nearer = planeZ(24576);
    const Rest after = restOn(sink, nearer, k);
    EXPECT_GT(nearer - after.hip, 0.0);
    EXPECT_NEAR(after.fz, k * (nearer - after.hip), 0.05) << "F = k·penetration of the new plane";
    EXPECT_NEAR(after.fz, 2.0, 0.1);
    gst_harness_teardown(h);
    gst_object_unref(sink);
}

TEST_F(HapticSinkTest, rgbCapsAreRefused)
{
    GstElement *sink = makeSink("none");
    GstHarness *h = gst_harness_new_with_element(sink, "sink", nullptr);
    GstPad *pad = gst_element_get_static_pad(sink, "sink");
    GstCaps *rgb =
        gst_caps_from_string("video/x-raw, format=RGB, width=32, height=24, framerate=30/1");
    GstCaps *gray = gst_caps_from_string(kGray16);
    EXPECT_FALSE(gst_pad_query_accept_caps(pad, rgb));
    EXPECT_TRUE(gst_pad_query_accept_caps(pad, gray));
    // a buffer after a caps event of RGB is not negotiated (pushing a sticky event stores it on
    // the harness's pad whatever the element says: its return value tells nothing)
    gst_harness_push_event(h, gst_event_new_caps(gst_caps_ref(rgb)));
    GstSegment segment;
    gst_segment_init(&segment, GST_FORMAT_TIME);
    gst_harness_push_event(h, gst_event_new_segment(&segment));
    EXPECT_EQ(gst_harness_push(h, flatFrame(100, 0)), GST_FLOW_NOT_NEGOTIATED);
    gst_caps_unref(rgb);
    gst_caps_unref(gray);
    gst_object_unref(pad);
    gst_harness_teardown(h);
    gst_object_unref(sink);
}

/// \return the text of the first error on the bus of \a pipeline, or "".
std::string firstError(GstElement *pipeline)
{
    GstBus *bus = gst_element_get_bus(pipeline);
    GstMessage *m = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR);
    std::string text;
    if (m != nullptr) {
        GError *error = nullptr;
        gst_message_parse_error(m, &error, nullptr);
        text = error != nullptr ? error->message : "";
        g_clear_error(&error);
        gst_message_unref(m);
    }
    gst_object_unref(bus);
    return text;
}

/// \return the start of a pipeline with \a sink set to PAUSED, and its first error in \a error.
GstStateChangeReturn startAlone(GstElement *sink, std::string &error)
{
    GstElement *pipeline = gst_pipeline_new(nullptr);
    gst_bin_add(GST_BIN_CAST(pipeline), sink);
    const GstStateChangeReturn r = gst_element_set_state(pipeline, GST_STATE_PAUSED);
    error = firstError(pipeline);
    gst_element_set_state(pipeline, GST_STATE_NULL);
    gst_object_unref(pipeline);
    return r;
}

TEST_F(HapticSinkTest, aBadMethodFailsTheStartWithPlaysMessage)
{
    GstElement *sink = makeSink("sim");
    g_object_set(asObject(sink), "method", "bogus", nullptr);
    std::string error;
    EXPECT_EQ(startAlone(sink, error), GST_STATE_CHANGE_FAILURE);
    EXPECT_EQ(error, "hapticsink: method must be finger, ball, modified, proxy-graph or mesh-bvh");
}

TEST_F(HapticSinkTest, anUnknownDeviceFailsTheStartNamingTheBackends)
{
    std::string error;
    EXPECT_EQ(startAlone(makeSink("nope"), error), GST_STATE_CHANGE_FAILURE);
    EXPECT_NE(error.find("cannot open the haptic device 'nope'"), std::string::npos) << error;
    EXPECT_NE(error.find("sim"), std::string::npos) << error;
}

TEST_F(HapticSinkTest, depthPlanesComeFromTheStreamTagsElseFromTheProperties)
{
    GstElement *sink = makeSink("none");
    g_object_set(asObject(sink), "depth-near", 0.8, "depth-far", 3.0, nullptr);
    GstHarness *h = gst_harness_new_with_element(sink, "sink", nullptr);
    gst_harness_set_src_caps_str(h, kGray16);
    EXPECT_DOUBLE_EQ(doubleProperty(sink, "depth-near"), 0.8);
    EXPECT_DOUBLE_EQ(doubleProperty(sink, "depth-far"), 3.0);
    // matroskademux's form of the file's stream tags: extended comments KEY=value
    GstTagList *tags = gst_tag_list_new(GST_TAG_EXTENDED_COMMENT, "DEPTH_NEAR=0.5", nullptr);
    gst_tag_list_add(tags, GST_TAG_MERGE_APPEND, GST_TAG_EXTENDED_COMMENT, "DEPTH_FAR=1.5",
                     nullptr);
    gst_tag_list_set_scope(tags, GST_TAG_SCOPE_STREAM);
    EXPECT_TRUE(gst_harness_push_event(h, gst_event_new_tag(tags)));
    EXPECT_DOUBLE_EQ(doubleProperty(sink, "depth-near"), 0.5);
    EXPECT_DOUBLE_EQ(doubleProperty(sink, "depth-far"), 1.5);
    gst_harness_teardown(h);
    gst_object_unref(sink);
}

TEST(DepthTagsTest, readsTheDepthTagsByTheMediaSourcesRules)
{
    hal::DepthMetadata md;
    EXPECT_TRUE(applyDepthTag("DEPTH_NEAR=0.5", md));
    EXPECT_TRUE(applyDepthTag(" depth_far = 1.5 ", md));
    EXPECT_TRUE(applyDepthTag("DEPTH_MAPPING=inverse_z", md));
    EXPECT_TRUE(applyDepthTag("DEPTH_BITS=10", md));
    EXPECT_TRUE(applyDepthTag("DEPTH_OCCUPANCY=96", md));
    EXPECT_DOUBLE_EQ(md.nearMetres, 0.5);
    EXPECT_DOUBLE_EQ(md.farMetres, 1.5);
    EXPECT_EQ(md.mapping, "inverse_z");
    EXPECT_EQ(md.bits, 10);
    EXPECT_EQ(md.occupancy, 96u);
    // nonsense is ignored and keeps what was read
    EXPECT_FALSE(applyDepthTag("DEPTH_NEAR=-1", md));
    EXPECT_FALSE(applyDepthTag("DEPTH_FAR=inf", md));
    EXPECT_FALSE(applyDepthTag("DEPTH_BITS=17", md));
    EXPECT_FALSE(applyDepthTag("DEPTH_OCCUPANCY=1.5", md));
    EXPECT_FALSE(applyDepthTag("TITLE=depth", md));
    EXPECT_FALSE(applyDepthTag("no equals sign", md));
    EXPECT_DOUBLE_EQ(md.nearMetres, 0.5);
    EXPECT_EQ(md.bits, 10);
    // holes of a 10-bit stream: widened to 16 bits (96 << 6), narrowed to 8 (96 >> 2)
    EXPECT_EQ(holeBelowFor(md, scene::SampleFormat::Gray16), 96u << 6);
    EXPECT_EQ(holeBelowFor(md, scene::SampleFormat::Gray8), 24u);
    EXPECT_EQ(holeBelowFor(hal::DepthMetadata{}, scene::SampleFormat::Gray8), 0u);
}

TEST(HapticSettingsTest, defaultsAndChecksArePlays)
{
    const HapticSettings s;
    EXPECT_EQ(s.device, "falcon,none");
    EXPECT_EQ(s.method, "finger");
    EXPECT_DOUBLE_EQ(s.stiffness, 800.0);
    EXPECT_EQ(checkHapticSettings(s), "");
    HapticSettings soft = s;
    soft.stiffness = 50.0;
    EXPECT_EQ(checkHapticSettings(soft), "stiffness must be in [100, 3000] N/m");
}

} // namespace
} // namespace depthtouch::gst
