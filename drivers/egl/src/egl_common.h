#pragma once
// Private helpers of the EGL display backends: EGL display references shared within the process,
// OpenGL ES 3 context creation, error names, and reading a framebuffer back into an ImageView.
// Thread-safety: acquireEglDisplay()/releaseEglDisplay() are thread-safe; the GL helpers act on
// the context current on the calling thread.

#include <cstdint>
#include <vector>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>

#include "depthtouch/hal/display.h"
#include "depthtouch/hal/types.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers::egl {

/// \return the name of an EGL error code, e.g. "EGL_BAD_ALLOC" (static string).
const char *eglErrorName(EGLint error) noexcept;

/// \brief Gets and initialises the EGL display of \a platform (an EGL_PLATFORM_* value) on
/// \a nativeDisplay, counting references: EGL hands out one EGLDisplay per platform and native
/// display, and eglTerminate() would destroy every context on it, so the last release terminates.
/// \return the display. Errors: NoDevice (the platform or its initialisation is unavailable).
Result<EGLDisplay> acquireEglDisplay(EGLenum platform, void *nativeDisplay);
/// Drops a reference taken by acquireEglDisplay(); the last one calls eglTerminate().
void releaseEglDisplay(EGLDisplay display) noexcept;

/// \brief Chooses an RGBA8888 + depth 24 + stencil 8 config for OpenGL ES 3 rendering to
/// \a surfaceType (EGL_WINDOW_BIT; 0 for none), whose native visual is \a visualId when non-zero
/// (X11) or whose EGL_NATIVE_VISUAL_ID is \a visualId (GBM format).
/// \return the config. Errors: NotSupported.
Result<EGLConfig> chooseConfig(EGLDisplay display, EGLint surfaceType, EGLint visualId);

/// \brief Creates an OpenGL ES 3 context (binds the ES API first). \a config may be
/// EGL_NO_CONFIG_KHR on displays with EGL_KHR_no_config_context. Errors: NotSupported.
Result<EGLContext> createGles3Context(EGLDisplay display, EGLConfig config);

/// \brief Creates a window surface with eglCreatePlatformWindowSurfaceEXT on \a platformWindow
/// when EGL has it, else with eglCreateWindowSurface on \a nativeWindow: the same window as the
/// EGLNativeWindowType value, passed as void * since that type depends on the platform headers a
/// file includes. \return the surface, EGL_NO_SURFACE on failure (eglGetError()).
EGLSurface createWindowSurface(EGLDisplay display, EGLConfig config, void *platformWindow,
                               void *nativeWindow);

/// \brief Makes \a context current on the calling thread, drawing to and reading from \a surface
/// (EGL_NO_SURFACE for a surfaceless context), unless it already is current.
/// \return EGL_SUCCESS, or the eglGetError() code of the eglMakeCurrent() that failed.
EGLint makeCurrentUnlessCurrent(EGLDisplay display, EGLSurface surface,
                                EGLContext context) noexcept;

/// \brief Makes a window display's \a context current on the calling thread, drawing to and
/// reading from \a surface (makeCurrentUnlessCurrent()). On failure logs "Failed to make the
/// <what> context current: <EGL error>" at Error level under \a category.
/// \return nothing once current. Errors: NoDevice with \a lostWhat when the error means the
/// context or surface is gone (isSurfaceGone(): the caller then marks the display lost), Io
/// otherwise. \a what and \a lostWhat are static strings.
Result<void> makeWindowCurrent(EGLDisplay display, EGLSurface surface, EGLContext context,
                               const platform::LogCategory &category, const char *what,
                               const char *lostWhat) noexcept;

/// \return true for the eglMakeCurrent()/eglSwapBuffers() errors that mean the context or the
/// window surface is gone for good (the display is lost): EGL_CONTEXT_LOST, EGL_BAD_NATIVE_WINDOW,
/// EGL_BAD_SURFACE.
bool isSurfaceGone(EGLint error) noexcept;

/// \brief Binds framebuffer \a fbo (0: the surface's) for drawing and reading, with a viewport of
/// \a size. \pre a context is current on the calling thread.
void bindDrawTarget(GLuint fbo, hal::Size size) noexcept;

/// \brief Checks that \a out is an Rgba8 or Rgb24 image of exactly \a size with room for a row.
Result<void> checkReadTarget(const hal::ImageView &out, hal::Size size) noexcept;

/// \brief Reads the \a size pixels of framebuffer \a fbo (0: the surface's) into \a out, top row
/// first, converting to out.format. \a staging is resized to hold one RGBA copy. Restores the
/// read-framebuffer binding. \pre checkReadTarget(out, size) passed; a context is current.
/// \return nothing; Errors: Io (GL error).
Result<void> readFramebuffer(GLuint fbo, hal::Size size, const hal::ImageView &out,
                             std::vector<std::uint8_t> &staging);

/// \brief A copy of a window surface's last presented frame, for readPixels() on displays whose
/// buffers are undefined after a swap (x11, kms with readback=1). Every call needs the display's
/// context current on the calling thread.
class FrameCopy {
public:
    /// \brief Creates the RGBA8 copy of \a size pixels. \return Errors: OutOfResources (incomplete
    /// framebuffer; logged); the copy is then deleted again.
    Result<void> create(hal::Size size);
    [[nodiscard]] bool created() const noexcept { return fbo_ != 0; }
    /// \brief Copies the surface's framebuffer (0), before a swap; no-op when not created.
    void keep(hal::Size size) noexcept;
    /// \brief Records that the kept frame reached the screen (read() may then return it).
    void markPresented() noexcept { presented_ = true; }
    /// \brief Reads the kept frame into \a out (checkReadTarget(), readFramebuffer()).
    /// \return Errors: InvalidState (nothing presented since create() or forget()), and theirs.
    Result<void> read(const hal::ImageView &out, hal::Size size);
    /// \brief Deletes the GL objects (context current) and forgets the frame.
    void destroy() noexcept;
    /// \brief Forgets the GL objects without deleting them (their context is gone) and the frame.
    void forget() noexcept;

private:
    GLuint fbo_ = 0;
    GLuint color_ = 0;
    bool presented_ = false;
    std::vector<std::uint8_t> staging_;
};

/// \brief Undoes the EGL part of a window display (x11, kms): deletes \a copy with \a context
/// current on \a surface, unbinds and destroys the context, destroys the surface and drops the
/// reference on \a display. Each handle may be EGL_NO_*; nothing happens without a display.
/// The caller then forgets the handles.
void destroyWindowContext(EGLDisplay display, EGLSurface surface, EGLContext context,
                          FrameCopy &copy) noexcept;

} // namespace depthtouch::drivers::egl
