#pragma once
// Private helper of the HAL bases: the close() step that their contracts share.

namespace depthtouch::hal::detail {

/// \brief Ends an open session: a no-op when \a state is already Closed; else calls \a release
/// (the backend's closeDevice() and whatever the base resets with it), then sets \a state to
/// Closed. \a State is the interface's state enumeration, \a release a noexcept callable.
template <class State, class Release> void closeSession(State &state, Release &&release) noexcept
{
    if (state == State::Closed)
        return;
    release();
    state = State::Closed;
}

} // namespace depthtouch::hal::detail
