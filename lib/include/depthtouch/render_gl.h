/*
 * depthtouch/render_gl.h: the render API of libdepthtouch (libdepthtouch.so.0): the player's
 * stereo view (the picture, the on-screen display and the avatar) drawn into a framebuffer object
 * of the host program's own OpenGL ES context, instead of a display the library opens itself.
 *
 * Modelled on libmpv's render API (mpv's include/mpv/render.h and render_gl.h, mpv 0.38:
 * mpv_render_context_create(), mpv_render_context_render() with MPV_RENDER_PARAM_OPENGL_FBO,
 * mpv_render_context_set_update_callback(), mpv_render_context_free()). See docs/embedding.md,
 * "Render API".
 *
 * How it works: the player keeps drawing on its own render thread, in an OpenGL ES 3 context of
 * its own that shares its objects with the host's context (EGL share group). Each frame it shows
 * goes into one of three textures; the frame-ready callback then tells the host, whose call of
 * dt_render_context_render() copies the newest one into the host's framebuffer object
 * (glBlitFramebuffer, scaled when the sizes differ). The haptic task is not touched.
 *
 * Conventions (as client.h):
 * - Every function that returns int returns >= 0 (DT_ERROR_SUCCESS) on success and a negative
 *   dt_error code otherwise; a NULL or malformed argument is DT_ERROR_INVALID_PARAMETER. No C++
 *   exception leaves the library.
 * - Units: pixels for sizes. The picture's own size is the display's: the option "display-options"
 *   ("width=1280,height=720,refresh=60", the headless display's keys) or the stereo layout's size
 *   for the video ("size"), as `play` opens its display; the frames are paced at "refresh" Hz
 *   (default 60) on the render thread.
 * - Threads: dt_render_context_create(), dt_render_context_render() and dt_render_context_free()
 *   are called on the host's thread that has its EGL context current (the same context each time),
 *   and not concurrently with each other. dt_render_context_set_update_callback() may be called
 *   from any thread. The callback is called on the library's render thread.
 * - This header is C99 and C++ compatible and declares nothing but dt_* names.
 */
#ifndef DEPTHTOUCH_RENDER_GL_H
#define DEPTHTOUCH_RENDER_GL_H

#include "client.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The render context: opaque. Made by dt_render_context_create(), ended by
 * dt_render_context_free(). */
typedef struct dt_render_context dt_render_context;

/* The kinds of dt_render_param (mpv_render_param_type's first values). */
typedef enum dt_render_param_type {
    DT_RENDER_PARAM_INVALID = 0, /* ends the list */
    /* const char *: the API the host renders with. Required; DT_RENDER_API_TYPE_OPENGL only. */
    DT_RENDER_PARAM_API_TYPE = 1
} dt_render_param_type;

/* The value of DT_RENDER_PARAM_API_TYPE: OpenGL ES 3 on EGL (as MPV_RENDER_API_TYPE_OPENGL). */
#define DT_RENDER_API_TYPE_OPENGL "opengl"

/* One parameter: its type and a pointer to its value. A list ends with DT_RENDER_PARAM_INVALID. */
typedef struct dt_render_param {
    dt_render_param_type type;
    void *data;
} dt_render_param;

/* Flags of dt_render_context_render(). */
typedef enum dt_render_flag {
    /* Draw the picture upside down (as MPV_RENDER_PARAM_FLIP_Y): for a host whose framebuffer's
     * first row is its top one. Without it row 0 of the FBO is the picture's bottom row, as GL's
     * convention (and as the default framebuffer of an EGL window shows it). */
    DT_RENDER_FLAG_FLIP_Y = 1
} dt_render_flag;

/* \brief Makes the render context of \a h on the EGL context current on the calling thread (an
 * OpenGL ES 3 context the host made): from dt_initialize() on, the player opens no display of its
 * own (the option "display" is not used) and draws each frame for dt_render_context_render().
 * \pre Called before dt_initialize(\a h) (unlike libmpv, where it comes after), on the thread that
 * will render, with the host's context current. One render context per handle.
 * \param[out] out the context, set on success (NULL otherwise).
 * \param[in] params a list ending with DT_RENDER_PARAM_INVALID; DT_RENDER_PARAM_API_TYPE
 * DT_RENDER_API_TYPE_OPENGL is required, unknown types are refused.
 * \return DT_ERROR_SUCCESS; DT_ERROR_INVALID_PARAMETER (a NULL argument, \a h already initialized
 * or already with a render context, an unknown parameter), DT_ERROR_NOT_IMPLEMENTED (another API
 * type), DT_ERROR_UNSUPPORTED (no EGL context current on this thread, or a library built without
 * EGL), DT_ERROR_NOMEM. */
DT_EXPORT int dt_render_context_create(dt_render_context **out, dt_handle *h,
                                       const dt_render_param *params);

/* \brief Sets the frame-ready callback (mpv_render_context_set_update_callback()): \a callback
 * (\a userdata) is called on the library's render thread each time a new frame is ready, and
 * should make the host call dt_render_context_render() soon (post to the host's loop). It must
 * return quickly and call no dt_* function. NULL removes it; once this returns, the previous
 * callback is no longer running nor called. */
DT_EXPORT void dt_render_context_set_update_callback(dt_render_context *ctx,
                                                     void (*callback)(void *userdata),
                                                     void *userdata);

/* \brief Draws the newest frame into the host's framebuffer object \a fbo (0: the default
 * framebuffer of the current surface), \a width x \a height pixels from its origin, as
 * mpv_render_context_render() with MPV_RENDER_PARAM_OPENGL_FBO. Black when no frame was drawn
 * yet (before the first file, or after the player stopped). Changes the GL_READ_FRAMEBUFFER and
 * GL_DRAW_FRAMEBUFFER bindings (both \a fbo afterwards); other GL state is left as it was. Does not
 * wait for the player: the GL commands are queued (a fence tells the render thread when the copy is
 * done).
 * \param[in] flags 0 or DT_RENDER_FLAG_FLIP_Y.
 * \return DT_ERROR_SUCCESS; DT_ERROR_INVALID_PARAMETER (NULL \a ctx, a size < 1, unknown flags),
 * DT_ERROR_UNSUPPORTED (\a fbo is not complete), DT_ERROR_GENERIC (a GL error). */
DT_EXPORT int dt_render_context_render(dt_render_context *ctx, unsigned fbo, int width, int height,
                                       int flags);

/* \brief Ends the render context: no callback after it, and the GL objects it made in the host's
 * context are deleted (call it with that context current). The player, if running, goes on drawing
 * for nobody; dt_terminate_destroy() of the handle may come before or after. NULL does nothing. */
DT_EXPORT void dt_render_context_free(dt_render_context *ctx);

#ifdef __cplusplus
}
#endif

#endif /* DEPTHTOUCH_RENDER_GL_H */
