#pragma once
/// \file
/// \brief The render API's two sides (depthtouch/render_gl.h): HostFrames, the frames the
/// player's render thread hands to the host's thread, and the display the player draws them on
/// (makeHostDisplay()), a hal::Display whose frame buffer is a texture shared with the host's
/// EGL context.
///
/// The player's display (host_display.cpp) opens, on the render thread, an OpenGL ES 3 context in
/// the share group of the host's context and three framebuffer objects, each with a colour texture
/// (shared objects) and its own depth buffer. The presenter blits its render target into the one
/// being drawn, as into any display's frame buffer; present() waits for the GPU (glFinish, as the
/// headless display does), hands it over (HostFrames::publish()), calls the frame-ready callback
/// and paces the frames on a simulated vertical blank (drivers::VsyncPacer). The host's
/// dt_render_context_render() blits the newest texture into its own framebuffer object and leaves
/// a fence, which the render thread waits for (glWaitSync) before it draws into that texture
/// again. The texture being read and the newest one are never drawn into (three buffers).
///
/// Reference: libmpv's render API (mpv's render.h, render_gl.h) for the shape; the EGL 1.5 and
/// OpenGL ES 3.0 specifications (§5 "Shared Objects and Multiple Contexts") for the sharing.
/// Thread-safety: HostFrames is shared by the host's thread (create, render, releaseHost) and the
/// render thread (the display's calls): its state is under a mutex; setCallback() from any thread.

#include <array>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "depthtouch/hal/display.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::client {

/// See the file comment.
class HostFrames {
public:
    /// The number of textures the frames rotate through.
    static constexpr int kBuffers = 3;
    using Callback = void (*)(void *userdata);

    /// \brief On the host's thread: records the EGL display and context current on it.
    /// \return DT_ERROR_SUCCESS with the frames in \a out; DT_ERROR_UNSUPPORTED (no EGL context
    /// current, or a build without EGL), DT_ERROR_NOMEM.
    static int create(std::shared_ptr<HostFrames> &out);

    HostFrames() = default;
    ~HostFrames();
    HostFrames(const HostFrames &) = delete;
    HostFrames &operator=(const HostFrames &) = delete;

    /// The host's EGLDisplay and EGLContext (as void *: no EGL header here).
    [[nodiscard]] void *eglDisplay() const noexcept { return eglDisplay_; }
    [[nodiscard]] void *eglContext() const noexcept { return eglContext_; }

    // The host's thread, its context current.

    /// \brief dt_render_context_render(): the newest frame into \a fbo (\a width x \a height).
    /// \return a dt_error code (see render_gl.h).
    int render(std::uint32_t fbo, int width, int height, bool flipY);
    /// \brief The host's side ends: its GL objects are deleted and no callback comes any more.
    void releaseHost() noexcept;

    /// dt_render_context_set_update_callback(); waits for a callback that is running.
    void setCallback(Callback cb, void *userdata);

    // The render thread (the player's display), the library's context current.

    /// \brief The display opened: frames are \a width x \a height, in \a textures.
    void attach(const std::array<std::uint32_t, kBuffers> &textures, int width, int height);
    /// \brief Buffer \a drawn holds a finished frame: it becomes the newest, the callback is
    /// called. \return the buffer to draw next (neither the newest nor the one being read), and
    /// in \a readFence the fence of the host's last read of it to wait for (a GLsync; null: none).
    int publish(int drawn, void *&readFence);
    /// \brief The display closes: waits for a read in progress, forgets the textures.
    /// \return the fences still held (GLsync; null: none), for the caller to delete.
    std::array<void *, kBuffers> detach();

private:
    void *eglDisplay_ = nullptr;
    void *eglContext_ = nullptr;
    std::mutex mutex_;
    std::condition_variable readDone_;
    std::array<std::uint32_t, kBuffers> textures_{};
    std::array<void *, kBuffers> readFences_{}; ///< The host's last read of each (GLsync).
    int width_ = 0;
    int height_ = 0;
    bool attached_ = false;
    int newest_ = -1;           ///< Buffer of the newest frame; -1: none.
    int reading_ = -1;          ///< Buffer the host is reading; -1: none.
    std::uint32_t readFbo_ = 0; ///< The host context's framebuffer over the texture read.
    std::mutex callbackMutex_;  ///< Held while the callback runs and while it is changed.
    Callback callback_ = nullptr;
    void *userdata_ = nullptr;
};

/// \brief The player's display on \a frames: options of \a displayOptions ("width", "height",
/// "refresh": the headless display's), time from \a clock (which outlives it).
/// \return the display, closed. Errors: InvalidArgument (an option), NotSupported (no EGL).
Result<std::unique_ptr<hal::Display>> makeHostDisplay(std::shared_ptr<HostFrames> frames,
                                                      platform::Clock &clock,
                                                      const std::string &displayOptions);

} // namespace depthtouch::client
