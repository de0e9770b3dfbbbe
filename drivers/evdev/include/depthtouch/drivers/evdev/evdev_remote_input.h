#pragma once
/// \file
/// \brief EvdevRemoteInput: remote-control keys from a Linux input device (/dev/input/eventN),
/// backend `evdev`. IR receivers (rc-core), HDMI-CEC bridges and USB remotes that present input
/// devices work through it.
///
/// Keys: EV_KEY codes listed in hal::Key map one to one; a few common aliases map too (KEY_MODE →
/// KEY_3D_MODE, KEY_PLAYCD / KEY_PAUSECD / KEY_STOPCD → play / pause / stop, KEY_SELECT → KEY_OK,
/// KEY_SPACE → KEY_PLAYPAUSE, KEY_ESC → KEY_EXIT, KEY_PAGEUP / KEY_PAGEDOWN → KEY_CHANNELUP /
/// KEY_CHANNELDOWN). Other codes and event types are skipped. Auto-repeat (EV_KEY value 2) is
/// passed for the continuous keys (arrows, fast-forward, rewind, volume, channel) and dropped for
/// the others, so a held toggle does not toggle again (option repeat).
///
/// Options: `device=/dev/input/eventN` (or BackendConfig::device; default: the first device with
/// EV_KEY and a media key), `grab=1` (EVIOCGRAB: other readers, e.g. the console, stop seeing the
/// keys), `repeat=nav|all|none` (default nav).
///
/// Reading goes through an EventSource: the real one uses libevdev (which resynchronises after
/// SYN_DROPPED), tests use a fake that yields input_event records.
/// Errors: the factory returns NoDevice when no device is found, InvalidArgument when the path is
/// not an input device (a bad option), PermissionDenied when it cannot be opened; poll() returns
/// NoDevice once the device is unplugged (ENODEV) and from then on. With
/// hal::BackendConfig::awaitDevice the device is optional instead: the factory succeeds without
/// one, and the device (the path given, or the first with media keys) is looked for every second
/// while it is missing, at the start and after an unplug (HotplugEventSource); poll() then
/// returns Timeout while there is none, never NoDevice. Time: KeyEvent::time is the
/// backend clock's time when the event was read. Thread-safety: thread-bound, as hal::RemoteInput.

#include <memory>
#include <string>
#include <string_view>

#include <linux/input.h>

#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/remote_input.h"
#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers {

/// \brief Where EvdevRemoteInput reads raw input events from.
class EventSource {
public:
    virtual ~EventSource() = default;

    /// \brief Returns the next event, waiting until \a until on \a clock.
    /// \return the event. Errors: Timeout (nothing by the deadline; a past deadline does not
    /// wait), NoDevice (the device went away), Io.
    [[nodiscard]] virtual Result<input_event> next(platform::Clock &clock, hal::Deadline until) = 0;

    /// \return false while a source that waits for its device has none (HotplugEventSource).
    [[nodiscard]] virtual bool connected() const noexcept { return true; }

protected:
    EventSource() = default;
    DT_DISABLE_COPY_AND_MOVE(EventSource)
};

/// Which auto-repeat events are passed on.
enum class RepeatPolicy {
    None,       ///< No repeats.
    Navigation, ///< Repeats of continuous keys only (isContinuousKey()).
    All,        ///< Every repeat.
};

/// \return true for keys whose auto-repeat makes sense: arrows, fast-forward, rewind, volume.
bool isContinuousKey(hal::Key key) noexcept;

/// \return the hal::Key of evdev code \a code, aliases included; Key::Unknown when unmapped.
hal::Key keyFromEvdevCode(int code) noexcept;

class EvdevRemoteInput final : public hal::RemoteInput {
public:
    /// Backend factory (see the file comment for the options).
    static Result<std::unique_ptr<hal::RemoteInput>> create(const hal::BackendConfig &cfg);
    /// Creates the backend on \a source, with the options of \a cfg other than device and grab.
    static Result<std::unique_ptr<EvdevRemoteInput>>
    createWithSource(const hal::BackendConfig &cfg, std::unique_ptr<EventSource> source);

    EvdevRemoteInput(std::unique_ptr<EventSource> source, platform::Clock &clock,
                     RepeatPolicy repeat) noexcept;
    ~EvdevRemoteInput() override = default;

    [[nodiscard]] Result<hal::KeyEvent> poll(hal::Deadline until) override;
    /// \return true while its source waits for a device (hal::BackendConfig::awaitDevice).
    [[nodiscard]] bool awaitingDevice() const noexcept override { return !source_->connected(); }

    /// The source read from (for tests that feed a fake).
    [[nodiscard]] EventSource &source() noexcept { return *source_; }

private:
    std::unique_ptr<EventSource> source_;
    platform::Clock &clock_;
    RepeatPolicy repeat_;
    bool gone_ = false;
};

/// \brief Opens \a path with libevdev. \param[in] grab Take the device exclusively (EVIOCGRAB).
/// \return the source. Errors: NoDevice (missing), InvalidArgument (not an input device),
/// PermissionDenied, Io.
Result<std::unique_ptr<EventSource>> openLibevdevSource(const std::string &path, bool grab);

/// \brief Finds the first event device in \a dir (event0, event1, ... in number order) that has
/// EV_KEY and at least one media key (play/pause, play, pause, stop, fast-forward, rewind).
/// \return its path. Errors: NoDevice (none found or readable).
Result<std::string> findRemoteDevice(const std::string &dir = "/dev/input");

} // namespace depthtouch::drivers
