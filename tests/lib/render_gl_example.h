/* The render API's example of docs/embedding.md (render_gl_example.c), run by render_gl_test.cpp.
 * C and C++ compatible. */
#ifndef DT_TESTS_RENDER_GL_EXAMPLE_H
#define DT_TESTS_RENDER_GL_EXAMPLE_H

#ifdef __cplusplus
extern "C" {
#endif

/* Plays \a url with the simulated hand, the options \a options (name, value, ..., NULL) set first,
 * and draws the newest frame into the framebuffer object \a fbo (\a width x \a height) of the EGL
 * context current on this thread, each time the frame-ready callback says one is there, until
 * \a frames were drawn. \return the number of frame-ready callbacks (>= \a frames), or a negative
 * dt_error code. */
int dt_example_render(const char *url, const char *const *options, unsigned fbo, int width,
                      int height, int frames);

#ifdef __cplusplus
}
#endif

#endif
