#pragma once
/// \file
/// \brief What the EGL display backends (headless, x11, kms) keep alike: capabilities, state, and
/// the size and refresh rate of the opened surface (read as 0 when Closed, per hal::Display).
/// Thread-safety: as hal::Display (thread-bound).

#include "depthtouch/hal/display.h"

namespace depthtouch::drivers {

class EglDisplayBase : public hal::Display {
public:
    [[nodiscard]] const hal::DisplayCapabilities &capabilities() const noexcept override
    {
        return caps_;
    }
    [[nodiscard]] State state() const noexcept override { return state_; }
    [[nodiscard]] hal::Size size() const noexcept override
    {
        return state_ == State::Closed ? hal::Size{} : size_;
    }
    [[nodiscard]] double refreshHz() const noexcept override
    {
        return state_ == State::Closed ? 0.0 : refreshHz_;
    }

protected:
    EglDisplayBase() = default;

    hal::DisplayCapabilities caps_; ///< Set by the backend's constructor.
    State state_ = State::Closed;
    hal::Size size_;                ///< Pixels, of the opened surface.
    double refreshHz_ = 0.0;        ///< Hertz, of the opened mode.
};

} // namespace depthtouch::drivers
