#pragma once
/// \file
/// \brief DisplayBase: the hal::Display contract in one place, for every display backend.
///
/// A backend derives from DisplayBase and implements only the device work (the protected
/// `...Device()` hooks); the public methods are `final` and do the contract around them, in the
/// manner of libcamera's PipelineHandler::queueRequest() and queueRequestDevice():
/// - open(): Closed required (else InvalidState, logged), then openDevice(); Open on success.
/// - close(): a no-op when Closed; else closeDevice(), then Closed with size and refresh rate zero.
/// - makeCurrent(), present() and readPixels(): InvalidState when Closed, NoDevice when Lost, then
///   the hook (which may find the display lost: markLost(), and NoDevice). readPixels() first
///   returns NotSupported when capabilities().readback is false.
/// - size(), refreshHz() and framebuffer() read as zero unless Open (size and refresh: unless
///   Closed).
///
/// Thread-safety: thread-bound, as hal::Display. Not real-time safe.

#include <cstdint>

#include "depthtouch/hal/display.h"

namespace depthtouch::hal {

/// \brief The base of every display backend: owns the state, the opened size and refresh rate,
/// and the contract (see the file comment); the backend implements the hooks.
class DisplayBase : public Display {
public:
    ~DisplayBase() override = default;

    [[nodiscard]] const DisplayCapabilities &capabilities() const noexcept final { return caps_; }
    [[nodiscard]] State state() const noexcept final { return state_; }
    [[nodiscard]] Result<void> open(const DisplayConfig &cfg) final;
    void close() noexcept final;
    [[nodiscard]] Size size() const noexcept final
    {
        return state_ == State::Closed ? Size{} : size_;
    }
    [[nodiscard]] double refreshHz() const noexcept final
    {
        return state_ == State::Closed ? 0.0 : refreshHz_;
    }
    [[nodiscard]] Result<void> makeCurrent() final;
    [[nodiscard]] Result<PresentInfo> present() final;
    [[nodiscard]] std::uint32_t framebuffer() const noexcept final;
    [[nodiscard]] Result<void> readPixels(const ImageView &out) final;

protected:
    DisplayBase() = default;

    /// \brief Opens the output (called in state Closed) and sets size_ and refreshHz_.
    /// \return Errors: as open() (NoDevice, NotSupported, InvalidArgument, ...), with everything
    /// it set up undone; the state stays Closed.
    [[nodiscard]] virtual Result<void> openDevice(const DisplayConfig &cfg) = 0;
    /// \brief Destroys the surface and context (called Open or Lost). noexcept.
    virtual void closeDevice() noexcept = 0;
    /// \brief Makes the context current on the calling thread (called Open).
    [[nodiscard]] virtual Result<void> makeCurrentDevice() = 0;
    /// \brief Shows the drawn frame at the next vertical blank (called Open).
    [[nodiscard]] virtual Result<PresentInfo> presentDevice() = 0;
    /// \return the framebuffer to draw into (called Open); 0: the surface's own. Default 0.
    [[nodiscard]] virtual std::uint32_t framebufferDevice() const noexcept { return 0; }
    /// \brief Reads the last presented frame back (called Open, with caps_.readback set).
    /// Default: NotSupported.
    [[nodiscard]] virtual Result<void> readPixelsDevice(const ImageView &out);

    /// \brief An Open display went away (unplugged, window closed, context lost): enters Lost.
    /// No-op in another state.
    void markLost() noexcept;

    DisplayCapabilities caps_; ///< Set by the backend's constructor; constant afterwards.
    Size size_;                ///< Pixels, of the opened surface (set by openDevice()).
    double refreshHz_ = 0.0;   ///< Hertz, of the opened mode (set by openDevice()).

private:
    /// InvalidState when Closed, NoDevice when Lost.
    [[nodiscard]] Result<void> checkOpen() const noexcept;

    State state_ = State::Closed;
};

} // namespace depthtouch::hal
