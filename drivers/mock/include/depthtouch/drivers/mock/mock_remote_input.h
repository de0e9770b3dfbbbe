#pragma once
/// \file
/// \brief MockRemoteInput: scripted remote-control key events delivered at their times on the
/// injected clock (backend `mock`), and NullRemoteInput: no remote at all (backend `none`).
///
/// Script text (option `keys`, or parseKeyScript()): items "NAME@SECONDS" separated by spaces or
/// '+', e.g. "KEY_PLAYPAUSE@1+RIGHT@2.5". Each item is a press at SECONDS after the backend was
/// created and a release kMockKeyHold later. Names are those of hal::keyFromName(). Thread-safety:
/// thread-bound, as hal::RemoteInput; the scripting and fault-injection calls too.

#include <cstddef>
#include <deque>
#include <memory>
#include <string_view>
#include <vector>

#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/remote_input.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {

/// Time between the press and the release of a scripted key.
inline constexpr platform::Duration kMockKeyHold = std::chrono::milliseconds(100);

/// \brief Parses a key script (see the file comment) into events whose times are offsets from
/// TimePoint{} (add the start time). \return the events in time order; InvalidArgument for an
/// unknown key name or a malformed or negative time.
Result<std::vector<hal::KeyEvent>> parseKeyScript(std::string_view script);

class MockRemoteInput final : public hal::RemoteInput {
public:
    /// Backend factory: option `keys` holds a script relative to the creation time on cfg.clock.
    static Result<std::unique_ptr<hal::RemoteInput>> create(const hal::BackendConfig &cfg);

    explicit MockRemoteInput(platform::Clock &clock);
    ~MockRemoteInput() override = default;

    [[nodiscard]] Result<hal::KeyEvent> poll(hal::Deadline until) override;

    /// \name Scripting
    ///@{
    /// Adds \a event; events come out in time order (equal times in the order added).
    void push(const hal::KeyEvent &event);
    /// Adds a press of \a key at \a at and its release \a hold later.
    void pushKey(hal::Key key, platform::TimePoint at, platform::Duration hold = kMockKeyHold);
    ///@}

    /// \name Fault injection
    ///@{
    /// Unplugs the remote: poll() returns NoDevice until replug(); scripted events stay queued.
    void unplug() noexcept { present_ = false; }
    void replug() noexcept { present_ = true; }
    ///@}

    /// \return events not yet delivered.
    [[nodiscard]] std::size_t pending() const noexcept { return events_.size(); }

private:
    platform::Clock &clock_;
    std::deque<hal::KeyEvent> events_; ///< Sorted by time.
    bool present_ = true;
};

/// \brief No remote control: poll() waits until the deadline and returns Timeout.
class NullRemoteInput final : public hal::RemoteInput {
public:
    /// Backend factory; ignores the options (so "mock,none" can share them as a fallback).
    static Result<std::unique_ptr<hal::RemoteInput>> create(const hal::BackendConfig &cfg);

    explicit NullRemoteInput(platform::Clock &clock) : clock_(clock) {}
    ~NullRemoteInput() override = default;

    [[nodiscard]] Result<hal::KeyEvent> poll(hal::Deadline until) override;

private:
    platform::Clock &clock_;
};

} // namespace depthtouch::drivers
