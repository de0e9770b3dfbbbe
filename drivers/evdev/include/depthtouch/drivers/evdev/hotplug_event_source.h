#pragma once
/// \file
/// \brief HotplugEventSource: an evdev EventSource for a remote that may be plugged in after the
/// start and unplugged and plugged in again (hal::BackendConfig::awaitDevice; a set-top box whose
/// USB or IR receiver enumerates after the player's service started).
///
/// While no device is there, next() waits until its deadline and returns Timeout, looking for the
/// device again (its opener: the configured path, or the first device with media keys) at most
/// once per retry interval; a device that goes away (NoDevice) is closed and looked for again.
/// So a remote is a device that is there or not, never a reason to fail or to stop reading keys.
///
/// Time: the clock given to next() (a ManualClock in tests). Thread-safety: thread-bound, as
/// EventSource; connected() and arrivals() are read by the same thread.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

#include "depthtouch/drivers/evdev/evdev_remote_input.h"

namespace depthtouch::drivers {

class HotplugEventSource final : public EventSource {
public:
    /// Opens the device: the source, or an error (NoDevice: not there; anything else, such as a
    /// node that udev has not yet given its permissions, is retried too). The first miss after
    /// a start or a loss is logged once, as a warning.
    using Opener = std::function<Result<std::unique_ptr<EventSource>>()>;

    /// \param[in] open Called from next() on the caller's thread. \param[in] retry How often a
    /// missing device is looked for (at least 1 ms).
    HotplugEventSource(Opener open, platform::Duration retry);

    /// \return the next event of the device, waiting until \a until. Errors: Timeout (nothing by
    /// the deadline, or no device), Io (a read error of a present device). Never NoDevice.
    [[nodiscard]] Result<input_event> next(platform::Clock &clock, hal::Deadline until) override;

    /// Looks for the device now (the first look at a start, so that connected() tells whether it
    /// was there), unless a look is not yet due at \a now. \return connected().
    bool look(platform::TimePoint now) { return device_ != nullptr || tryOpen(now); }

    /// \return true while a device is open.
    [[nodiscard]] bool connected() const noexcept override { return device_ != nullptr; }
    /// \return how many times a device was found (the first time included).
    [[nodiscard]] std::uint64_t arrivals() const noexcept { return arrivals_; }

private:
    /// Tries the opener when a try is due. \return true when a device is open.
    bool tryOpen(platform::TimePoint now);

    Opener open_;
    platform::Duration retry_;
    std::unique_ptr<EventSource> device_;
    std::optional<platform::TimePoint> nextTry_;
    std::uint64_t arrivals_ = 0;
    bool failureLogged_ = false;
};

} // namespace depthtouch::drivers
