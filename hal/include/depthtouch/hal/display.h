#pragma once
/// \file
/// \brief Display: an output surface with a rendering context, presented in step with the display's
/// vertical refresh. Real backends hold an EGL display, an OpenGL ES 3 context and a window or GBM
/// surface; the HAL itself includes no EGL or GL header.
///
/// State machine:
/// \verbatim
///   Closed --open()--> Open --(display unplugged, GPU reset)--> Lost
///     ^                 |                                        |
///     +----close()------+-------------------close()--------------+
/// \endverbatim
/// A call that is not allowed in the current state returns Errc::InvalidState and has no effect. In
/// Lost, makeCurrent() and present() return Errc::NoDevice; the caller closes and opens again
/// (open() fails with NoDevice while no display is connected). Backends derive from DisplayBase
/// (display_base.h), which does the state checks of this contract and leaves them the device work.
///
/// Time: PresentInfo::vsyncTime is on the backend clock (BackendConfig::clock).
/// Thread-safety: thread-bound: call every method from the render thread, the one that calls
/// makeCurrent() (a GL context is current on one thread only). Not real-time safe.

#include <cstdint>
#include <string>

#include "depthtouch/hal/types.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::hal {

/// \brief What open() should set up. Zero fields ask for the backend's default (the connected
/// display's preferred mode, or 1280×720 at 60 Hz for windows and offscreen surfaces).
struct DisplayConfig {
    int width = 0;          ///< Pixels.
    int height = 0;         ///< Pixels.
    double refreshHz = 0.0; ///< Vertical refresh rate in hertz.
    std::string mode; ///< Backend-specific mode or connector, e.g. "HDMI-A-1" or "1920x1080@60";
                      ///< empty = default.
};

/// \brief What a display backend can do. Constant for the display's lifetime.
struct DisplayCapabilities {
    bool hasGlesContext = false; ///< An OpenGL ES 3 context is current after makeCurrent().
    bool offscreen = false;      ///< Nothing is shown on a screen (surfaceless, or simulated).
    bool readback = false;       ///< readPixels() returns the presented frame.
};

/// Pixel size of a surface.
struct Size {
    int width = 0;
    int height = 0;
};

/// \brief When a presented frame reached the screen.
struct PresentInfo {
    platform::TimePoint vsyncTime{}; ///< The vertical blank at which the frame became visible.
    std::uint64_t frameCounter =
        0; ///< Frames presented since open(), this one included (1, 2, ...).
    std::uint32_t skippedVsyncs =
        0; ///< Refresh periods since the previous frame without a new frame.
};

/// \brief A display output with a GL ES context.
class Display {
public:
    enum class State : std::uint8_t { Closed, Open, Lost };

    virtual ~Display() = default;

    /// \return what the backend can do; constant for its whole lifetime.
    [[nodiscard]] virtual const DisplayCapabilities &capabilities() const noexcept = 0;

    /// \return the current state.
    [[nodiscard]] virtual State state() const noexcept = 0;

    /// \brief Opens the output and creates the context and surface.
    /// \pre Closed.
    /// \param[in] cfg Requested size, refresh and mode.
    /// \return nothing on success (state Open). Errors: InvalidState (not Closed), NoDevice (no
    /// display connected), NotSupported (the mode cannot be set), InvalidArgument (malformed cfg).
    [[nodiscard]] virtual Result<void> open(const DisplayConfig &cfg) = 0;

    /// \brief Destroys the surface and context. Always allowed; no-op when Closed.
    virtual void close() noexcept = 0;

    /// \return the surface size in pixels; {0, 0} when Closed.
    [[nodiscard]] virtual Size size() const noexcept = 0;

    /// \return the refresh rate of the opened mode in hertz; 0 when Closed.
    [[nodiscard]] virtual double refreshHz() const noexcept = 0;

    /// \brief Makes the context current on the calling thread (the render thread).
    /// \pre Open.
    /// \return nothing on success. Errors: InvalidState (Closed), NoDevice (Lost).
    [[nodiscard]] virtual Result<void> makeCurrent() = 0;

    /// \brief Shows the frame drawn since the last present() at the next vertical blank; blocks
    /// until then on the backend clock (at most one refresh period, plus the time the caller is
    /// late). \pre Open. \return when it became visible. Errors: InvalidState (Closed), NoDevice
    /// (the display was lost: state Lost).
    [[nodiscard]] virtual Result<PresentInfo> present() = 0;

    /// \brief The GL framebuffer object the renderer draws the next frame into.
    ///
    /// makeCurrent() and present() bind it as GL_FRAMEBUFFER; a renderer that binds its own
    /// framebuffers binds this one again before drawing the frame to show. It may change at every
    /// present() (an offscreen backend swaps its buffers).
    /// \return the framebuffer name; 0 (the default) means the EGL surface's own framebuffer, and
    /// also a display without a GL context, or a Closed one.
    [[nodiscard]] virtual std::uint32_t framebuffer() const noexcept { return 0; }

    /// \brief Copies the most recently presented frame into \a out (snapshots, tests).
    ///
    /// Rows are written top row first (as shown on the screen), converted to out.format.
    /// Blocks until the GPU has finished that frame. Needs the context current on the calling
    /// thread (makeCurrent() is called when it is not).
    /// \pre Open, a frame presented since open().
    /// \param[in] out Rgba8 or Rgb24, exactly size() pixels, plane 0 with strideBytes ≥ one row.
    /// \return nothing on success. Errors: NotSupported (capabilities().readback is false: the
    /// default implementation), InvalidState (Closed, or nothing presented yet), InvalidArgument
    /// (\a out has another size or format, or no memory), NoDevice (Lost).
    [[nodiscard]] virtual Result<void> readPixels(const ImageView &out)
    {
        (void)out;
        return unexpected(Errc::NotSupported, "This display cannot read back its frames");
    }

protected:
    Display() = default;
    DT_DISABLE_COPY_AND_MOVE(Display)
};

/// \return the name of \a s: "Closed", "Open" or "Lost" (a static string; "?" for another value),
/// for messages. Thread-safe.
[[nodiscard]] const char *toString(Display::State s) noexcept;

} // namespace depthtouch::hal
