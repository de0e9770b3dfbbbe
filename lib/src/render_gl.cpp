/// \file
/// \brief The render API of depthtouch/render_gl.h: checks the arguments, catches every exception
/// and hands the work to HostFrames (host_frames.h), which the handle's player draws for.
/// Reference: libmpv's render.h and render_gl.h (mpv 0.38) for the shape.

#include "depthtouch/render_gl.h"

#include <cstring>
#include <memory>
#include <mutex>
#include <new>

#include "handle.h"
#include "host_frames.h"

/// A render context: the frames it reads (the handle holds them too, for its player).
struct dt_render_context {
    std::shared_ptr<depthtouch::client::HostFrames> frames;
};

namespace {

/// \return the code of \a params: DT_ERROR_SUCCESS when they ask for OpenGL.
int checkParams(const dt_render_param *params)
{
    if (params == nullptr)
        return DT_ERROR_INVALID_PARAMETER;
    bool opengl = false;
    for (const dt_render_param *p = params; p->type != DT_RENDER_PARAM_INVALID; ++p) {
        if (p->type != DT_RENDER_PARAM_API_TYPE || p->data == nullptr)
            return DT_ERROR_INVALID_PARAMETER;
        if (std::strcmp(static_cast<const char *>(p->data), DT_RENDER_API_TYPE_OPENGL) != 0)
            return DT_ERROR_NOT_IMPLEMENTED;
        opengl = true;
    }
    return opengl ? DT_ERROR_SUCCESS : DT_ERROR_INVALID_PARAMETER;
}

} // namespace

int dt_render_context_create(dt_render_context **out, dt_handle *h, const dt_render_param *params)
{
    if (out == nullptr)
        return DT_ERROR_INVALID_PARAMETER;
    *out = nullptr;
    if (h == nullptr)
        return DT_ERROR_INVALID_PARAMETER;
    try {
        if (const int rc = checkParams(params); rc < 0)
            return rc;
        const std::lock_guard<std::mutex> lock(h->mutex);
        if (h->player || h->render)
            return DT_ERROR_INVALID_PARAMETER;
        auto ctx = std::make_unique<dt_render_context>();
        if (const int rc = depthtouch::client::HostFrames::create(ctx->frames); rc < 0)
            return rc;
        h->render = ctx->frames;
        *out = ctx.release();
        return DT_ERROR_SUCCESS;
    } catch (const std::bad_alloc &) {
        return DT_ERROR_NOMEM;
    } catch (...) {
        return DT_ERROR_GENERIC;
    }
}

void dt_render_context_set_update_callback(dt_render_context *ctx, void (*callback)(void *),
                                           void *userdata)
{
    if (ctx == nullptr)
        return;
    try {
        ctx->frames->setCallback(callback, userdata);
    } catch (...) {
        // A mutex that cannot be locked: nothing is changed.
    }
}

int dt_render_context_render(dt_render_context *ctx, unsigned fbo, int width, int height, int flags)
{
    if (ctx == nullptr || width < 1 || height < 1 || (flags & ~DT_RENDER_FLAG_FLIP_Y) != 0)
        return DT_ERROR_INVALID_PARAMETER;
    try {
        return ctx->frames->render(fbo, width, height, (flags & DT_RENDER_FLAG_FLIP_Y) != 0);
    } catch (const std::bad_alloc &) {
        return DT_ERROR_NOMEM;
    } catch (...) {
        return DT_ERROR_GENERIC;
    }
}

void dt_render_context_free(dt_render_context *ctx)
{
    if (ctx == nullptr)
        return;
    try {
        ctx->frames->releaseHost();
    } catch (...) {
        // A mutex that cannot be locked: the callback stays, the context goes.
    }
    delete ctx;
}
