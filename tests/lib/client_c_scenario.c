/* A program of an integrator, in C99: it includes depthtouch/client.h alone (compiled as C, this
 * file proves the header is C) and plays a mock clip through libdepthtouch.so.0. Every wait is a
 * bounded poll for a state (at most kMaxWaits waits of 1 s for an event), never a judgement of
 * the wall clock. */
#include "client_c_scenario.h"

#include <stdio.h>
#include <string.h>

#include "depthtouch/client.h"

/* The most 1 s waits for one expected event (the player is slow under a sanitizer). */
enum { kMaxWaits = 60 };
/* The reply_userdata of the observer of pause and of the asynchronous seek. */
enum { kPauseObserver = 7, kSeekReply = 42 };

#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            snprintf(why, n, __VA_ARGS__);                                                         \
            dt_terminate_destroy(h);                                                               \
            return __LINE__;                                                                       \
        }                                                                                          \
    } while (0)

/* \return the first event of \a id (with \a userdata when it is not 0) within kMaxWaits waits, or
 * NULL. Other events are skipped. */
static dt_event *waitFor(dt_handle *h, dt_event_id id, uint64_t userdata)
{
    int waits = 0;
    while (waits < kMaxWaits) {
        dt_event *e = dt_wait_event(h, 1.0);
        if (e->event_id == DT_EVENT_NONE) {
            ++waits;
            continue;
        }
        if (e->event_id == id && (userdata == 0 || e->reply_userdata == userdata))
            return e;
    }
    return NULL;
}

/* \return the first PROPERTY_CHANGE of \a userdata whose flag is \a flag, or NULL. */
static dt_event *waitForFlag(dt_handle *h, uint64_t userdata, int flag)
{
    int tries = 0;
    while (tries < kMaxWaits) {
        dt_event *e = waitFor(h, DT_EVENT_PROPERTY_CHANGE, userdata);
        const dt_event_property *p = e != NULL ? (const dt_event_property *)e->data : NULL;
        if (p == NULL)
            return NULL;
        if (p->format == DT_FORMAT_FLAG && *(const int *)p->data == flag)
            return e;
        ++tries;
    }
    return NULL;
}

int dt_test_c_scenario(const char *clip, char *why, size_t n)
{
    dt_handle *h = dt_create();
    const char *loadfile[3];
    const char *pause[] = {"pause", NULL};
    const char *seek[] = {"seek", "0", "absolute", NULL};
    const char *unknown[] = {"no-such-command", NULL};
    const char *stop[] = {"stop", NULL};
    double timePos = -1.0;
    double later = -1.0;
    int flag = -1;
    int polls = 0;
    int rc = 0;
    char *state = NULL;
    dt_event *e = NULL;

    loadfile[0] = "loadfile";
    loadfile[1] = clip;
    loadfile[2] = NULL;
    CHECK(h != NULL, "dt_create returned NULL");
    CHECK(dt_client_api_version() == DT_CLIENT_API_VERSION, "API version %lu",
          dt_client_api_version());

    /* Options: play's table, its names, ranges and messages. */
    rc = dt_set_option_string(h, "no-such-option", "1");
    CHECK(rc == DT_ERROR_OPTION_NOT_FOUND, "unknown option: %d (%s)", rc, dt_error_string(rc));
    rc = dt_set_option_string(h, "stiffness", "5000");
    CHECK(rc == DT_ERROR_OPTION_FORMAT, "stiffness 5000: %d (%s)", rc, dt_error_string(rc));
    rc = dt_set_option_string(h, "stiffness", "stiff");
    CHECK(rc == DT_ERROR_OPTION_FORMAT, "stiffness stiff: %d", rc);
    CHECK(dt_set_option_string(h, "stiffness", "1200") == 0, "stiffness 1200");
    CHECK(dt_set_option_string(h, "display", "mock") == 0, "display");
    CHECK(dt_set_option_string(h, "haptic", "mock") == 0, "haptic");
    CHECK(dt_set_option_string(h, "source", "mock") == 0, "source");
    CHECK(dt_set_option_string(h, "decoder", "mock") == 0, "decoder");
    CHECK(dt_set_option_string(h, "no-audio", "yes") == 0, "no-audio");
    CHECK(dt_set_option_string(h, "loop", "yes") == 0, "loop");

    rc = dt_get_property_double(h, "time-pos", &timePos);
    CHECK(rc == DT_ERROR_UNINITIALIZED, "time-pos before initialize: %d", rc);
    CHECK(dt_observe_property(h, kPauseObserver, "pause", DT_FORMAT_FLAG) == 0, "observe pause");
    rc = dt_initialize(h);
    CHECK(rc == 0, "dt_initialize: %d (%s)", rc, dt_error_string(rc));
    CHECK(dt_initialize(h) == DT_ERROR_INVALID_PARAMETER, "a second dt_initialize");

    rc = dt_command(h, loadfile);
    CHECK(rc == 0, "loadfile: %d (%s)", rc, dt_error_string(rc));
    CHECK(waitFor(h, DT_EVENT_FILE_LOADED, 0) != NULL, "no file-loaded event");

    rc = dt_get_property_double(h, "stiffness", &later);
    CHECK(rc == 0 && later == 1200.0, "stiffness: %d, %g N/m", rc, later);
    rc = dt_command(h, pause);
    CHECK(rc == 0, "pause: %d (%s)", rc, dt_error_string(rc));
    CHECK(waitForFlag(h, kPauseObserver, 1) != NULL, "no property-change of pause to 1");
    CHECK(dt_get_property_flag(h, "pause", &flag) == 0 && flag == 1, "pause is %d", flag);
    CHECK(dt_get_property_string(h, "state", &state) == 0, "state as a string");
    CHECK(strcmp(state, "paused") == 0, "state is %s", state);
    dt_free(state);
    rc = dt_get_property_double(h, "state", &later);
    CHECK(rc == DT_ERROR_PROPERTY_FORMAT, "state as a double: %d", rc);
    rc = dt_get_property_double(h, "no-such-property", &later);
    CHECK(rc == DT_ERROR_PROPERTY_NOT_FOUND, "unknown property: %d", rc);
    rc = dt_command(h, unknown);
    CHECK(rc == DT_ERROR_INVALID_PARAMETER, "unknown command: %d", rc);
    rc = dt_get_property_double(h, "time-pos", &timePos);
    CHECK(rc == 0 && timePos >= 0.0, "time-pos: %d, %g s", rc, timePos);

    /* Playing again: time-pos moves on (a bounded poll, one event wait per try). */
    CHECK(dt_set_property_flag(h, "pause", 0) == 0, "set pause 0");
    CHECK(waitForFlag(h, kPauseObserver, 0) != NULL, "no property-change of pause to 0");
    later = timePos;
    for (polls = 0; polls < 1000 && later == timePos; ++polls) {
        dt_wait_event(h, 0.05);
        rc = dt_get_property_double(h, "time-pos", &later);
        CHECK(rc == 0, "time-pos while playing: %d", rc);
    }
    CHECK(later != timePos, "time-pos stayed at %g s", timePos);

    rc = dt_command_async(h, kSeekReply, seek);
    CHECK(rc == 0, "seek: %d", rc);
    e = waitFor(h, DT_EVENT_COMMAND_REPLY, kSeekReply);
    CHECK(e != NULL && e->error == 0, "seek's reply: %d", e != NULL ? e->error : 1);

    CHECK(dt_command(h, stop) == 0, "stop");
    e = waitFor(h, DT_EVENT_END_FILE, 0);
    CHECK(e != NULL, "no end-file event");
    CHECK(((const dt_event_end_file *)e->data)->reason == DT_END_FILE_REASON_STOP,
          "end-file reason %d", ((const dt_event_end_file *)e->data)->reason);
    dt_terminate_destroy(h);
    return 0;
}
