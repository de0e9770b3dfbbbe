/* The render API's example of docs/embedding.md ("Render API"), compiled as C11 and run by
 * render_gl_test.cpp: the host makes its EGL context current, the player draws for it. */
#include "render_gl_example.h"

#include <stdatomic.h>
#include <stddef.h>

#include <depthtouch/client.h>
#include <depthtouch/render_gl.h>

static atomic_int frames_ready; /* set on the player's render thread */

static void on_frame_ready(void *userdata)
{
    (void)userdata;
    atomic_fetch_add(&frames_ready, 1); /* a real host posts a redraw to its main loop */
}

int dt_example_render(const char *url, const char *const *options, unsigned fbo, int width,
                      int height, int frames)
{
    dt_handle *h = dt_create();
    if (!h)
        return DT_ERROR_NOMEM;
    dt_set_option_string(h, "haptic", "sim"); /* play --haptic sim */
    for (int i = 0; options[i] && options[i + 1]; i += 2)
        dt_set_option_string(h, options[i], options[i + 1]);
    dt_render_param params[] = {{DT_RENDER_PARAM_API_TYPE, DT_RENDER_API_TYPE_OPENGL},
                                {DT_RENDER_PARAM_INVALID, NULL}};
    dt_render_context *render = NULL;
    int rc = dt_render_context_create(&render, h, params); /* before dt_initialize() */
    if (rc >= 0) {
        dt_render_context_set_update_callback(render, on_frame_ready, NULL);
        rc = dt_initialize(h); /* no display of its own: it draws for render */
    }
    const char *load[] = {"loadfile", url, NULL};
    if (rc >= 0)
        rc = dt_command(h, load);
    int drawn = 0;
    int ready = 0;
    while (rc >= 0 && drawn < frames) {
        dt_event *e = dt_wait_event(h, 0.01); /* the host's loop: events, then redraws */
        if (e->event_id == DT_EVENT_SHUTDOWN || e->event_id == DT_EVENT_END_FILE)
            break;
        const int n = atomic_exchange(&frames_ready, 0);
        if (n == 0)
            continue;
        ready += n;
        rc = dt_render_context_render(render, fbo, width, height, 0);
        drawn++;
    }
    dt_render_context_free(render); /* the host's context still current */
    dt_terminate_destroy(h);
    if (rc < 0)
        return rc;
    return drawn < frames ? DT_ERROR_GENERIC : ready;
}
