#include "depthtouch/hal/display_base.h"

#include "depthtouch/platform/log.h"
#include "session_state.h"

DT_LOG_CATEGORY(Display)

namespace depthtouch::hal {

Result<void> DisplayBase::open(const DisplayConfig &cfg)
{
    if (state_ != State::Closed) {
        DT_LOG(Display, Error, "In state %s trying open() requiring Closed", toString(state_));
        return unexpected(Errc::InvalidState, "open() requires state Closed");
    }
    DT_TRY(openDevice(cfg));
    state_ = State::Open;
    return ok();
}

void DisplayBase::close() noexcept
{
    detail::closeSession(state_, [this]() noexcept {
        closeDevice();
        size_ = {};
        refreshHz_ = 0.0;
    });
}

void DisplayBase::markLost() noexcept
{
    if (state_ == State::Open)
        state_ = State::Lost;
}

Result<void> DisplayBase::checkOpen() const noexcept
{
    if (state_ == State::Closed)
        return unexpected(Errc::InvalidState, "Display is closed");
    if (state_ == State::Lost)
        return unexpected(Errc::NoDevice, "Display lost");
    return ok();
}

Result<void> DisplayBase::makeCurrent()
{
    DT_TRY(checkOpen());
    return makeCurrentDevice();
}

Result<PresentInfo> DisplayBase::present()
{
    DT_TRY(checkOpen());
    return presentDevice();
}

std::uint32_t DisplayBase::framebuffer() const noexcept
{
    return state_ == State::Open ? framebufferDevice() : 0u;
}

Result<void> DisplayBase::readPixels(const ImageView &out)
{
    if (!caps_.readback)
        return unexpected(Errc::NotSupported,
                          "This display keeps no copy of its frames (capabilities().readback)");
    DT_TRY(checkOpen());
    return readPixelsDevice(out);
}

Result<void> DisplayBase::readPixelsDevice(const ImageView &out)
{
    (void)out;
    return unexpected(Errc::NotSupported, "This display cannot read back its frames");
}

} // namespace depthtouch::hal
