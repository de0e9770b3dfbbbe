/// \file
/// \brief libdepthtouch on the headless EGL display (label gl): a handle draws a mock clip with
/// the GL renderer on its own render thread inside the host's process, the simulated hand presses
/// it (haptic-force and contact read through the API), it seeks and ends. Bounded polls for a
/// state, no judgement by the wall clock.

#include <cstdint>

#include <gtest/gtest.h>

#include "depthtouch/client.h"

namespace {

/// At most this many waits of 50 ms for a state (the player is slow under a sanitizer).
constexpr int kMaxPolls = 1200;

/// \return the first event of \a id within kMaxPolls waits, or nullptr.
dt_event *waitFor(dt_handle *h, dt_event_id id)
{
    for (int i = 0; i < kMaxPolls; ++i) {
        dt_event *e = dt_wait_event(h, 0.05);
        if (e->event_id == id)
            return e;
    }
    return nullptr;
}

TEST(ClientGlTest, playsOnTheHeadlessDisplayAndTheSimulatedHandTouches)
{
    dt_handle *h = dt_create();
    ASSERT_NE(h, nullptr);
    const char *options[][2] = {
        {"display", "headless"}, {"haptic", "sim"},   {"haptic-options", "intent=press"},
        {"source", "mock"},      {"decoder", "mock"}, {"no-audio", "yes"},
        {"loop", "yes"}};
    for (const auto &o : options)
        ASSERT_EQ(dt_set_option_string(h, o[0], o[1]), 0) << o[0];
    const int rc = dt_initialize(h);
    if (rc == DT_ERROR_VO_INIT_FAILED) {
        dt_terminate_destroy(h);
        GTEST_SKIP() << "no headless EGL display here";
    }
    ASSERT_EQ(rc, 0) << dt_error_string(rc);
    const char *load[] = {"loadfile", "mock://clip?frames=60&fps=30", nullptr};
    ASSERT_EQ(dt_command(h, load), 0);
    ASSERT_NE(waitFor(h, DT_EVENT_FILE_LOADED), nullptr);

    double timePos = -1.0;
    for (int i = 0; i < kMaxPolls && timePos <= 0.0; ++i) {
        dt_wait_event(h, 0.05);
        ASSERT_EQ(dt_get_property_double(h, "time-pos", &timePos), 0);
    }
    EXPECT_GT(timePos, 0.0);
    int contact = 0;
    double force = 0.0;
    for (int i = 0; i < kMaxPolls && contact == 0; ++i) {
        dt_wait_event(h, 0.05);
        ASSERT_EQ(dt_get_property_flag(h, "contact", &contact), 0);
    }
    EXPECT_EQ(contact, 1) << "the simulated hand never touched";
    EXPECT_EQ(dt_get_property_double(h, "haptic-force", &force), 0);
    EXPECT_GE(force, 0.0);

    const char *seek[] = {"seek", "0", "absolute", nullptr};
    EXPECT_EQ(dt_command(h, seek), 0);
    EXPECT_NE(waitFor(h, DT_EVENT_SEEK), nullptr);
    const char *stop[] = {"stop", nullptr};
    EXPECT_EQ(dt_command(h, stop), 0);
    dt_event *e = waitFor(h, DT_EVENT_END_FILE);
    ASSERT_NE(e, nullptr);
    EXPECT_EQ(static_cast<const dt_event_end_file *>(e->data)->reason, DT_END_FILE_REASON_STOP);
    dt_terminate_destroy(h);
}

} // namespace
